"""Model API of Soft Dynamics for the CLI: initial state, derived numbers, runs.

``run`` dispatches on ``study.kind``: ``single`` (the time series of one T1 or two-sphere run),
``sweep`` (the duration map over (h0, F~)), ``phase`` (T1 occurrence over (F_h/F_v, F~)) and
``accuracy`` (:mod:`craquelure.softdyn.accuracy`). Nothing is random: the seed is only recorded.
"""

import math
from functools import partial
from pathlib import Path

import numpy as np
import xarray as xr

from craquelure import runner
from craquelure.errors import CraquelureError
from craquelure.provenance import WallClock
from craquelure.scene import Scene
from craquelure.softdyn import engine, studies, theory
from craquelure.softdyn.accuracy import run_accuracy
from craquelure.softdyn.initial_state import build, material_constants, predictions, series_dataset
from craquelure.throughput import prediction_lines


def build_initial_state(scene: Scene, seed: int) -> xr.Dataset:
    setup = build(scene)
    sysm = setup.system
    ds = xr.Dataset(
        {"position": (("particle", "dim"), sysm.x0 / sysm.radius, {"units": "R"}),
         "load": (("particle", "dim"), sysm.F0 / setup.f_v, {"units": "F_v"}),
         "pair_i": ("pair", sysm.pi), "pair_j": ("pair", sysm.pj)},
        coords={"particle": list(sysm.particle_names), "pair": list(sysm.pair_names),
                "dim": list("xyz"[: sysm.d])})
    ds.attrs.update({"tau": setup.tau, "F_v": setup.f_v, "F_h": setup.f_h})
    return ds


def derived_numbers(scene: Scene) -> dict[str, object]:
    setup = build(scene)
    pred = predictions(scene)
    ft = scene.get("loads.reduced_force")
    k_n, c_n = material_constants(scene)["k_n"], scene.get("material.c_n")
    # Fastest relaxation: the far CD pair (h ~ 1.46 R) relaxes at (k_n/c_n)(h/a)^3/F~ per tau.
    far_gap = math.sqrt(3.0) * (2.0 + scene.get("particles.h0")) - 2.0 \
        if scene.get("particles.arrangement") == "t1" else scene.get("particles.h0")
    rate = (k_n / c_n) * (far_gap / math.sqrt(far_gap)) ** 3 / ft
    young_r2 = setup.system.young * setup.system.radius**2
    out: dict[str, object] = {
        "Stokes time tau = eta R^2/F": setup.tau, "F_v [E R^2]": setup.f_v / young_r2,
        "F_h [E R^2]": setup.f_h / young_r2, "crossover gap h* [R]": pred["h_star"],
        "h0/h*": pred["h0_over_h_star"], "regime": pred["regime"],
        "T_P [tau] (Eq. 33)": pred["T_P"], "T_H [tau] (Eq. 34)": pred["T_H"],
        "T_sep [tau] (quadrature)": pred["T_sep"], "fastest pair relaxation rate [1/tau]": rate,
        "explicit (heun) step limit ~2/rate [tau]": 2.0 / rate,
        "state size": setup.system.state_size, "linear solver": setup.system.solver}
    if scene.get("study.kind") == "sweep":
        out["sweep points in window"] = len(studies.sweep_points(scene))
    out.update(prediction_lines("softdyn", workload(scene)))
    return out


def _integration_cost(scene: Scene, h0: float, force: float) -> float:
    """Relative cost of one integration (the measure the sweep balances its batches by):
    log(1 + T) (1 + log10(1/F~)), T the simulated time in tau (the predicted T1 duration,
    or t_end when the run goes on past the stop or the stop is not the T1's)."""
    t_end = scene.get("outputs.t_end")
    k_n, c_n = material_constants(scene)["k_n"], scene.get("material.c_n")
    t = t_end
    if scene.get("particles.arrangement") == "t1" and not scene.get("outputs.run_past_stop"):
        t = min(t_end, theory.t_separation(h0, force, k_n, c_n) + theory.t_poiseuille(h0, c_n))
    return math.log(1.0 + t) * (1.0 + math.log10(1.0 / force))


