r"""Time integrators (drying spec section 8). They see only a state array ``y`` and a rate callable
``f(y, t) -> dy/dt``, nothing of the physics. Every step takes ``f0 = f(y_n, t_n)`` (the last
evaluation of the previous step) and returns ``y_{n+1}``; the caller evaluates ``f(y_{n+1})`` once,
which both ends this step (fracture test, ABM history, RKC error estimate) and starts the next.

Fixed-step schemes (the paper's and the accuracy study's), with their real-axis stability:

- ``rk4``: classical four-stage Runge-Kutta (4th order; 2.785).
- ``abm4``: Adams-Bashforth-Moulton PECE, 4th order, two evaluations per step (1.285):
  :math:`Y^* = Y_n + \tfrac{\Delta t}{24}(55F_n - 59F_{n-1} + 37F_{n-2} - 9F_{n-3})`,
  :math:`Y_{n+1} = Y_n + \tfrac{\Delta t}{24}(9F(Y^*) + 19F_n - 5F_{n-1} + F_{n-2})`. The
  caller restarts it with RK4 steps at the start and whenever its history of rates becomes
  invalid (particle removal, a change of time step).
- ``rk2``: Heun's method, the cheap second-order scheme of the accuracy study.

Stabilised explicit scheme for the real viscous spectrum, not bound by the viscous limit:

- ``rkc2``: damped second-order Runge-Kutta-Chebyshev (Sommeijer, Shampine & Verwer, J. Comput.
  Appl. Math. 88 (1998) 315; van der Houwen & Sommeijer 1980). With :math:`s` stages,
  damping :math:`\epsilon = 2/13`, :math:`w_0 = 1 + \epsilon/s^2`,
  :math:`w_1 = T_s'(w_0)/T_s''(w_0)`, :math:`b_j = T_j''(w_0)/T_j'(w_0)^2` (:math:`j \ge 2`,
  :math:`b_0 = b_1 = b_2`), :math:`a_j = 1 - b_j T_j(w_0)` and Chebyshev polynomials
  :math:`T_j`:

  .. math::

     Y_0 &= y_n, \qquad Y_1 = Y_0 + \tilde\mu_1 \Delta t F_0, \qquad \tilde\mu_1 = b_1 w_1,\\
     Y_j &= (1-\mu_j-\nu_j) Y_0 + \mu_j Y_{j-1} + \nu_j Y_{j-2}
            + \tilde\mu_j \Delta t\, F(Y_{j-1}, t_n + c_{j-1}\Delta t)
            + \tilde\gamma_j \Delta t F_0, \quad j = 2..s,\\
     y_{n+1} &= Y_s,

  :math:`\mu_j = 2 b_j w_0/b_{j-1}`, :math:`\nu_j = -b_j/b_{j-2}`,
  :math:`\tilde\mu_j = 2 b_j w_1/b_{j-1}`, :math:`\tilde\gamma_j = -a_{j-1}\tilde\mu_j`,
  stage times :math:`c_j = w_1 T_j''(w_0)/T_j'(w_0)` (:math:`c_1 = c_2/T_2'(w_0)`,
  :math:`c_s = 1`). Its stability polynomial is
  :math:`R_s(z) = a_s + b_s T_s(w_0 + w_1 z)`, second order, with a real-axis stability
  interval :math:`[-\beta(s), 0]`,
  :math:`\beta(s) \approx \tfrac23 (s^2-1)(1 - \tfrac{2}{15}\epsilon) \approx 0.653\,s^2`.
  The stage count is the smallest that covers the spectrum:
  :math:`s = 1 + \lfloor\sqrt{1 + 1.54\,\Delta t\,\rho}\rfloor` (:math:`\ge 2`), with
  :math:`\rho` the (safety-scaled) spectral radius of the stiff part, so the work per unit
  time falls as :math:`\Delta t^{-1/2}`.
  Near the imaginary axis :math:`|R_s(iy)| \approx 1 + 0.035\,y^4` (:math:`s \ge 6`): undamped
  oscillations (the substrate mode, :math:`y = \omega_0\Delta t`, and the grid-scale velocity
  modes the kernel gradient cannot see) grow slowly, which the step cap ``dt_max`` keeps
  small; hence the default ``dt_max = 0.2``.

  Local error estimate (second order, from the two end rates, no extra evaluation because
  :math:`F_{n+1}` is needed anyway for the fracture test and the next step):
  :math:`\mathrm{est} = \tfrac{12}{15}(y_n - y_{n+1}) + \tfrac{6}{15}\Delta t (F_n + F_{n+1})`.
  :class:`StepController` accepts a step when the scaled max-norm
  :math:`e = \max |\mathrm{est}|/\mathrm{scale} \le 1` and proposes
  :math:`\Delta t_{new} = \Delta t \min(10, \max(0.1, 0.8\, e^{-1/3}))` (with the PI
  correction :math:`(\Delta t/\Delta t_{prev})(e_{prev}/e)^{1/3}` after an accepted step, and
  no growth right after a rejection), capped at ``dt_max``. The max norm makes the step follow
  the worst particle: it shrinks where a removal starts a fast local transient.

The per-step vector work (RKC stages, ABM4's predictor and corrector, the RKC error norm) runs
in fused numba loops on the run's threads, each element computed in the same order as the
numpy expression (bit-identical to it) instead of serial numpy temporaries."""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from functools import cache

