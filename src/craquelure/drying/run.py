"""``craquelure run`` for the drying paste: initial state -> engine -> run dataset, with
checkpoints and resume.

Run dataset: snapshots on dim ``time`` x ``particle``: ``x``, ``y`` (wrapped into the box),
``vx``, ``vy``, ``alive`` (removed particles keep their index with alive = 0), ``mass``, ``rho``,
``mean_stress`` (tr(sigma)/2 of the total stress); time series on dim ``step_time``:
``n_removed``, ``kinetic_energy``, ``elastic_energy``, ``momentum_x``, ``momentum_y``; attributes
``h``, ``box_length``, ``effects`` and the provenance of :mod:`craquelure.provenance`.

Checkpoints (``<out>.checkpoint.nc``, written atomically every ``checkpoint_every`` steps) hold
the full engine state, the integrator history and the output gathered so far; ``--resume``
continues from it to a bit-identical result, because the engine rebuilds its neighbour list at
every checkpoint in both runs.
"""

from __future__ import annotations

import hashlib
import os
import sys
from pathlib import Path

import numpy as np
import xarray as xr

from craquelure.drying.engine import NVAR, VX, VY, DryingEngine, X, Y
from craquelure.drying.initial_state import build_initial_state
from craquelure.errors import CraquelureError
from craquelure.io import open_dataset, write_dataset
from craquelure.progress import Progress
from craquelure.provenance import WallClock, provenance_attrs
from craquelure.scene import Scene

SNAPSHOT_VARS = {
    "x": ("position x (wrapped into the box)", "length"),
    "y": ("position y (wrapped into the box)", "length"),
    "vx": ("velocity x", "sqrt(lambda/rho0)"),
    "vy": ("velocity y", "sqrt(lambda/rho0)"),
    "alive": ("1 if the particle is present, 0 once removed by fracture", "1"),
    "mass": ("particle mass", "rho0 length^2"),
    "rho": ("density", "rho0"),
    "mean_stress": ("mean stress tr(sigma)/2 of the total stress", "lambda"),
}
SERIES_VARS = {
    "n_removed": ("particles removed so far", "1"),
    "kinetic_energy": ("kinetic energy sum m v^2 / 2", "lambda length^2"),
    "elastic_energy": ("elastic energy of sigma_e", "lambda length^2"),
    "momentum_x": ("total momentum x", "rho0 length^2 sqrt(lambda/rho0)"),
    "momentum_y": ("total momentum y", "rho0 length^2 sqrt(lambda/rho0)"),
    "time_step": ("size of the last time step", "eta/lambda"),
}


def output_times(scene: Scene) -> np.ndarray:
    t_end = float(scene.get("outputs.t_end"))
    times = scene.get("outputs.times", None)
    if times is None:
        return np.linspace(t_end / 10, t_end, 10)
    times = np.asarray(sorted(times), float)
    if times.size and times[-1] > t_end + 1e-12:
        raise CraquelureError(f"outputs.times: {times[-1]} is after outputs.t_end = {t_end}")
    return times


def engine_from_initial(scene: Scene, init: xr.Dataset) -> DryingEngine:
    stress = np.stack([init["sigma_e_xx"].values, init["sigma_e_yy"].values,
                       init["sigma_e_xy"].values])
    return DryingEngine(scene, init["x"].values, init["y"].values, init["mass"].values,
                        init["rho"].values, stress)


