"""Model API of the drying paste for the CLI: initial state, derived numbers and the run
(``craquelure run``: initial state -> engine -> run dataset, with checkpoints and resume).

Run dataset: the snapshots of :data:`SNAPSHOT_VARS` on dims ``time`` x ``particle`` (removed
particles keep their index with alive = 0), the time series of :data:`SERIES_VARS` on dim
``step_time`` (the onset diagnostics: :mod:`craquelure.drying.engine`), the run's numbers and
the provenance of :mod:`craquelure.provenance` as attributes.

The loop, checkpoints and ``--resume`` are the runner's (:mod:`craquelure.runner`);
:class:`DryingRun` gives it all that evolves (:meth:`DryingRun.parts`): a resumed run is
bit-identical."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import xarray as xr

from craquelure import runner
from craquelure.drying.engine import RHO, VX, VY, DryingEngine, X, Y
from craquelure.drying.initial_state import build_initial_state
from craquelure.drying.integrators import REAL_AXIS_LIMIT, RKC_SPECTRAL_SAFETY, rkc_stages
from craquelure.drying.rules import (
    SNAPSHOTS_WITHOUT_TIMES,
    initial_state_problems,
    run_step,
    viscous_spectral_radius,
)
from craquelure.errors import CraquelureError, SceneError
from craquelure.io import read_dataset
from craquelure.provenance import WallClock
from craquelure.scene import Scene
from craquelure.throughput import prediction_lines

EVALS_PER_STEP = {"rk4": 4, "abm4": 2, "rk2": 2}

__all__ = ["build_initial_state", "derived_numbers", "run", "workload"]


def evaluations_per_step(scene: Scene, dt: float) -> int:
    """Rate evaluations per step: fixed for abm4/rk4/rk2; rkc2's stage count at step dt
    (between removal events its controlled step sits at step_control.dt_max)."""
    integrator = scene.get("numerics.integrator")
    if integrator == "rkc2":
        return rkc_stages(dt, RKC_SPECTRAL_SAFETY * viscous_spectral_radius(scene))
    return EVALS_PER_STEP[integrator]


def stable_time_step(scene: Scene) -> float:
    """Largest stable step of the scene's integrator, from the viscous and acoustic limits
    (rkc2: its stages cover the viscous spectrum, so the cap ``step_control.dt_max``)."""
    radius = viscous_spectral_radius(scene)
    integrator = scene.get("numerics.integrator")
    if integrator == "rkc2":
        return float(scene.get("numerics.step_control")["dt_max"])
    limits = [REAL_AXIS_LIMIT[integrator] / radius] if radius > 0 else []
    if scene.has("elasticity"):
        lam, mu = scene.get("material.lame_lambda"), scene.get("material.lame_mu")
        c_l = math.sqrt((lam + 2 * mu) / scene.get("material.rho0"))
        # Largest SPH wavenumber of this kernel ~ 3.2/h (16 at h = 0.2, spec section 8).
        limits.append(2.785 / (c_l * 3.2 / scene.get("numerics.h")))
    return min(limits) if limits else math.inf


def derived_numbers(scene: Scene) -> dict[str, object]:
    length, n, h = (scene.get("domain.box_length"), scene.get("particles.n"),
                    scene.get("numerics.h"))
    dt, steps, evals = _run_steps(scene)
    return {
        "particle spacing L/sqrt(N)": length / math.sqrt(n),
        "h / spacing": h / (length / math.sqrt(n)),
        "neighbours per particle": n * math.pi * h * h / length**2 - 1,
        "viscous spectral radius": viscous_spectral_radius(scene),
        "stable time step": stable_time_step(scene),
        "time step (numerics.dt)": scene.get("numerics.dt"),
        "time step of the run (halved below 0.6 of the viscous limit)": dt,
        "steps": steps, "rate evaluations": steps * evals,
        **prediction_lines("drying", workload(scene)),
    }


def _run_steps(scene: Scene) -> tuple[float, int, int]:
    """The run's step (numerics.adapt_dt halves it), step count and evaluations per step."""
    dt = run_step(scene.data)
    return dt, math.ceil(scene.get("outputs.t_end") / dt), evaluations_per_step(scene, dt)


