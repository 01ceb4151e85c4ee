"""Model API of the beam lattice for the CLI: initial state, derived numbers and the run.

Run dataset: dimension ``sample`` (energy series every ``numerics.series_every`` steps: the
columns of ``SERIES``), ``frame`` (snapshots x, y, theta at ``outputs.frames`` equally spaced
times, the first at t = 0), ``particle`` (mass, body, row, col) and ``bond`` (end indices,
final state 1 intact / 0 broken / 2 removed, break time, unbreakable); attributes: derived
constants (dt, k_n, k_s, E, nu, P-wave modulus, rho_2) and provenance. A checkpoint of the
runner (:mod:`craquelure.runner`) holds :meth:`Engine.state` and the frames so far.
"""

import math
from pathlib import Path

import numpy as np
import xarray as xr

from craquelure import runner
from craquelure.errors import CraquelureError
from craquelure.lattice import beam
from craquelure.lattice.engine import PARALLEL_MIN_BONDS, Engine
from craquelure.lattice.initial_state import (
    beam_constants,
    build_system,
    engine_params,
    make_engine,
)
from craquelure.provenance import WallClock
from craquelure.scene import Scene
from craquelure.throughput import prediction_lines


def build_initial_state(scene: Scene, seed: int) -> xr.Dataset:
    s, labels = build_system(scene, seed)
    return xr.Dataset({"x": ("particle", s.x), "y": ("particle", s.y),
                       "body": ("particle", labels["body"]), "row": ("particle", labels["row"]),
                       "bond_i": ("bond", s.bi), "bond_j": ("bond", s.bj),
                       "bond_state": ("bond", s.state)})


def derived_numbers(scene: Scene) -> dict[str, object]:
    s, _ = build_system(scene, 0)
    c = beam_constants(scene)
    m = beam.lattice_moduli(c.kn, c.ks)
    p = engine_params(scene, s)
    rho2 = float(s.mass[0] / beam.cell_area(s.L))
    load = workload(scene)
    return {
        "particles": s.n, "bonds": int(s.bi.size), "k_n": c.kn, "k_s": c.ks,
        "E_b": c.E_b, "beam width": c.width, "lattice E": m["E"], "lattice nu": m["nu"],
        "P-wave speed": math.sqrt(m["M"] / rho2), "time step": p["dt"], "steps": load["units"],
        **prediction_lines("lattice", load),
    }


def workload(scene: Scene) -> dict[str, float]:
    """Steps, particles, bonds per particle (2 x bonds / N) and effects of a run; serial below
    the engine's parallel threshold (the serial kernel runs whatever the thread count)."""
    s, _ = build_system(scene, 0)
    steps = math.ceil(scene.get("outputs.t_end") / engine_params(scene, s)["dt"])
    return {"units": steps, "particles": s.n, "neighbours": 2.0 * s.bi.size / s.n,
            "effects": tuple(scene.effects), "serial": s.bi.size < PARALLEL_MIN_BONDS}


def frame_marks(scene: Scene, dt: float) -> np.ndarray:
    n_steps = int(np.ceil(scene.get("outputs.t_end") / dt))
    return np.unique(np.linspace(0, n_steps, scene.get("outputs.frames") + 1).round().astype(int))


