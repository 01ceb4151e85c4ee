"""Run a lattice scene and write its dataset (energy series, frames, final bonds).

Dataset layout: dimension ``sample`` (energy series every ``numerics.series_every`` steps:
the columns of :data:`SERIES`), ``frame`` (snapshots x, y, theta at ``outputs.frames``
equally spaced times, the first at t = 0), ``particle`` (mass, body, row, col) and ``bond``
(end indices, final state 1 intact / 0 broken / 2 removed, break time, unbreakable).
Attributes: derived constants (dt, k_n, k_s, E, nu, P-wave modulus, rho_2) and provenance.
A diverged run raises :class:`~craquelure.errors.SimulationDiverged` and writes nothing.

Checkpoints: every ``numerics.checkpoint_every`` frames the full evolving state
(:meth:`Engine.checkpoint`: configurations, bond list, rest states and damping history,
accumulators, energy series) and the frames so far are written atomically (temporary file,
then rename) to ``<out>.checkpoint.nc``; ``craquelure run ... --resume`` continues from it
and gives a dataset bit-identical to the uninterrupted run (same data, same series). A
checkpoint carries a fingerprint of the resolved scene and the seed and is ignored by any
other run; it is deleted when the finished dataset is written. Decision [D]: checkpoints are
taken at frame marks only (an engine chunk boundary in both runs) and the contact list is
rebuilt at each of them in both runs, so the Verlet-list order is the same after a resume.
"""

from __future__ import annotations

import hashlib
import os
import sys
from pathlib import Path

import numpy as np
import xarray as xr

from craquelure.io import read_checkpoint, write_dataset
from craquelure.lattice import beam
from craquelure.lattice.build import beam_constants, make_engine
from craquelure.lattice.engine import Engine
from craquelure.progress import Progress
from craquelure.provenance import WallClock, provenance_attrs
from craquelure.scene import Scene


def frame_marks(scene: Scene, dt: float) -> np.ndarray:
    n_steps = int(np.ceil(scene.get("outputs.t_end") / dt))
    return np.unique(np.linspace(0, n_steps, scene.get("outputs.frames") + 1).round().astype(int))


def checkpoint_path(out: Path) -> Path:
    return out.with_name(out.name + ".checkpoint.nc")


def fingerprint(scene: Scene, seed: int) -> str:
    """Hash of the resolved scene and the seed: a checkpoint is only resumed by its run."""
    return hashlib.sha256(f"{scene.text}\nseed={int(seed)}".encode()).hexdigest()


def _checkpoint_dataset(scene: Scene, seed: int, engine: Engine, frames: dict, clock: WallClock,
                        wall_before: float) -> xr.Dataset:
    state = engine.checkpoint()
    data = {}
    for name, arr in state.items():
        dims = tuple(f"{name}_{k}" for k in range(arr.ndim))
        data[f"ck_{name}"] = (dims, arr)
    for name, values in frames.items():
        arr = np.array(values)
        data[f"frame_{name}"] = (tuple(f"frame_{name}_{k}" for k in range(arr.ndim)), arr)
    ds = xr.Dataset(data)
    ds.attrs.update(provenance_attrs(scene, seed, clock, extra_wall_time=wall_before))
    ds.attrs.update(fingerprint=fingerprint(scene, seed), wall_time_so_far=clock.elapsed
                    + wall_before, step=engine.step, finished=0)
    return ds


def _restore(engine: Engine, ck: xr.Dataset) -> tuple[dict, float]:
    state = {name[3:]: ck[name].values for name in ck.data_vars if name.startswith("ck_")}
    engine.restore(state)
    frames = {name[6:]: list(ck[name].values) for name in ck.data_vars
              if name.startswith("frame_")}
    return frames, float(ck.attrs["wall_time_so_far"])


def simulate(scene: Scene, seed: int, progress: bool = True, out: Path | None = None,
             resume: bool = False, clock: WallClock | None = None,
             stop_after_checkpoints: int | None = None):
    """Run the scene; returns the engine, labels, frames {time, x, y, theta} and the wall
    time of earlier (checkpointed) parts of the run. With ``out``, checkpoints are written next
    to it every ``numerics.checkpoint_every`` frames; ``resume`` continues from one.
    ``stop_after_checkpoints`` returns ``None`` after writing that many checkpoints (tests of
    resume: an interrupted run)."""
    clock = clock or WallClock()
    engine, labels = make_engine(scene, seed)
    t_end = scene.get("outputs.t_end")
    marks = frame_marks(scene, engine.dt)
    frames = {"time": [], "x": [], "y": [], "theta": []}
    wall_before = 0.0
    ck_every = int(scene.get("numerics.checkpoint_every")) if out is not None else 0
    ck_path = checkpoint_path(Path(out)) if out is not None else None
    ck = read_checkpoint(ck_path, fingerprint(scene, seed), "lattice checkpoint",
                         ("ck_q", "ck_qm", "ck_step", "frame_time")) \
        if resume and ck_path is not None else None
    if ck is not None:
        frames, wall_before = _restore(engine, ck)
        print(f"resumed from {ck_path} at t = {engine.time:g} (step {engine.step})",
              file=sys.stderr)
    bar = Progress(t_end, f"lattice {scene.name}") if progress else None
    written = 0
    for k, mark in enumerate(marks):
        if k < len(frames["time"]):
            continue  # frame restored from the checkpoint
        if mark > engine.step:
            engine.run(mark - engine.step)
        frames["time"].append(engine.time)
        for a, name in enumerate(("x", "y", "theta")):
            frames[name].append(engine.q[a].copy())
        if bar is not None:
            bar.update_to(min(engine.time, t_end))
        if ck_every and 0 < k < len(marks) - 1 and k % ck_every == 0:
            write_dataset(_checkpoint_dataset(scene, seed, engine, frames, clock, wall_before),
                          ck_path)
            written += 1
            if stop_after_checkpoints is not None and written >= stop_after_checkpoints:
                if bar is not None:
                    bar.close()
                return None
    if bar is not None:
        bar.close()
    return engine, labels, {k: np.array(v) for k, v in frames.items()}, wall_before


def to_dataset(scene: Scene, seed: int, engine: Engine, labels: dict, frames: dict,
               clock: WallClock, wall_before: float = 0.0) -> xr.Dataset:
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
    ds.attrs.update(provenance_attrs(scene, seed, clock, extra_wall_time=wall_before))
    return ds


def run(scene: Scene, out: Path, seed: int = 0, init: Path | None = None,
        resume: bool = False, stop_after_checkpoints: int | None = None) -> Path:
    """``craquelure run lattice/<scene> --out RUN.nc [--resume]``. The initial state is
    rebuilt from the scene and seed (``init`` is not used by this model). Returns the
    checkpoint path instead when stopped early by ``stop_after_checkpoints``."""
    clock = WallClock()
    out = Path(out)
    result = simulate(scene, seed, out=out, resume=resume, clock=clock,
                      stop_after_checkpoints=stop_after_checkpoints)
    if result is None:
        return checkpoint_path(out)
    engine, labels, frames, wall_before = result
    path = write_dataset(to_dataset(scene, seed, engine, labels, frames, clock, wall_before), out)
    ck_path = checkpoint_path(out)
    if ck_path.exists():
        os.unlink(ck_path)
    return path
