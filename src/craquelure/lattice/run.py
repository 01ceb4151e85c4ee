"""Run a lattice scene and write its dataset (energy series, frames, final bonds).

Dataset layout: dimension ``sample`` (energy series every ``numerics.series_every`` steps:
the columns of :data:`SERIES`), ``frame`` (snapshots x, y, theta at ``outputs.frames``
equally spaced times, the first at t = 0), ``particle`` (mass, body, row, col) and ``bond``
(end indices, final state 1 intact / 0 broken / 2 removed, break time, unbreakable).
Attributes: derived constants (dt, k_n, k_s, E, nu, P-wave modulus, rho_2) and provenance.
A diverged run raises :class:`~craquelure.errors.SimulationDiverged` and writes nothing.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr

from craquelure.io import write_dataset
from craquelure.lattice import beam
from craquelure.lattice.build import beam_constants, make_engine
from craquelure.lattice.engine import Engine
from craquelure.progress import Progress
from craquelure.provenance import WallClock, provenance_attrs
from craquelure.scene import Scene


def simulate(scene: Scene, seed: int, progress: bool = True) -> tuple[Engine, dict, dict]:
    """Run the scene; returns the engine, labels and frames {time, x, y, theta}."""
    engine, labels = make_engine(scene, seed)
    t_end = scene.get("outputs.t_end")
    n_steps = int(np.ceil(t_end / engine.dt))
    n_frames = scene.get("outputs.frames")
    marks = np.unique(np.linspace(0, n_steps, n_frames + 1).round().astype(int))
    frames = {"time": [], "x": [], "y": [], "theta": []}
    bar = Progress(t_end, f"lattice {scene.name}") if progress else None
    for mark in marks:
        if mark > engine.step:
            engine.run(mark - engine.step)
        frames["time"].append(engine.time)
        for k, name in enumerate(("x", "y", "theta")):
            frames[name].append(engine.q[k].copy())
        if bar is not None:
            bar.update_to(min(engine.time, t_end))
    if bar is not None:
        bar.close()
    return engine, labels, {k: np.array(v) for k, v in frames.items()}


def to_dataset(scene: Scene, seed: int, engine: Engine, labels: dict, frames: dict,
               clock: WallClock) -> xr.Dataset:
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
    ds.attrs.update({
        "dt": engine.dt, "steps": engine.step, "kn": c.kn, "ks": c.ks, "E_b": c.E_b,
        "beam_width": c.width, "E": moduli["E"], "nu": moduli["nu"], "P_modulus": moduli["M"],
        "rho2": float(s.mass[0] / beam.cell_area(s.L)), "L": s.L, "period_x": s.period_x,
        "n_particles": s.n, "n_bonds_final": int(s.bi.size),
        "water_level": float(scene.get("domain.water_level", np.nan)),
        "bed_level": float(scene.get("domain.bed_level", np.nan))})
    ds.attrs.update(provenance_attrs(scene, seed, clock))
    return ds


def run(scene: Scene, out: Path, seed: int = 0, init: Path | None = None,
        resume: bool = False) -> Path:
    """``craquelure run lattice/<scene> --out RUN.nc``. The initial state is rebuilt from the
    scene and seed (``init`` and ``resume`` are not used by this model: runs are minutes)."""
    clock = WallClock()
    engine, labels, frames = simulate(scene, seed)
    return write_dataset(to_dataset(scene, seed, engine, labels, frames, clock), out)
