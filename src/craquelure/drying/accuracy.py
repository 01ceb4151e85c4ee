r"""What accuracy costs in time for the drying engine: error versus wall time over integrators
and time steps (the "cheap scheme" of spec section 8 against RK4 and ABM4-PECE).

Problem: the scene given (normally ``drying/accuracy``, fracture off so the solution is
smooth) integrated to ``outputs.t_end`` with each (integrator, dt) pair. The reference is RK4
at ``reference_dt`` (half the smallest dt studied). The error of a run is the relative L2
distance of its final velocity field from the reference's,

    e = ||v - v_ref||_2 / ||v_ref||_2,

the velocities being the most sensitive part of the state (positions and stresses follow from them
by one more integration). Wall time is measured around the stepping loop only, after the rate
function is compiled, on the threads the caller has set, so it is the cost of the integration alone.
The observed order between successive dt (slope of log e against log dt) is stored too.

The error-controlled Runge-Kutta-Chebyshev scheme ``rkc2`` (not bound by the viscous limit,
:mod:`craquelure.drying.integrators`) is run at each of ``rkc_tolerances`` (its own dim
``tolerance``: its steps are chosen by the controller, not from the dt grid) with the same
error measure, wall time and evaluation count, so both families sit on one error-versus-cost
plot."""

from __future__ import annotations

import time
from collections.abc import Sequence

import numpy as np
import xarray as xr

from craquelure.drying.api import engine_from_initial
from craquelure.drying.engine import VX, VY
from craquelure.drying.initial_state import build_initial_state
from craquelure.errors import CraquelureError
from craquelure.scene import Scene

INTEGRATORS = ("rk2", "abm4", "rk4")
RKC_TOLERANCES = (1e-2, 1e-3, 1e-4, 1e-5, 1e-6)


def _integrate(scene: Scene, init: xr.Dataset, integrator: str, dt: float,
               tolerance: float | None = None) -> tuple[np.ndarray, float, int]:
    """Final velocities, wall time of the stepping loop and rate evaluations (fixed dt, or
    rkc2 error-controlled at ``tolerance`` starting from dt)."""
    overrides = [f"numerics.integrator={integrator}", f"numerics.dt={dt!r}",
                 f"numerics.adapt_dt={'true' if tolerance else 'false'}"]
    if tolerance:
        overrides.append(f"numerics.step_control.tolerance={tolerance!r}")
    engine = engine_from_initial(scene.with_overrides(overrides), init)
    t_end = float(scene.get("outputs.t_end"))
    n_steps = int(round(t_end / dt))
    if not tolerance and abs(n_steps * dt - t_end) > 1e-9 * t_end:
        raise CraquelureError(f"accuracy: dt = {dt} does not divide t_end = {t_end}")
    evaluations, start = engine.evaluations, time.perf_counter()
    engine.stop_at = t_end  # the adaptive steps end on it
    while engine.t < t_end - engine.time_tolerance() if tolerance else engine.step_count < n_steps:
        engine.step()
    wall = time.perf_counter() - start
    engine.check_health()
    velocity = np.concatenate([engine.state[VX], engine.state[VY]])
    return velocity, wall, engine.evaluations - evaluations


def error_versus_wall_time(scene: Scene, seed: int, time_steps: Sequence[float],
                           integrators: Sequence[str] = INTEGRATORS,
                           reference_dt: float | None = None,
                           rkc_tolerances: Sequence[float] = RKC_TOLERANCES) -> xr.Dataset:
    """Error and wall time for every (integrator, dt); dims ``integrator`` x ``dt``; and of
    rkc2 at every tolerance (dim ``tolerance``, variables ``rkc2_*``)."""
    if scene.has("fracture"):
        raise CraquelureError("accuracy: the scene must not contain the effect 'fracture' "
                              "(removals make the solution non-smooth in time)")
    unknown = sorted(set(integrators) - set(INTEGRATORS))
    if unknown:
        raise CraquelureError(f"accuracy: integrators {unknown} are not allowed; allowed "
                              f"values: {', '.join(INTEGRATORS)}")
    dts = np.array(sorted(time_steps, reverse=True), float)
    ref_dt = float(reference_dt) if reference_dt else float(dts[-1]) / 2.0
    init = build_initial_state(scene, seed)
    # Compile (or load from the disk cache) before anything is timed: two reference steps.
    warm_end = 2.0 * ref_dt
    warm_up = scene.with_overrides([f"numerics.dt={ref_dt!r}", f"outputs.t_end={warm_end!r}",
                                   f"outputs.times=[{warm_end!r}]"])
    _integrate(warm_up, init, "rk4", ref_dt)
    reference, ref_wall, _ = _integrate(scene, init, "rk4", ref_dt)
    ref_norm = float(np.linalg.norm(reference))
    if ref_norm == 0.0:
        raise CraquelureError("accuracy: the reference run stays at rest; the scene needs a "
                              "driving effect (drying) so that the error is measurable")
    shape = (len(integrators), dts.size)
    error, wall, evaluations = np.empty(shape), np.empty(shape), np.empty(shape, np.int64)
    for i, name in enumerate(integrators):
        for j, dt in enumerate(dts.tolist()):
            velocity, wall[i, j], evaluations[i, j] = _integrate(scene, init, name, dt)
            error[i, j] = np.linalg.norm(velocity - reference) / ref_norm
    tolerances = np.array(sorted(rkc_tolerances, reverse=True), float)
    rkc = np.empty((3, tolerances.size))
    for k, tol in enumerate(tolerances.tolist()):
        velocity, rkc[1, k], rkc[2, k] = _integrate(scene, init, "rkc2", float(dts[-1]), tol)
        rkc[0, k] = np.linalg.norm(velocity - reference) / ref_norm
    with np.errstate(divide="ignore", invalid="ignore"):
        order = np.log(error[:, :-1] / error[:, 1:]) / np.log(dts[:-1] / dts[1:])
    return xr.Dataset(  # long names and units: craquelure.cf's table on writing
        {"error": (("integrator", "dt"), error), "wall_time": (("integrator", "dt"), wall),
         "rate_evaluations": (("integrator", "dt"), evaluations),
         "observed_order": (("integrator", "dt_pair"), order), "rkc2_error": ("tolerance", rkc[0]),
         "rkc2_wall_time": ("tolerance", rkc[1]),
         "rkc2_rate_evaluations": ("tolerance", rkc[2].astype(np.int64))},
        coords={"integrator": list(integrators), "dt": dts, "dt_pair": np.arange(dts.size - 1),
                "tolerance": tolerances},
        attrs={"reference": "rk4", "reference_dt": ref_dt,
               "reference_wall_time_s": ref_wall, "t_end": float(scene.get("outputs.t_end")),
               "n_particles": int(init.sizes["particle"]),
               "error_measure": "||v - v_ref||_2 / ||v_ref||_2 at t_end"},
    )