def workload(scene: Scene) -> dict[str, float]:
    """Rate evaluations, particles and listed neighbours (Verlet radius 1.1 h: 1.21x the
    pairs within h) of a run, for the throughput model."""
    length, n, h = (scene.get("domain.box_length"), scene.get("particles.n"),
                    scene.get("numerics.h"))
    _, steps, evals = _run_steps(scene)
    return {"units": steps * evals, "particles": n,
            "neighbours": 1.21 * (n * math.pi * h * h / length**2 - 1)}


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
    "kappa_max": ("max_I sigma_bar_I / F before the first removal, from F >= 20 a sigma_Y "
                  "(NaN otherwise)", "1"),
    "kappa_criterion_max": ("max_I s_I / F of the fracture criterion's stress s, before the "
                            "first removal, from F >= 20 a sigma_Y (NaN otherwise)", "1"),
}


INITIAL_STATE_VARS = ("x", "y", "mass", "rho", "sigma_e_xx", "sigma_e_yy", "sigma_e_xy")


def output_times(scene: Scene) -> np.ndarray:
    t_end = float(scene.get("outputs.t_end"))
    times = scene.optional("outputs.times")
    if times is None:  # equally spaced up to t_end
        return np.linspace(t_end / SNAPSHOTS_WITHOUT_TIMES, t_end, SNAPSHOTS_WITHOUT_TIMES)
    times = np.asarray(sorted(times), float)
    if times.size and times[-1] > t_end + 1e-12:
        raise CraquelureError(f"outputs.times: {times[-1]} is after outputs.t_end = {t_end}")
    return times


def engine_from_initial(scene: Scene, init: xr.Dataset) -> DryingEngine:
    stress = np.stack([init[f"sigma_e_{c}"].values for c in ("xx", "yy", "xy")])
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
        values = (engine.n_removed, engine.kinetic_energy(), engine.elastic_energy(),
                  *engine.momentum(), engine.dt, *engine.onset_kappa())  # SERIES_VARS' order
        self.series_times.append(engine.t)
        for key, value in zip(SERIES_VARS, values, strict=True):
            self.series[key].append(value)

    def maybe_snapshot(self, engine: DryingEngine) -> None:
        while (self.next_output < self.times.size
               and engine.t >= self.times[self.next_output] - engine.time_tolerance()):
            s, length = engine.state, engine.box_length
            values = (np.mod(s[X], length), np.mod(s[Y], length), s[VX].copy(), s[VY].copy(),
                      engine.alive.astype(np.int8), engine.mass.copy(), s[RHO].copy(),
                      engine.mean_stress.copy())  # SNAPSHOT_VARS' order
            for key, value in zip(SNAPSHOT_VARS, values, strict=True):
                self.snapshots[key].append(value)
            self.snapshot_times.append(engine.t)
            self.next_output += 1

    def next_stop(self, t_end: float) -> float:
        """The next output time (adaptive steps end exactly on it), else t_end."""
        return float(self.times[self.next_output]) if self.next_output < self.times.size \
            else t_end


def _dataset(engine: DryingEngine, rec: Recorder, finished: bool) -> xr.Dataset:
    data = {}
    for key, (long_name, units) in SNAPSHOT_VARS.items():
        arr = (np.stack(rec.snapshots[key]) if rec.snapshots[key]
               else np.zeros((0, engine.n), np.int8 if key == "alive" else float))
        data[key] = (("time", "particle"), arr, {"long_name": long_name, "units": units})
    for key, (long_name, units) in SERIES_VARS.items():
        data[key] = (("step_time",), np.asarray(rec.series[key], float),
                     {"long_name": long_name, "units": units})
    coords = {"time": np.asarray(rec.snapshot_times, float),  # long names, units: craquelure.cf
              "step_time": np.asarray(rec.series_times, float)}
    return xr.Dataset(data, coords=coords, attrs={
        "h": engine.h, "box_length": engine.box_length, "n_particles": engine.n,
        "dt_final": engine.dt, "steps": engine.step_count,
        "rate_evaluations": engine.evaluations, "neighbour_builds": engine.neighbour_builds,
        "integrator": engine.stepper.name, "finished": int(finished),
        "rkc_stage_evaluations": engine.stage_evaluations,
        "spectral_radius_evaluations": engine.viscous_evaluations,
        "rejected_steps": engine.controller.rejected if engine.controller else 0,
        "fracture_stress_measure": engine.fracture_measure,
        "kappa_min_drying_stress": engine.kappa_min_f,
    })