import numpy as np
from numba import njit, prange

Rate = Callable[[np.ndarray, float], np.ndarray]

FIXED_STEP = ("abm4", "rk4", "rk2")
ADAPTIVE = ("rkc2",)
INTEGRATORS = FIXED_STEP + ADAPTIVE
REAL_AXIS_LIMIT = {"rk4": 2.785, "abm4": 1.285, "rk2": 2.0}
RKC_DAMPING = 2.0 / 13.0
# Safety factor on the power-iteration estimate of the spectral radius (a lower bound).
RKC_SPECTRAL_SAFETY = 1.2
# columns per block of the parallel error norm (one partial maximum per block)
NORM_BLOCK = 4096


@njit(parallel=True, cache=True)
def _rkc_stage(a, y, b, current, c, previous, d, rate, e, f0, out):
    for i in prange(out.size):
        out[i] = a * y[i] + b * current[i] + c * previous[i] + d * rate[i] + e * f0[i]


@njit(parallel=True, cache=True)
def _abm4_predictor(y, h, fn, f1, f2, f3, out):
    for i in prange(out.size):
        out[i] = y[i] + h * (55.0 * fn[i] - 59.0 * f1[i] + 37.0 * f2[i] - 9.0 * f3[i])


@njit(parallel=True, cache=True)
def _abm4_corrector(y, h, fp, fn, f1, f2, out):
    for i in prange(out.size):
        out[i] = y[i] + h * (9.0 * fp[i] + 19.0 * fn[i] - 5.0 * f1[i] + f2[i])


@njit(parallel=True, cache=True)
def _rkc2_error_norm(y0, y1, f0, f1, h, scale, alive):
    """max over alive columns of |0.8 (y0 - y1) + h (f0 + f1)| / scale[row] (rows of
    (nrow, ncol) arrays); inf if any of those is not finite."""
    nrow, ncol = y0.shape
    blocks = (ncol + NORM_BLOCK - 1) // NORM_BLOCK
    peak = np.zeros(blocks)
    bad = np.zeros(blocks, np.bool_)
    for b in prange(blocks):
        m = 0.0
        for j in range(b * NORM_BLOCK, min(ncol, (b + 1) * NORM_BLOCK)):
            if alive[j]:
                for r in range(nrow):
                    x = abs(0.8 * (y0[r, j] - y1[r, j]) + h * (f0[r, j] + f1[r, j])) / scale[r]
                    if not x <= np.inf:  # NaN or inf
                        bad[b] = True
                    elif x > m:
                        m = x
        peak[b] = m
    return np.inf if bad.any() else peak.max()


def _flat(a: np.ndarray) -> np.ndarray:
    return np.ascontiguousarray(a).reshape(-1)


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
    h = dt / 24.0
    predicted = np.empty_like(y)
    _abm4_predictor(_flat(y), h, _flat(fn), _flat(f1), _flat(f2), _flat(f3), _flat(predicted))
    fp = f(predicted, t + dt)
    corrected = np.empty_like(y)
    _abm4_corrector(_flat(y), h, _flat(fp), _flat(fn), _flat(f1), _flat(f2), _flat(corrected))
    return corrected


