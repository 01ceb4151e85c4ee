"""Time integration of a :class:`~craquelure.softdyn.engine.Engine` (spec section 8).

* ``LSODA``, ``BDF``, ``Radau``: SciPy's adaptive stiff solvers, driven step by step (their
  ``OdeSolver.step`` interface) so that every accepted step is checked: a step that ends with a
  gap h <= 0 is rejected and redone from the previous state with a quarter of the step as the
  maximum (up to ``MAX_REJECTIONS`` times); NaN/inf and a particle balance residual
  max_i |F_i + sum_j f_ij| above ``drift_tolerance * force_scale`` stop the run with
  :class:`~craquelure.errors.SimulationDiverged`. The load ramp has a kink in dF/dt at t_r, so
  integration restarts there.
* ``heun``: fixed-step second-order Runge-Kutta (explicit trapezoid), for the accuracy study; it is
  explicit, so it needs dt below the fastest relaxation time (about 5 F~ tau, spec section 8).

A stop condition ``g(t, y)`` ends the run at its first upward zero crossing, located on the
solver's dense output (Brent's method; linear interpolation for ``heun``).
"""

import math
import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from scipy.integrate import BDF, LSODA, Radau
from scipy.optimize import brentq

from craquelure.errors import CraquelureError, SimulationDiverged
from craquelure.progress import Progress
from craquelure.runner import Divergence, Interrupted, diverged, stop_requested

ADAPTIVE = {"LSODA": LSODA, "BDF": BDF, "Radau": Radau}
METHODS = (*ADAPTIVE, "heun")
MAX_REJECTIONS = 40


@dataclass
class Result:
    t: np.ndarray            # sample times (including 0 and the stop time when stopped)
    y: np.ndarray            # (n_samples, state size)
    stopped: bool            # the stop condition was met
    t_stop: float            # time of the (first) stop crossing (t_end when not met)
    y_stop: np.ndarray
    t_final: float           # last time integrated (t_stop unless run on after the stop)
    n_steps: int
    n_rhs: int
    n_rejected: int
    wall_time_s: float