class DryingRun(runner.EngineRun):
    """The drying engine and its recorder as the runner sees them (:mod:`craquelure.runner`).

    One advance is one step. After it, in this order: the series every
    ``outputs.series_every`` steps, the snapshots due, the time-step control every
    ``numerics.spectral_check_every`` steps and a fresh neighbour list every
    ``numerics.checkpoint_every`` steps (a fixed schedule of the trajectory, so a checkpoint
    written at any step, which holds the neighbour list, does not change it)."""

    def __init__(self, scene: Scene, engine: DryingEngine, rec: Recorder) -> None:
        self.engine, self.rec = engine, rec
        self.t_end = float(scene.get("outputs.t_end"))
        self.series_every = int(scene.get("outputs.series_every"))
        self.rebuild_every = int(scene.get("numerics.checkpoint_every"))
        self.spectral_every = int(scene.get("numerics.spectral_check_every"))
        self.n_particles = engine.n

    def start(self) -> None:
        self.engine.control_time_step()
        self.rec.maybe_snapshot(self.engine)
        self.rec.record_series(self.engine)

    def done(self) -> bool:
        return self.engine.t >= self.t_end - self.engine.time_tolerance()

    def advance(self) -> None:
        self.engine.stop_at = self.rec.next_stop(self.t_end)
        self.engine.step()

    def divergence(self):
        return self.engine.health()

    def sample(self) -> None:
        engine, step = self.engine, self.engine.step_count
        if step % self.series_every == 0:
            self.rec.record_series(engine)
        self.rec.maybe_snapshot(engine)
        if step % self.spectral_every == 0:
            engine.control_time_step()
        if step % self.rebuild_every == 0:
            engine.rebuild()

    def finish(self) -> None:
        if self.engine.step_count % self.series_every != 0:
            self.rec.record_series(self.engine)

    def parts(self) -> dict[str, object]:
        """What evolves, by checkpoint prefix: the engine's arrays and numbers (with the
        neighbour list and the current rate, so that resuming needs no rebuild), the
        integrator's history, the step control's memory and the recorder's outputs."""
        engine = self.engine
        return {"engine_": engine, "stepper_": engine.stepper, "rec_": self.rec,
                **({"control_": engine.controller} if engine.controller else {})}


def run(scene: Scene, out: Path, seed: int = 0, init: Path | None = None, **checkpoints) -> Path:
    """Simulate ``scene`` and write the run dataset to ``out`` (through the runner;
    ``checkpoints``: the options of :func:`craquelure.runner.run_to_file`; checkpoints every
    ``numerics.checkpoint_every`` steps unless ``checkpoint_every`` is given)."""
    clock = WallClock()
    if init is not None:
        init_ds = read_dataset(init, "drying initial state", model="drying",
                               variables=INITIAL_STATE_VARS)
        problems = initial_state_problems(scene, init_ds, init)
        if problems:
            raise SceneError("--init does not match the scene:\n  " + "\n  ".join(problems))
        seed = int(init_ds.attrs.get("seed", seed))
    else:
        init_ds = build_initial_state(scene, seed)
    model = DryingRun(scene, engine_from_initial(scene, init_ds), Recorder(output_times(scene)))
    # the initial state's bytes: a checkpoint is only resumed by the run it belongs to
    fingerprint = b"".join(np.ascontiguousarray(init_ds[key].values).tobytes()
                           for key in ("x", "y", "mass", "sigma_e_xx", "sigma_e_yy", "sigma_e_xy"))
    return runner.run_to_file(
        model, scene, seed, out, lambda: _dataset(model.engine, model.rec, finished=True), clock,
        t_end=model.t_end, desc=f"drying {scene.name} seed {seed}", time_unit="eta/lambda",
        default_every=model.rebuild_every, extra_fingerprint=fingerprint, **checkpoints)
