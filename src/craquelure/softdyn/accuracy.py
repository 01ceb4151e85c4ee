"""Accuracy versus cost of the integrators on one T1 (spec section 8, check 13).

The scene's T1 (``study.kind: accuracy``) is run once with LSODA at ``study.reference_rtol``
(atol 1e-14 R): that tightest run is the reference. Then every adaptive integrator in
``study.integrators`` at every ``study.rtol``, and the fixed-step ``heun`` scheme at every
``study.dt`` (units of tau). For each run: the T1 duration error |T - T_ref| / tau, the error of
the whole state at ``study.probe_time`` (a smooth observable; max norm, units of R), the
integration wall time (kernels compiled before, so it is the cost of the run) and the number of
right-hand sides. A heun step above its stability limit stops with ``SimulationDiverged``: such
a point is recorded as ``stable = 0`` with NaN errors, which marks the explicit limit.

Decision [D]: every run of the study (the reference included) uses the scene's Baumgarte time;
the exact solution does not depend on it (the drift term vanishes on the constraint), but the
explicit step must resolve 1/tau_B, so the accuracy scene sets tau_B = 0.1 tau and a loose drift
tolerance (heun has no error control on the constraint; its residual is O(dt^2)).
"""

import numpy as np
import xarray as xr

from craquelure.errors import SceneError, SimulationDiverged
from craquelure.softdyn.engine import run
from craquelure.softdyn.initial_state import build


def _run(scene, overrides: list[str], probe_tau: float):
    setup = build(scene.with_overrides(["outputs.run_past_stop=false", *overrides]))
    res = run(setup, sample_times_tau=np.array([probe_tau]), desc="accuracy")
    k = int(np.argmin(np.abs(res.t / setup.tau - probe_tau)))
    if not res.stopped:
        raise SceneError("accuracy study: the T1 did not end by outputs.t_end")
    return (res.t_stop / setup.tau, res.y[k] / setup.system.radius, res.wall_time_s, res.n_rhs)


def run_accuracy(scene) -> xr.Dataset:
    integrators = list(scene.get("study.integrators"))
    rtols = np.asarray(scene.get("study.rtol"), dtype=float)
    dts = np.asarray(scene.get("study.dt"), dtype=float)  # one at least (scene rules)
    probe = float(scene.get("study.probe_time"))
    ref_rtol = float(scene.get("study.reference_rtol"))
    t_ref, y_ref, w_ref, n_ref = _run(scene, ["numerics.integrator=LSODA",
                                             f"numerics.rtol={ref_rtol!r}",
                                             "numerics.atol=1.0e-14"], probe)
    shape = (len(integrators), rtols.size)
    ad = {k: np.full(shape, np.nan) for k in ("duration", "error", "state_error",
                                               "wall_time_s", "n_rhs")}
    for a, method in enumerate(integrators):
        for b, rtol in enumerate(rtols):
            t, y, w, n = _run(scene, [f"numerics.integrator={method}",
                                      f"numerics.rtol={float(rtol)!r}"], probe)
            ad["duration"][a, b], ad["error"][a, b] = t, abs(t - t_ref)
            ad["state_error"][a, b] = float(np.abs(y - y_ref).max())
            ad["wall_time_s"][a, b], ad["n_rhs"][a, b] = w, n
    hn = {k: np.full(dts.size, np.nan) for k in ("duration", "error", "state_error",
                                                   "wall_time_s", "n_rhs", "stable")}
    for c, dt in enumerate(dts):
        try:
            t, y, w, n = _run(scene, ["numerics.integrator=heun", f"numerics.dt={float(dt)!r}"],
                              probe)
        except SimulationDiverged:
            hn["stable"][c] = 0.0
            continue
        hn["stable"][c] = 1.0
        hn["duration"][c], hn["error"][c] = t, abs(t - t_ref)
        hn["state_error"][c] = float(np.abs(y - y_ref).max())
        hn["wall_time_s"][c], hn["n_rhs"][c] = w, n
    adims, hdims = ("integrator", "rtol"), ("dt",)
    ds = xr.Dataset(
        {**{f"adaptive_{k}": (adims, v) for k, v in ad.items()},
         **{f"heun_{k}": (hdims, v) for k, v in hn.items()}},
        coords={"integrator": integrators, "rtol": rtols, "dt": ("dt", dts, {"units": "tau"})})
    for name in ("adaptive_error", "heun_error"):  # durations, wall times: craquelure.cf
        ds[name].attrs.update({"units": "tau", "long_name": "|T - T_ref| (T1 duration error)"})
    for name in ("adaptive_state_error", "heun_state_error"):
        ds[name].attrs.update({"units": "R", "long_name": f"max |y - y_ref| at t = {probe} tau"})
    ds.attrs.update({"reference": f"LSODA rtol {ref_rtol:g} atol 1e-14 R",
                     "reference_duration": t_ref, "reference_wall_time_s": w_ref,
                     "reference_n_rhs": n_ref, "probe_time": probe,
                     "h0": scene.get("particles.h0"),
                     "reduced_force": scene.get("loads.reduced_force")})
    ds.attrs["heun_duration_order"], ds.attrs["heun_state_order"] = heun_order(ds)
    return ds


def heun_order(ds: xr.Dataset, n_finest: int = 3) -> tuple[float, float]:
    """Least-squares convergence orders of heun (duration, state) over the ``n_finest``
    smallest stable steps (the coarse ones are pre-asymptotic)."""
    ok = np.isfinite(ds.heun_error.values) & (ds.heun_error.values > 0)
    finest = np.argsort(ds.dt.values)[:n_finest]
    ok &= np.isin(np.arange(ok.size), finest)
    if ok.sum() < 2:
        return float("nan"), float("nan")
    ldt = np.log(ds.dt.values[ok])
    return (float(np.polyfit(ldt, np.log(ds.heun_error.values[ok]), 1)[0]),
            float(np.polyfit(ldt, np.log(ds.heun_state_error.values[ok]), 1)[0]))
