r"""Time integrators (drying spec section 8). They see only a state array ``y`` and a rate
callable ``f(y, t) -> dy/dt``; they know nothing of the physics.

- ``rk4``: classical four-stage Runge-Kutta (4th order; real-axis stability 2.785).
- ``abm4``: Adams-Bashforth-Moulton PECE, 4th order, two evaluations per step:
  :math:`Y^* = Y_n + \tfrac{\Delta t}{24}(55F_n - 59F_{n-1} + 37F_{n-2} - 9F_{n-3})`,
  :math:`Y_{n+1} = Y_n + \tfrac{\Delta t}{24}(9F(Y^*) + 19F_n - 5F_{n-1} + F_{n-2})`
  (real-axis stability 1.285). It needs the three previous rates; the caller restarts it with
  RK4 steps at the start and whenever the history becomes invalid (particle removal, a change
  of time step).
- ``rk2``: Heun's method, the cheap second-order scheme of the accuracy study.

Every step takes ``f0 = f(y_n, t_n)`` (already known: it is the last evaluation of the previous
step) and returns ``y_{n+1}``; the caller evaluates ``f(y_{n+1})`` once, which both ends this
step (fracture test, ABM history) and starts the next.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np

Rate = Callable[[np.ndarray, float], np.ndarray]

EVALUATIONS_PER_STEP = {"rk4": 4, "abm4": 2, "rk2": 2}
REAL_AXIS_LIMIT = {"rk4": 2.785, "abm4": 1.285, "rk2": 2.0}
ORDER = {"rk4": 4, "abm4": 4, "rk2": 2}


def rk4_step(y: np.ndarray, f0: np.ndarray, t: float, dt: float, f: Rate) -> np.ndarray:
    k2 = f(y + 0.5 * dt * f0, t + 0.5 * dt)
    k3 = f(y + 0.5 * dt * k2, t + 0.5 * dt)
    k4 = f(y + dt * k3, t + dt)
    return y + (dt / 6.0) * (f0 + 2.0 * k2 + 2.0 * k3 + k4)


def rk2_step(y: np.ndarray, f0: np.ndarray, t: float, dt: float, f: Rate) -> np.ndarray:
    k2 = f(y + dt * f0, t + dt)
    return y + (0.5 * dt) * (f0 + k2)


def abm4_step(y: np.ndarray, history: Sequence[np.ndarray], t: float, dt: float,
              f: Rate) -> np.ndarray:
    """``history = (F_n, F_{n-1}, F_{n-2}, F_{n-3})``."""
    fn, f1, f2, f3 = history
    predicted = y + (dt / 24.0) * (55.0 * fn - 59.0 * f1 + 37.0 * f2 - 9.0 * f3)
    fp = f(predicted, t + dt)
    return y + (dt / 24.0) * (9.0 * fp + 19.0 * fn - 5.0 * f1 + f2)


class Stepper:
    """One integrator with its history. ``step(y, f0, t, dt, f)`` advances one step;
    ``restart(n)`` forces ``n`` RK4 steps (ABM4 only) and discards the history."""

    def __init__(self, name: str, restart_steps: int = 4) -> None:
        if name not in EVALUATIONS_PER_STEP:
            raise ValueError(f"integrator: {name!r} is not allowed; allowed values: "
                             f"{', '.join(EVALUATIONS_PER_STEP)}")
        self.name = name
        self.restart_steps = restart_steps
        self.history: list[np.ndarray] = []
        self.rk4_left = restart_steps if name == "abm4" else 0

    def restart(self) -> None:
        self.history.clear()
        if self.name == "abm4":
            self.rk4_left = self.restart_steps

    def step(self, y: np.ndarray, f0: np.ndarray, t: float, dt: float, f: Rate) -> np.ndarray:
        if self.name == "rk2":
            return rk2_step(y, f0, t, dt, f)
        if self.name == "rk4":
            return rk4_step(y, f0, t, dt, f)
        self.history.insert(0, f0)
        del self.history[4:]
        if self.rk4_left > 0 or len(self.history) < 4:
            self.rk4_left = max(0, self.rk4_left - 1)
            return rk4_step(y, f0, t, dt, f)
        return abm4_step(y, self.history, t, dt, f)

    def state(self) -> tuple[list[np.ndarray], int]:
        return list(self.history), self.rk4_left

    def set_state(self, history: list[np.ndarray], rk4_left: int) -> None:
        self.history = list(history)
        self.rk4_left = int(rk4_left)
