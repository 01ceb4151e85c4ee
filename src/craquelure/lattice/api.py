"""Model API of the beam lattice for the CLI: initial state, derived numbers, run."""

from __future__ import annotations

import math
from pathlib import Path

import xarray as xr

from craquelure.errors import CraquelureError
from craquelure.lattice import beam
from craquelure.lattice.build import beam_constants, build_system, engine_params
from craquelure.lattice.run import run as _run
from craquelure.provenance import WallClock, provenance_attrs
from craquelure.scene import Scene

# bond updates per second of the serial kernel (benchmarks/lattice_engine.py on this shared
# 2-core machine, 2026-11-22, after the chunked kernel: 2.1-2.6e7 wall at load average 3.8,
# 1.9e7 at 7.7); used only for wall-time estimates
BOND_UPDATES_PER_S = 2.0e7

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
        "estimated wall time [s]": steps * s.bi.size / BOND_UPDATES_PER_S,
    }


def run(scene: Scene, out: Path, seed: int = 0, init: Path | None = None,
        resume: bool = False, **checkpoints) -> Path:
    if init is not None:
        raise CraquelureError("lattice runs build their initial state from the scene and seed: "
                              "run without --init")
    return _run(scene, out, seed=seed, resume=resume, **checkpoints)