class Recorder:
    """Snapshots and time series gathered during a run."""

    def __init__(self, times: np.ndarray) -> None:
        self.times = times
        self.next_output = 0
        self.snapshots: dict[str, list[np.ndarray]] = {k: [] for k in SNAPSHOT_VARS}
        self.snapshot_times: list[float] = []
        self.series: dict[str, list[float]] = {k: [] for k in SERIES_VARS}
        self.series_times: list[float] = []

    def record_series(self, engine: DryingEngine) -> None:
        px, py = engine.momentum()
        self.series_times.append(engine.t)
        self.series["n_removed"].append(engine.n_removed)
        self.series["kinetic_energy"].append(engine.kinetic_energy())
        self.series["elastic_energy"].append(engine.elastic_energy())
        self.series["momentum_x"].append(px)
        self.series["momentum_y"].append(py)
        self.series["time_step"].append(engine.dt)

    def maybe_snapshot(self, engine: DryingEngine) -> None:
        while (self.next_output < self.times.size
               and engine.t >= self.times[self.next_output] - engine.time_tolerance()):
            length = engine.box_length
            s = engine.state
            values = {
                "x": np.mod(s[X], length), "y": np.mod(s[Y], length), "vx": s[VX].copy(),
                "vy": s[VY].copy(), "alive": engine.alive.astype(np.int8),
                "mass": engine.mass.copy(), "rho": s[4].copy(),
                "mean_stress": engine.mean_stress.copy(),
            }
            for key, value in values.items():
                self.snapshots[key].append(value)
            self.snapshot_times.append(engine.t)
            self.next_output += 1

    def next_stop(self, t_end: float) -> float:
        """The next output time (adaptive steps end exactly on it), else t_end."""
        return float(self.times[self.next_output]) if not self.done() else t_end

    def done(self) -> bool:
        return self.next_output >= self.times.size


def _dataset(engine: DryingEngine, rec: Recorder, finished: bool) -> xr.Dataset:
    data = {}
    for key, (long_name, units) in SNAPSHOT_VARS.items():
        arr = (np.stack(rec.snapshots[key]) if rec.snapshots[key]
               else np.zeros((0, engine.n), np.int8 if key == "alive" else float))
        data[key] = (("time", "particle"), arr, {"long_name": long_name, "units": units})
    for key, (long_name, units) in SERIES_VARS.items():
        data[key] = (("step_time",), np.asarray(rec.series[key], float),
                     {"long_name": long_name, "units": units})
    coords = {
        "time": ("time", np.asarray(rec.snapshot_times, float),
                 {"long_name": "snapshot time", "units": "eta/lambda"}),
        "step_time": ("step_time", np.asarray(rec.series_times, float),
                      {"long_name": "time-series sample time", "units": "eta/lambda"}),
    }
    return xr.Dataset(data, coords=coords, attrs={
        "h": engine.h, "box_length": engine.box_length, "n_particles": engine.n,
        "dt_final": engine.dt, "steps": engine.step_count,
        "rate_evaluations": engine.evaluations, "neighbour_builds": engine.neighbour_builds,
        "integrator": engine.stepper.name, "finished": int(finished),
        "rkc_stage_evaluations": engine.stage_evaluations,
        "spectral_radius_evaluations": engine.viscous_evaluations,
        "rejected_steps": engine.controller.rejected if engine.controller else 0,
    })


def _checkpoint_dataset(engine: DryingEngine, rec: Recorder, wall: float) -> xr.Dataset:
    ds = _dataset(engine, rec, finished=False)
    history, rk4_left = engine.stepper.state()
    ds["state"] = (("var", "particle"), engine.state)
    ds["x0"] = (("particle",), engine.x0)
    ds["y0"] = (("particle",), engine.y0)
    ds["mass_now"] = (("particle",), engine.mass)
    ds["alive_now"] = (("particle",), engine.alive.astype(np.int8))
    ds["history"] = (("history", "var", "particle"),
                     np.stack(history) if history else np.zeros((0, NVAR, engine.n)))
    ds.attrs.update(t=engine.t, step=engine.step_count, dt=engine.dt, rk4_left=rk4_left,
                    n_removed=engine.n_removed, evaluations=engine.evaluations,
                    next_output=rec.next_output, wall_time_so_far=wall)
    ds.attrs.update({f"step_control_{k}": v for k, v in engine.step_control_state().items()})
    return ds