class LatticeRun(runner.EngineRun):
    """The lattice engine as the runner sees it (:mod:`craquelure.runner`): one advance runs
    to the next frame mark and records the frame. The contact list is rebuilt every
    ``numerics.checkpoint_every`` frames (decision [D]: a fixed schedule of the trajectory;
    the checkpoints themselves hold the contact list and change nothing)."""

    TIME, STEPS = "time", "step"

    def __init__(self, scene: Scene, engine: Engine) -> None:
        self.engine = engine
        self.t_end = float(scene.get("outputs.t_end"))
        self.marks = frame_marks(scene, engine.dt)
        self.rebuild_every = int(scene.get("numerics.checkpoint_every"))
        self.frames: dict[str, list] = {"time": [], "x": [], "y": [], "theta": []}
        self.n_particles = engine.system.n
        self._bad = None

    def start(self) -> None:
        self._record()  # the frame at t = 0 (mark 0)

    def done(self) -> bool:
        return len(self.frames["time"]) >= len(self.marks)

    def advance(self) -> None:
        mark = self.marks[len(self.frames["time"])]
        if mark > self.engine.step:
            self._bad = self.engine.advance(mark - self.engine.step)

    def divergence(self):
        return self._bad

    def sample(self) -> None:
        self._record()
        k = len(self.frames["time"]) - 1
        if (self.rebuild_every and 0 < k < len(self.marks) - 1 and k % self.rebuild_every == 0
                and self.engine.flags["CONTACT"]):
            self.engine.rebuild_contacts()

    def _record(self) -> None:
        self.frames["time"].append(self.engine.time)
        for a, name in enumerate(("x", "y", "theta")):
            self.frames[name].append(self.engine.q[a].copy())

    def state(self) -> dict[str, np.ndarray]:
        return {**{f"engine_{k}": v for k, v in self.engine.state().items()},
                **runner.attributes(self, "model_")}  # the frames so far

    def restore(self, state: dict[str, np.ndarray]) -> None:
        self.engine.restore({k[7:]: v for k, v in state.items() if k.startswith("engine_")})
        runner.set_attributes(self, state, "model_")

    def result(self) -> dict[str, np.ndarray]:
        return {k: np.array(v) for k, v in self.frames.items()}


def to_dataset(scene: Scene, engine: Engine, labels: dict, frames: dict) -> xr.Dataset:
    """The run dataset's variables and the lattice's derived constants (the runner adds the
    provenance)."""
    s = engine.system
    series = engine.series_array()
    names = engine.kernel.SERIES
    data = {name: ("sample", series[:, k]) for k, name in enumerate(names) if name != "time"}
    data.update(
        x=(("frame", "particle"), frames["x"]), y=(("frame", "particle"), frames["y"]),
        theta=(("frame", "particle"), frames["theta"]),
        mass=("particle", s.mass), body=("particle", labels["body"]),
        row=("particle", labels["row"]), col=("particle", labels["col"]),
        bond_i=("bond", s.bi), bond_j=("bond", s.bj), bond_state=("bond", s.state),
        bond_break_time=("bond", engine.tbreak), bond_unbreakable=("bond", s.unbreakable))
    ds = xr.Dataset(data, coords={"time": ("sample", series[:, 0]),
                                  "frame_time": ("frame", frames["time"])})
    c = beam_constants(scene)
    moduli = beam.lattice_moduli(c.kn, c.ks)
    water, bed = scene.optional("domain.water_level"), scene.optional("domain.bed_level")
    ds.attrs.update({
        "dt": engine.dt, "steps": engine.step, "kn": c.kn, "ks": c.ks, "E_b": c.E_b,
        "beam_width": c.width, "E": moduli["E"], "nu": moduli["nu"], "P_modulus": moduli["M"],
        "rho2": float(s.mass[0] / beam.cell_area(s.L)), "L": s.L, "period_x": s.period_x,
        "n_particles": s.n, "n_bonds_final": int(s.bi.size),
        # NaN: the scene has no water line / bed
        "water_level": math.nan if water is None else float(water),
        "bed_level": math.nan if bed is None else float(bed)})
    return ds


def run(scene: Scene, out: Path, seed: int = 0, init: Path | None = None, **checkpoints) -> Path:
    """``craquelure run lattice/<scene>`` (checkpoints every ``numerics.checkpoint_every``
    frames); the initial state is built from the scene and seed (``--init`` is refused)."""
    if init is not None:
        raise CraquelureError("lattice runs build their initial state from the scene and seed: "
                              "run without --init")
    clock = WallClock()
    engine, labels = make_engine(scene, seed)
    model = LatticeRun(scene, engine)
    return runner.run_to_file(
        model, scene, seed, out, lambda: to_dataset(scene, engine, labels, model.result()), clock,
        t_end=model.t_end, desc=f"lattice {scene.name}", default_every=model.rebuild_every,
        **checkpoints)