def rkc_stages(dt: float, spectral_radius: float) -> int:
    """Smallest stage count whose real stability interval covers ``dt * spectral_radius``."""
    return max(2, 1 + int(math.sqrt(1.0 + 1.54 * dt * max(spectral_radius, 0.0))))


@cache
def rkc_coefficients(s: int, damping: float = RKC_DAMPING):
    """(mu, nu, mu_tilde, gamma_tilde, c, a_s, b_s, w0, w1) of the s-stage damped RKC2; index
    j = 1..s (entry 0 unused except c[0] = 0)."""
    if s < 2:
        raise ValueError(f"rkc2 needs at least 2 stages, got {s}")
    w0 = 1.0 + damping / s**2
    t, tp, tpp = np.zeros((3, s + 1))  # T_j, T_j' and T_j'' at w0
    t[0], t[1], tp[1] = 1.0, w0, 1.0
    for j in range(2, s + 1):
        t[j] = 2.0 * w0 * t[j - 1] - t[j - 2]
        tp[j] = 2.0 * t[j - 1] + 2.0 * w0 * tp[j - 1] - tp[j - 2]
        tpp[j] = 4.0 * tp[j - 1] + 2.0 * w0 * tpp[j - 1] - tpp[j - 2]
    w1 = tp[s] / tpp[s]
    b = np.zeros(s + 1)
    b[2:] = tpp[2:] / tp[2:] ** 2
    b[0] = b[1] = b[2]
    a = 1.0 - b * t
    mu, nu, mu_t, gamma_t = np.zeros((4, s + 1))
    mu_t[1] = b[1] * w1
    for j in range(2, s + 1):
        mu[j] = 2.0 * b[j] * w0 / b[j - 1]
        nu[j] = -b[j] / b[j - 2]
        mu_t[j] = 2.0 * b[j] * w1 / b[j - 1]
        gamma_t[j] = -a[j - 1] * mu_t[j]
    c = np.zeros(s + 1)
    c[2:] = w1 * tpp[2:] / tp[2:]
    c[1] = c[2] / tp[2]
    c[s] = 1.0
    return mu, nu, mu_t, gamma_t, c, float(a[s]), float(b[s]), w0, w1


def rkc_stability(z: np.ndarray, s: int, damping: float = RKC_DAMPING) -> np.ndarray:
    """R_s(z) = a_s + b_s T_s(w0 + w1 z) of the s-stage damped RKC2."""
    *_, a_s, b_s, w0, w1 = rkc_coefficients(s, damping)
    return a_s + b_s * np.polynomial.chebyshev.chebval(w0 + w1 * np.asarray(z),
                                                       [0.0] * s + [1.0])


def rkc2_step(y: np.ndarray, f0: np.ndarray, t: float, dt: float, f: Rate,
              stages: int) -> np.ndarray:
    """One step of the s-stage damped RKC2 (``stages - 1`` new evaluations)."""
    mu, nu, mu_t, gamma_t, c, *_ = rkc_coefficients(stages)
    previous = y
    current = y + (mu_t[1] * dt) * f0
    for j in range(2, stages + 1):
        rate = f(current, t + c[j - 1] * dt)
        following = np.empty_like(y)
        _rkc_stage(1.0 - mu[j] - nu[j], _flat(y), mu[j], _flat(current), nu[j], _flat(previous),
                   mu_t[j] * dt, _flat(rate), gamma_t[j] * dt, _flat(f0), _flat(following))
        previous, current = current, following
    return current


def rkc2_error_norm(y0: np.ndarray, y1: np.ndarray, f0: np.ndarray, f1: np.ndarray, dt: float,
                    scale: np.ndarray, alive: np.ndarray) -> float:
    """Scaled max-norm (module docstring) of an RKC2 step's local error estimate over the
    columns with ``alive``, in one pass without temporaries; inf if any entry is not finite."""
    arrays = [np.ascontiguousarray(a, dtype=np.float64) for a in (y0, y1, f0, f1)]
    return float(_rkc2_error_norm(*arrays, 0.4 * dt, np.ascontiguousarray(scale, np.float64),
                                  np.ascontiguousarray(alive)))