def _restore(engine: DryingEngine, rec: Recorder, ck: xr.Dataset) -> float:
    engine.state = ck["state"].values.copy()
    engine.x0, engine.y0 = ck["x0"].values.copy(), ck["y0"].values.copy()
    engine.mass = ck["mass_now"].values.copy()
    engine.alive = ck["alive_now"].values.astype(np.bool_)
    engine.t, engine.step_count = float(ck.attrs["t"]), int(ck.attrs["step"])
    engine.dt, engine.n_removed = float(ck.attrs["dt"]), int(ck.attrs["n_removed"])
    engine.stepper.set_state(list(ck["history"].values), int(ck.attrs["rk4_left"]))
    prefix = "step_control_"
    engine.set_step_control_state({k[len(prefix):]: v for k, v in ck.attrs.items()
                                   if k.startswith(prefix)})
    rec.next_output = int(ck.attrs["next_output"])
    rec.snapshot_times = [float(t) for t in ck["time"].values]
    for key in SNAPSHOT_VARS:
        rec.snapshots[key] = list(ck[key].values)
    rec.series_times = [float(t) for t in ck["step_time"].values]
    for key in SERIES_VARS:
        rec.series[key] = [float(v) for v in ck[key].values]
    engine.rebuild()
    # counted after the rebuild, which the uninterrupted run also did before writing it
    engine.evaluations = int(ck.attrs["evaluations"])
    return float(ck.attrs["wall_time_so_far"])


def _fingerprint(scene: Scene, init: xr.Dataset) -> str:
    """Hash of the resolved scene and the initial state: a checkpoint is only resumed by the
    run it belongs to."""
    digest = hashlib.sha256(scene.text.encode())
    for key in ("x", "y", "mass", "sigma_e_xx", "sigma_e_yy", "sigma_e_xy"):
        digest.update(np.ascontiguousarray(init[key].values).tobytes())
    return digest.hexdigest()


def checkpoint_path(out: Path) -> Path:
    return out.with_name(out.name + ".checkpoint.nc")


def run(scene: Scene, out: Path, seed: int = 0, init: Path | None = None,
        resume: bool = False, stop_after_steps: int | None = None) -> Path:
    """Simulate ``scene`` and write the run dataset to ``out``.

    ``stop_after_steps`` ends the process early after writing a checkpoint (tests of resume).
    """
    clock = WallClock()
    out = Path(out)
    if init is not None:
        init_ds = open_dataset(init)
        seed = int(init_ds.attrs.get("seed", seed))
    else:
        init_ds = build_initial_state(scene, seed)
    engine = engine_from_initial(scene, init_ds)
    rec = Recorder(output_times(scene))
    ck_path = checkpoint_path(out)
    wall_before = 0.0
    fingerprint = _fingerprint(scene, init_ds)
    checkpoint = open_dataset(ck_path) if resume and ck_path.exists() else None
    if checkpoint is not None and checkpoint.attrs.get("fingerprint") != fingerprint:
        print(f"ignoring checkpoint {ck_path}: made from another scene or initial state",
              file=sys.stderr)
        checkpoint = None
    if checkpoint is not None:
        wall_before = _restore(engine, rec, checkpoint)
        print(f"resumed from {ck_path} at t = {engine.t:g} (step {engine.step_count})",
              file=sys.stderr)
    else:
        engine.control_time_step()
        rec.maybe_snapshot(engine)
        rec.record_series(engine)
    t_end = float(scene.get("outputs.t_end"))
    every = int(scene.get("outputs.series_every"))
    ck_every = int(scene.get("numerics.checkpoint_every"))
    spectral_every = int(scene.get("numerics.spectral_check_every"))
    progress = Progress(t_end, f"drying {scene.name} seed {seed}", initial=engine.t,
                        stream=sys.stderr)
    steps_this_process = 0
    while engine.t < t_end - engine.time_tolerance():
        engine.stop_at = rec.next_stop(t_end)
        engine.step()
        steps_this_process += 1
        engine.check_health()
        if engine.step_count % every == 0:
            rec.record_series(engine)
        rec.maybe_snapshot(engine)
        if engine.step_count % spectral_every == 0:
            engine.control_time_step()
        if engine.step_count % ck_every == 0:
            engine.rebuild()
            ck = _checkpoint_dataset(engine, rec, wall_before + clock.elapsed)
            ck.attrs["fingerprint"] = fingerprint
            write_dataset(ck, ck_path)
            if stop_after_steps is not None and steps_this_process >= stop_after_steps:
                progress.close()
                return ck_path
        progress.update_to(engine.t, f"removed {engine.n_removed}")
    progress.close()
    if engine.step_count % every != 0:
        rec.record_series(engine)
    ds = _dataset(engine, rec, finished=True)
    ds.attrs.update(provenance_attrs(scene, seed, clock, extra_wall_time=wall_before))
    write_dataset(ds, out)
    if ck_path.exists():
        os.unlink(ck_path)
    return out