class Guard:
    """Checks run after every accepted step."""

    def __init__(self, system, force_scale: float, drift_tolerance: float, time_unit: float):
        self.system, self.force_scale = system, force_scale
        self.drift_tolerance, self.time_unit = drift_tolerance, time_unit

    def where(self, t: float, step: int) -> str:
        return f"at t = {t / self.time_unit:.6g} tau (step {step})"

    def check_health(self, t: float, y: np.ndarray, step: int) -> None:
        """Raise the runner's :class:`SimulationDiverged` when :meth:`health` fails."""
        bad = self.health(t, y)
        if bad is not None:
            raise diverged("softdyn", bad, step, t / self.time_unit, "tau")

    def health(self, t: float, y: np.ndarray) -> Divergence | None:
        """NaN/inf in the state (the particle of the first bad centre coordinate), or the
        particle balance residual max_i |F_i + sum_j f_ij| above ``drift_tolerance`` times
        the force scale (the particle with the largest residual)."""
        if not np.all(np.isfinite(y)):
            first = int(np.flatnonzero(~np.isfinite(y))[0])
            n, d = self.system.x0.shape
            return Divergence("finite", f"state component {first} is not finite",
                              first // d if first < n * d else None)
        if not self.system.flags.hertz:
            return None
        sysm = self.system
        x, s, q = sysm.unpack(y)
        out = sysm.k.pair_terms(x, s, q, sysm.pi, sysm.pj, sysm.p)
        _, resid = sysm.k.particle_terms(t, sysm.pi, sysm.pj, sysm.F0, sysm.p, out[6], out[8])
        per_particle = np.abs(np.asarray(resid)).reshape(sysm.n, -1).max(axis=1)
        worst = float(per_particle.max())
        if not math.isfinite(worst) or worst > self.drift_tolerance * self.force_scale:
            return Divergence("force balance",
                              f"drifted: max_i |F_i + sum_j f_ij| = {worst:.3g} > "
                              f"{self.drift_tolerance:g} x {self.force_scale:.3g}",
                              int(np.nanargmax(per_particle)))
        return None


def integrate(system, t_end: float, method: str = "LSODA", rtol: float = 1e-8,
              atol: float = 1e-12, dt: float | None = None,
              stop: Callable[[float, np.ndarray], float] | None = None,
              sample_times: np.ndarray | None = None, force_scale: float = 1.0,
              drift_tolerance: float = 1e-6, time_unit: float = 1.0, max_steps: int = 2_000_000,
              desc: str = "softdyn", terminal: bool = True) -> Result:
    """Integrate from the system's initial state to ``t_end`` or the stop condition.

    ``atol`` is in units of R (positions and deflections); ``dt`` is the ``heun`` step. With
    ``terminal=False`` the first stop crossing is recorded and the run goes on to ``t_end``."""
    if method not in METHODS:
        raise CraquelureError(f"numerics.integrator: {method!r}; allowed: {', '.join(METHODS)}")
    guard = Guard(system, force_scale, drift_tolerance, time_unit)
    samples = np.unique(np.concatenate([[0.0], [] if sample_times is None else sample_times]))
    samples = samples[samples <= t_end]
    rec = _Recorder(samples, system.initial_state())
    event = _Event(stop, terminal)
    clock = time.perf_counter()
    n_rhs0 = system.n_rhs
    progress = Progress(t_end / time_unit, desc, unit="tau")
    try:
        if method == "heun":
            if not dt or dt <= 0:
                raise CraquelureError("numerics.dt: the heun integrator needs a step dt > 0")
            out = _heun(system, t_end, dt, event, rec, guard, max_steps, progress, time_unit)
        else:
            out = _adaptive(system, ADAPTIVE[method], t_end, rtol, atol, event, rec, guard,
                            max_steps, progress, time_unit)
    finally:
        progress.close()
    t_final, y_final, n_steps, n_rej = out
    rec.finish(t_final, y_final)
    stopped = event.t is not None
    return Result(t=np.array(rec.t), y=np.array(rec.y), stopped=stopped,
                  t_stop=event.t if stopped else t_final,
                  y_stop=event.y if stopped else y_final, t_final=t_final,
                  n_steps=n_steps, n_rhs=system.n_rhs - n_rhs0,
                  n_rejected=n_rej, wall_time_s=time.perf_counter() - clock)


class _Event:
    """First upward zero crossing of the stop function."""

    def __init__(self, stop, terminal: bool):
        self.stop, self.terminal = stop, terminal
        self.t = self.y = None
        self.g_prev = -1.0

    def start(self, t: float, y: np.ndarray) -> None:
        if self.stop is not None:
            self.g_prev = self.stop(t, y)

    def crossed(self, t_old, t_new, y_new, interp, linear: bool = False) -> bool:
        """Locate a crossing in (t_old, t_new]; True when the run must end here."""
        if self.stop is None or self.t is not None:
            return False
        g_new = self.stop(t_new, y_new)
        if self.g_prev < 0.0 <= g_new:
            if linear:
                ts = t_old + (-self.g_prev / (g_new - self.g_prev)) * (t_new - t_old)
            else:
                ts = brentq(lambda tt: self.stop(tt, interp(tt)), t_old, t_new,
                            xtol=1e-14 * max(1.0, t_new), rtol=1e-13)
            self.t, self.y = float(ts), np.asarray(interp(ts), dtype=float).copy()
            return self.terminal
        self.g_prev = g_new
        return False


class _Recorder:
    def __init__(self, samples: np.ndarray, y0: np.ndarray):
        self.samples = samples
        self.next = 1 if samples.size and samples[0] == 0.0 else 0
        self.t, self.y = [0.0], [y0.copy()]

    def take(self, t_new: float, interp: Callable[[float], np.ndarray]) -> None:
        while self.next < self.samples.size and self.samples[self.next] <= t_new:
            ts = float(self.samples[self.next])
            self.t.append(ts)
            self.y.append(np.asarray(interp(ts), dtype=float).copy())
            self.next += 1

    def finish(self, t: float, y: np.ndarray) -> None:
        if t > self.t[-1]:
            self.t.append(float(t))
            self.y.append(y.copy())


def _adaptive(system, cls, t_end, rtol, atol, event, rec, guard, max_steps, progress, unit):
    atol_v = np.full(system.state_size, atol * system.radius)  # atol in units of R
    t, y = 0.0, system.initial_state()
    event.start(t, y)
    breaks = [tb for tb in (system.ramp_time,) if 0.0 < tb < t_end] + [t_end]
    n_steps = n_rej = 0
    for t_bound in breaks:
        max_step = np.inf
        solver = cls(system.rhs, t, y, t_bound, rtol=rtol, atol=atol_v)
        while t < t_bound:
            t_old, y_old = t, y.copy()
            try:
                message = solver.step()
            except (np.linalg.LinAlgError, ValueError, ZeroDivisionError, FloatingPointError) \
                    as exc:
                raise SimulationDiverged(f"{cls.__name__} step failed "
                                         f"{guard.where(t_old, n_steps)}: {exc}") from exc
            if solver.status == "failed":
                raise SimulationDiverged(f"{cls.__name__} failed {guard.where(t_old, n_steps)}: "
                                         f"{message}")
            t_new, y_new = solver.t, solver.y
            if not np.all(np.isfinite(y_new)) or system.min_gap(y_new) <= 0.0:
                n_rej += 1
                if n_rej > MAX_REJECTIONS:
                    guard.check_health(t_new, y_new, n_steps)
                    raise SimulationDiverged(
                        f"a gap closed (h <= 0) {guard.where(t_new, n_steps)} after "
                        f"{MAX_REJECTIONS} step rejections")
                max_step = 0.25 * (t_new - t_old) if t_new > t_old else max_step / 4
                solver = cls(system.rhs, t_old, y_old, t_bound, rtol=rtol, atol=atol_v,
                             max_step=max_step)
                continue
            n_steps += 1
            guard.check_health(t_new, y_new, n_steps)
            interp = solver.dense_output()
            rec.take(t_new, interp)
            if event.crossed(t_old, t_new, y_new, interp):
                return event.t, event.y, n_steps, n_rej
            t, y = t_new, np.array(y_new)
            progress.update_to(t / unit)
            if stop_requested():  # SIGTERM/SIGINT: the runner keeps the finished points
                raise Interrupted
            if n_steps >= max_steps:
                raise CraquelureError(f"numerics.max_steps = {max_steps} reached "
                                      f"{guard.where(t, n_steps)}")
    return t, y, n_steps, n_rej


def _heun(system, t_end, dt, event, rec, guard, max_steps, progress, unit):
    """Explicit trapezoid on a step grid that lands on every break of the right-hand side (the
    end of the load ramp, where dF/dt jumps) and evaluates its second stage there on the
    left-hand side (``nextafter`` below the break), so no step straddles the jump: a straddling
    step makes an O(dt) local error, hence first order globally."""
    breaks = [tb for tb in (system.ramp_time,) if 0.0 < tb < t_end] + [t_end]
    n_total = sum(int(math.ceil((b - a) / dt - 1e-9))
                  for a, b in zip([0.0, *breaks[:-1]], breaks, strict=True))
    if n_total > max_steps:
        raise CraquelureError(f"heun: t_end/dt = {n_total} steps > numerics.max_steps")
    y = system.initial_state()
    t = 0.0
    event.start(t, y)
    step = 0
    for t_bound in breaks:
        n_seg = int(math.ceil((t_bound - t) / dt - 1e-9))
        t_seg = t
        for m in range(1, n_seg + 1):
            step += 1
            t_new = t_seg + (t_bound - t_seg) * m / n_seg if m < n_seg else t_bound
            h = t_new - t
            k1 = system.rhs(t, y)
            t_stage = t_new if m < n_seg else math.nextafter(t_new, -math.inf)
            k2 = system.rhs(t_stage, y + h * k1)
            y_new = y + 0.5 * h * (k1 + k2)
            if system.min_gap(y_new) <= 0.0:
                raise SimulationDiverged(f"a gap closed (h <= 0) {guard.where(t_new, step)}: "
                                         f"the heun step dt = {dt / unit:g} tau is too large")
            guard.check_health(t_new, y_new, step)

            def interp(tt, t0=t, y0=y, t1=t_new, y1=y_new):
                w = (tt - t0) / (t1 - t0)
                return (1.0 - w) * y0 + w * y1

            rec.take(t_new, interp)
            if event.crossed(t, t_new, y_new, interp, linear=True):
                return event.t, event.y, step, 0
            t, y = t_new, y_new
            if step % 1000 == 0:
                progress.update_to(t / unit)
                if stop_requested():
                    raise Interrupted
    return t, y, n_total, 0