class StepController:
    """Step control of ``rkc2`` (elementary + PI control as in RKC) and what the engine's rkc2
    step keeps between steps. ``propose(err, dt)``, once per attempted step with the scaled
    error norm, returns True if the step is accepted and sets ``dt_next``."""

    SAFETY, FAC_MIN, FAC_MAX = 0.8, 0.1, 10.0

    def __init__(self, dt: float, dt_max: float) -> None:
        self.dt_next = float(min(dt, dt_max))
        self.dt_max = float(dt_max)
        self.err_prev = 0.0  # 0: no accepted step yet (elementary control)
        self.dt_prev = 0.0
        self.rejected_last = False
        self.accepted = self.rejected = 0
        self.spectral_radius = 0.0
        self.dt_event = math.inf
        self.error_scale = np.ones(1)

    @classmethod
    def from_scene(cls, scene, dt: float) -> StepController:
        """The controller of a scene's rkc2 run, starting at ``dt``."""
        control = scene.get("numerics.step_control")
        ctrl = cls(dt, float(control["dt_max"]))
        ctrl.adapt = bool(scene.get("numerics.adapt_dt"))
        ctrl.tolerance = float(control["tolerance"])
        ctrl.removal_tolerance = float(control["removal_tolerance"])
        ctrl.spectral_every = int(control["spectral_radius_every"])
        ctrl.dt_floor = float(control["dt_min"])
        return ctrl

    def propose(self, err: float, dt: float) -> bool:
        if not math.isfinite(err) or err > 1.0:
            fac = self.SAFETY * err ** (-1.0 / 3.0) if math.isfinite(err) else self.FAC_MIN
            self.dt_next = dt * max(self.FAC_MIN, min(fac, 0.9))
            self.rejected_last = True
            self.rejected += 1
            return False
        e = max(err, 1e-10)
        fac = self.SAFETY * e ** (-1.0 / 3.0)
        if self.err_prev > 0.0:
            fac *= (dt / self.dt_prev) * (self.err_prev / e) ** (1.0 / 3.0)
        fac = min(self.FAC_MAX, max(self.FAC_MIN, fac))
        if self.rejected_last:
            fac = min(fac, 1.0)
        self.dt_next = min(self.dt_max, dt * fac)
        self.err_prev, self.dt_prev = e, dt
        self.rejected_last = False
        self.accepted += 1
        return True

    def forget(self) -> None:
        """Drop the PI memory (after a removal the error history describes another problem)."""
        self.err_prev = 0.0


class Stepper:
    """One integrator with its history. ``step(y, f0, t, dt, f)`` advances one step;
    ``restart(n)`` forces ``n`` RK4 steps (ABM4 only) and discards the history. For ``rkc2``
    the caller sets ``stages`` (from the spectral radius) before each step."""

    def __init__(self, name: str, restart_steps: int = 4) -> None:
        if name not in INTEGRATORS:
            raise ValueError(f"integrator: {name!r} is not allowed; allowed values: "
                             f"{', '.join(INTEGRATORS)}")
        self.name = name
        self.adaptive = name in ADAPTIVE
        self.restart_steps = restart_steps
        self.history: list[np.ndarray] = []
        self.rk4_left = restart_steps if name == "abm4" else 0
        self.stages = 2

    def restart(self) -> None:
        self.history.clear()
        if self.name == "abm4":
            self.rk4_left = self.restart_steps

    def step(self, y: np.ndarray, f0: np.ndarray, t: float, dt: float, f: Rate) -> np.ndarray:
        if self.name == "rkc2":
            return rkc2_step(y, f0, t, dt, f, self.stages)
        if self.name != "abm4":
            return {"rk2": rk2_step, "rk4": rk4_step}[self.name](y, f0, t, dt, f)
        self.history.insert(0, f0)
        del self.history[4:]
        if self.rk4_left > 0 or len(self.history) < 4:
            self.rk4_left = max(0, self.rk4_left - 1)
            return rk4_step(y, f0, t, dt, f)
        return abm4_step(y, self.history, t, dt, f)
