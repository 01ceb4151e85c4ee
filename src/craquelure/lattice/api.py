"""Model API of the beam lattice for the CLI: initial state, derived numbers, run."""

from __future__ import annotations

import math
from pathlib import Path

import xarray as xr

from craquelure.errors import CraquelureError
from craquelure.lattice import beam
from craquelure.lattice.build import beam_constants, build_system, engine_params
from craquelure.lattice.engine import PARALLEL_MIN_BONDS
from craquelure.lattice.run import run as _run
from craquelure.provenance import WallClock, provenance_attrs
from craquelure.scene import Scene
from craquelure.throughput import prediction_lines

__all__ = ["build_initial_state", "derived_numbers", "run"]


def build_initial_state(scene: Scene, seed: int) -> xr.Dataset:
    clock = WallClock()
    s, labels = build_system(scene, seed)
    ds = xr.Dataset({"x": ("particle", s.x), "y": ("particle", s.y),
                     "body": ("particle", labels["body"]), "row": ("particle", labels["row"]),
                     "bond_i": ("bond", s.bi), "bond_j": ("bond", s.bj),
                     "bond_state": ("bond", s.state)})
    ds.attrs.update(provenance_attrs(scene, seed, clock))
    return ds


def derived_numbers(scene: Scene) -> dict[str, object]:
    s, _ = build_system(scene, 0)
    c = beam_constants(scene)
    m = beam.lattice_moduli(c.kn, c.ks)
    p = engine_params(scene, s)
    rho2 = float(s.mass[0] / beam.cell_area(s.L))
    steps = math.ceil(scene.get("outputs.t_end") / p["dt"])
    return {
        "particles": s.n, "bonds": int(s.bi.size), "k_n": c.kn, "k_s": c.ks,
        "E_b": c.E_b, "beam width": c.width, "lattice E": m["E"], "lattice nu": m["nu"],
        "P-wave speed": math.sqrt(m["M"] / rho2), "time step": p["dt"], "steps": steps,
        **prediction_lines("lattice", workload(scene)),
    }


def workload(scene: Scene) -> dict[str, float]:
    """Steps, particles, bonds per particle (2 x bonds / N) and effects of a run; serial below
    the engine's parallel threshold (the serial kernel runs whatever the thread count)."""
    s, _ = build_system(scene, 0)
    steps = math.ceil(scene.get("outputs.t_end") / engine_params(scene, s)["dt"])
    return {"units": steps, "particles": s.n, "neighbours": 2.0 * s.bi.size / s.n,
            "effects": tuple(scene.effects), "serial": s.bi.size < PARALLEL_MIN_BONDS}


def run(scene: Scene, out: Path, seed: int = 0, init: Path | None = None,
        resume: bool = False, **checkpoints) -> Path:
    if init is not None:
        raise CraquelureError("lattice runs build their initial state from the scene and seed: "
                              "run without --init")
    return _run(scene, out, seed=seed, resume=resume, **checkpoints)