def workload(scene: Scene) -> dict[str, float]:
    """Integrations of a run weighted by :func:`_integration_cost` (the throughput model's
    unit), spheres and pair partners per sphere."""
    setup = build(scene)
    kind = scene.get("study.kind")
    h0, force = scene.get("particles.h0"), scene.get("loads.reduced_force")
    if kind == "sweep":
        hs, fs, _ = studies.sweep_grid(scene)
        units = sum(_integration_cost(scene, hs[i], fs[j]) for i, j in studies.sweep_points(scene))
    elif kind == "phase":
        units = sum(_integration_cost(scene, h0, float(f)) * len(scene.get("study.fh_over_fv"))
                    for f in scene.get("study.reduced_force"))
    elif kind == "accuracy":
        runs = 1 + len(scene.get("study.integrators")) * len(
            scene.get("study.rtol")) + len(scene.get("study.dt"))
        units = runs * _integration_cost(scene, h0, force)
    else:
        units = _integration_cost(scene, h0, force)
    sysm = setup.system
    return {"units": units, "particles": sysm.n, "neighbours": 2.0 * sysm.n_pairs / sysm.n}


class StudyRun(runner.EngineRun):
    """A Soft Dynamics study as the runner sees it: one advance runs one point (a sweep or
    phase grid point; a single run or the accuracy study is one point), so a checkpoint holds
    the finished points. Within a point the integrator's guards run after every step."""

    def __init__(self, points: list, combine) -> None:
        self.points, self.combine = points, combine
        self.results: list[xr.Dataset] = []
        self.n_particles = 1

    @property
    def time(self) -> float:
        return float(len(self.results))

    @property
    def steps(self) -> int:
        return len(self.results)

    def done(self) -> bool:
        return len(self.results) >= len(self.points)

    def advance(self) -> None:
        self.results.append(self.points[len(self.results)]())

    def state(self) -> dict[str, np.ndarray]:
        # each finished point as its netCDF bytes: exact, and any layout
        return {f"point_{k}": runner.dataset_bytes(ds) for k, ds in enumerate(self.results)}

    def restore(self, state: dict[str, np.ndarray]) -> None:
        self.results = [runner.dataset_from_bytes(state[f"point_{k}"]) for k in range(len(state))]

    def result(self) -> xr.Dataset:
        return self.combine(self.results)


def study(scene: Scene, batch: list[tuple[int, int]] | None = None) -> StudyRun:
    """The scene's study as runner points; with ``batch``, those sweep points only (one
    workflow job's batch file)."""
    kind = scene.get("study.kind")
    if batch is not None:
        return StudyRun([partial(studies.run_sweep_point, scene, i, j) for i, j in batch],
                        studies.batch_dataset)
    if kind == "single":
        def single():
            setup = build(scene)
            return series_dataset(setup, engine.run(setup, desc=scene.name))
        return StudyRun([single], lambda results: results[0])
    if kind == "sweep":
        return StudyRun([partial(studies.run_sweep_point, scene, i, j)
                         for i, j in studies.sweep_points(scene)],
                        partial(studies.aggregate_sweep, scene))
    if kind == "accuracy":
        return StudyRun([partial(run_accuracy, scene)], lambda results: results[0])
    return StudyRun([partial(studies.phase_point, scene, r, f)
                     for r, f in studies.phase_points(scene)],
                    partial(studies.phase_dataset, scene))


def run(scene: Scene, out: Path, seed: int | None = 0, init: Path | None = None,
        batch: list[tuple[int, int]] | None = None, attrs: dict | None = None,
        **checkpoints) -> Path:
    """Run the scene's study (or one sweep ``batch``) through
    :func:`craquelure.runner.run_to_file`. ``seed`` is only recorded (``None``: not at all);
    ``attrs`` are added to the dataset."""
    if init is not None:
        raise CraquelureError("softdyn runs start from the scene's arrangement; --init is not "
                              "used")
    clock = WallClock()
    model = study(scene, batch)
    return runner.run_to_file(
        model, scene, seed, out, lambda: model.result().assign_attrs(attrs or {}), clock,
        t_end=len(model.points), desc=f"softdyn {scene.name}", time_unit="points",
        **checkpoints)
