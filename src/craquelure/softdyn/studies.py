"""Studies made of many T1 runs: the duration sweep over (h0, F~) (paper Fig. 5) and the
occurrence of the T1 in the (F_h, F_v) plane (Fig. 3).

Sweep: grid ``study.h0`` x ``study.reduced_force``; only points with h0/h* inside
``study.window`` are run (the informative window of spec 9.2; outside it a run is either pure
Poiseuille or hopelessly long), the others are NaN with ``computed = 0``; a point that does not
finish by ``outputs.t_end`` has ``finished = 0`` and a NaN duration. The workflow runs the
points in batches of similar estimated cost (:func:`sweep_batches`): a process start costs more
than most points. Phase: grid ``study.fh_over_fv`` x ``study.reduced_force``, each run until
theta <= ``outputs.theta_end_deg`` or ``outputs.t_end``.
"""

import math

import numpy as np
import xarray as xr

from craquelure.errors import SceneError
from craquelure.softdyn import theory
from craquelure.softdyn.engine import run
from craquelure.softdyn.initial_state import SQRT3, build, material_constants, t1_angle


def sweep_grid(scene) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(h0 values, force values, mask[h0, force] of points inside the window)."""
    h0 = np.asarray(scene.get("study.h0"), dtype=float)
    force = np.asarray(scene.get("study.reduced_force"), dtype=float)
    if h0.size == 0 or force.size == 0:
        raise SceneError("study.h0 and study.reduced_force: a sweep needs both lists")
    lo, hi = scene.get("study.window")
    k_n = material_constants(scene)["k_n"]
    ratio = h0[:, None] / np.array([theory.h_star(f, k_n) for f in force])[None, :]
    return h0, force, (ratio >= lo * (1 - 1e-9)) & (ratio <= hi * (1 + 1e-9))


def sweep_points(scene) -> list[tuple[int, int]]:
    h0, force, mask = sweep_grid(scene)
    return [(i, j) for i in range(h0.size) for j in range(force.size) if mask[i, j]]


def point_scene(scene, h0: float, force: float, extra: tuple[str, ...] = ()):
    return scene.with_overrides([f"particles.h0={h0!r}", f"loads.reduced_force={force!r}",
                                 "outputs.run_past_stop=false", *extra])


def run_sweep_point(scene, i: int, j: int) -> xr.Dataset:
    """One T1 of the sweep, as a dataset with length-1 dims h0 and force."""
    h0, force, mask = sweep_grid(scene)
    if not mask[i, j]:
        raise SceneError(f"sweep point ({i}, {j}) = (h0 {h0[i]:g}, F~ {force[j]:g}) is outside "
                         f"study.window")
    sc = point_scene(scene, float(h0[i]), float(force[j]))
    setup = build(sc)
    res = run(setup, sample_times_tau=np.array([]), desc=f"T1 h0={h0[i]:g} F~={force[j]:g}")
    k_n, c_n = sc.get("material.k_n"), sc.get("material.c_n")
    x = setup.system.unpack(res.y_stop)[0]
    values = {
        "duration": res.t_stop / setup.tau if res.stopped else math.nan,
        "finished": int(res.stopped), "theta_end": math.degrees(t1_angle(x)),
        "T_P": theory.t_poiseuille(h0[i], c_n), "T_H": theory.t_hertz(h0[i], force[j], k_n, c_n),
        "T_sep": theory.t_separation(h0[i], force[j], k_n, c_n),
        "h0_over_h_star": h0[i] / theory.h_star(force[j], k_n),
        "n_rhs": res.n_rhs, "n_steps": res.n_steps, "run_wall_time_s": res.wall_time_s}
    ds = xr.Dataset({k: (("h0", "force"), [[v]]) for k, v in values.items()},
                    coords={"h0": [h0[i]], "force": [force[j]]})
    ds["regime"] = (("h0", "force"), [[theory.regime(h0[i], force[j], k_n)]])
    return ds


def point_cost(scene, i: int, j: int) -> float:
    """Relative cost estimate of a sweep point, for balancing the batches: the predicted
    duration (the AB opening quadrature plus T_P, units of tau) times the stiffness of the far
    CD pair (steps scale like 1/F~, spec section 8), in log form so that no point dominates."""
    h0, force, _ = sweep_grid(scene)
    k_n, c_n = scene.get("material.k_n"), scene.get("material.c_n")
    t_pred = theory.t_separation(h0[i], force[j], k_n, c_n) + theory.t_poiseuille(h0[i], c_n)
    return math.log(1.0 + t_pred) * (1.0 + math.log10(1.0 / force[j]))


def sweep_batches(scene, n_batches: int) -> list[list[tuple[int, int]]]:
    """The window's points split into at most ``n_batches`` non-empty batches of similar
    estimated cost (longest-processing-time-first greedy; deterministic)."""
    points = sweep_points(scene)
    n = max(1, min(int(n_batches), len(points)))
    order = sorted(points, key=lambda ij: (-point_cost(scene, *ij), ij))
    loads = [0.0] * n
    batches: list[list[tuple[int, int]]] = [[] for _ in range(n)]
    for ij in order:
        k = min(range(n), key=lambda b: (loads[b], b))
        batches[k].append(ij)
        loads[k] += point_cost(scene, *ij)
    return [sorted(b) for b in batches]


def batch_dataset(points: list[xr.Dataset]) -> xr.Dataset:
    """Sweep point datasets stacked along ``point`` (the layout of a batch file; no points:
    an empty batch)."""
    if not points:
        return xr.Dataset(coords={"point": ("point", np.zeros(0, np.int64))})
    return xr.concat([p.squeeze(("h0", "force")).reset_coords(("h0", "force")) for p in points],
                     dim="point")


def aggregate_sweep(scene, points: list[xr.Dataset]) -> xr.Dataset:
    """Sweep dataset with named dims (h0, force) from the point datasets (long names and units
    from :mod:`craquelure.cf`'s table on writing)."""
    h0, force, mask = sweep_grid(scene)
    k_n, c_n = scene.get("material.k_n"), scene.get("material.c_n")
    hs = np.array([theory.h_star(f, k_n) for f in force])
    shape = (h0.size, force.size)
    ds = xr.Dataset(coords={"h0": h0, "force": force})
    ds["h_star"] = ("force", hs)
    numeric = ["duration", "finished", "theta_end", "T_sep", "n_rhs", "n_steps", "run_wall_time_s"]
    for name in numeric:
        ds[name] = (("h0", "force"), np.full(shape, np.nan))
    ds["computed"] = (("h0", "force"), mask.astype(np.int8))
    ds["T_P"] = (("h0", "force"), np.array([[theory.t_poiseuille(h, c_n) for _ in force]
                                            for h in h0]))
    ds["T_H"] = (("h0", "force"), np.array([[theory.t_hertz(h, f, k_n, c_n) for f in force]
                                            for h in h0]))
    ds["h0_over_h_star"] = (("h0", "force"), h0[:, None] / hs[None, :])
    ds["regime"] = (("h0", "force"), np.array([[theory.regime(h, f, k_n) for f in force]
                                               for h in h0], dtype=object))
    for point in _single_points(points):
        i = int(np.argmin(np.abs(np.log(h0 / _scalar(point.h0)))))
        j = int(np.argmin(np.abs(np.log(force / _scalar(point.force)))))
        for name in numeric:
            ds[name].values[i, j] = _scalar(point[name])
    missing = [(float(h0[i]), float(force[j])) for i, j in zip(*np.nonzero(mask), strict=True)
               if np.isnan(ds["finished"].values[i, j])]
    if missing:
        raise SceneError(f"sweep aggregate: no result for the grid points {missing}")
    ds.attrs.update({"n_points": int(mask.sum()),
                     "n_finished": int(np.nansum(ds["finished"].values)),
                     "window_lo": scene.get("study.window")[0],
                     "window_hi": scene.get("study.window")[1]})
    return ds


def _scalar(var) -> float:
    return float(np.asarray(var.values).reshape(-1)[0])


def _single_points(datasets):
    """Point datasets from point (length-1 h0, force) or batch (``point`` dim) datasets."""
    for ds in datasets:
        if "point" in ds.dims:
            for k in range(ds.sizes["point"]):
                yield ds.isel(point=k)
        else:
            yield ds


def phase_points(scene) -> list[tuple[float, float]]:
    """The (F_h/F_v, F~) grid of a phase scan, row by row."""
    ratios = np.asarray(scene.get("study.fh_over_fv"), dtype=float)
    force = np.asarray(scene.get("study.reduced_force"), dtype=float)
    if ratios.size == 0 or force.size == 0:
        raise SceneError("study.fh_over_fv and study.reduced_force: a phase scan needs both")
    return [(float(r), float(f)) for r in ratios for f in force]


PHASE_VALUES = ("occurred", "time", "theta_end", "f_ab_end", "f_v", "f_h", "tau", "n_rhs")


def phase_point(scene, r: float, f: float) -> xr.Dataset:
    """One point of the phase scan (scalars named as in :data:`PHASE_VALUES`)."""
    sc = point_scene(scene, scene.get("particles.h0"), float(f),
                     (f"loads.fh_over_fv={float(r)!r}", "outputs.stop=angle"))
    setup = build(sc)
    res = run(setup, sample_times_tau=np.array([]), desc=f"phase r={r:g} F~={f:g}")
    ev = setup.system.evaluate(res.t_stop, res.y_stop)
    young_r2 = setup.system.young * setup.system.radius**2
    return xr.Dataset({
        "occurred": float(res.stopped), "time": res.t_stop / setup.tau,
        "theta_end": math.degrees(t1_angle(ev["x"])), "f_ab_end": ev["f_n"][0] / setup.f_v,
        "f_v": setup.f_v / young_r2, "f_h": setup.f_h / young_r2, "tau": setup.tau,
        "n_rhs": float(res.n_rhs)})


def phase_dataset(scene, points: list[xr.Dataset]) -> xr.Dataset:
    """The phase scan's dataset from its points (in the order of :func:`phase_points`)."""
    ratios = np.asarray(scene.get("study.fh_over_fv"), dtype=float)
    force = np.asarray(scene.get("study.reduced_force"), dtype=float)
    shape = (ratios.size, force.size)
    out = {k: np.array([float(p[k]) for p in points]).reshape(shape) for k in PHASE_VALUES}
    dims = ("fh_over_fv", "force")
    ds = xr.Dataset({k: (dims, v) for k, v in out.items()},
                    coords={"fh_over_fv": ratios, "force": force})
    ds["predicted"] = (dims, np.repeat((ratios < 1 / SQRT3)[:, None], force.size, 1)
                       .astype(float))
    ds["time"].attrs["units"] = "tau (AB load)"  # the rest: craquelure.cf's table on writing
    ds.attrs.update({"theta_end_deg": scene.get("outputs.theta_end_deg"),
                     "t_end": scene.get("outputs.t_end"), "h0": scene.get("particles.h0")})
    return ds
