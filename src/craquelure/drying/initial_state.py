"""Initial state of the drying paste (drying spec section 7).

Positions by random sequential addition (minimum separation ``rsa_min_separation`` x L/sqrt(N)) or a
square lattice; optional particle-free bands; particles sorted by cell for locality; masses from the
truncated-CG mass-consistency solve, or its clamped variant that keeps every mass above the floor on
more disordered positions (``numerics.mass_solve.method``), or equal masses (ablations); v = 0,
rho = rho0, elastic stress components i.i.d. U(-a sigma_Y, a sigma_Y)."""

from __future__ import annotations

import math
from dataclasses import asdict

import numpy as np
import xarray as xr

from craquelure.drying.mass_consistency import MassBounds, consistent_masses
from craquelure.drying.positions import random_sequential_addition, square_lattice
from craquelure.scene import Scene
from craquelure.sph.neighbours import Box, cell_order


def initial_positions(scene: Scene, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    length, n = scene.get("domain.box_length"), scene.get("particles.n")
    if scene.get("particles.placement") == "square_lattice":
        side = math.isqrt(n)
        if side * side != n:
            raise ValueError(f"particles.n = {n}: a square lattice needs a perfect square")
        x, y = square_lattice(side, length)
    else:
        spacing = length / math.sqrt(n)
        d_min = scene.get("particles.rsa_min_separation") * spacing
        x, y = random_sequential_addition(n, length, d_min, rng)
    keep = np.ones(x.size, bool)
    for band in scene.get("particles.excluded_bands"):
        coord = x if band["axis"] == "x" else y
        keep &= ~((coord >= band["lo"]) & (coord < band["hi"]))
    x, y = x[keep], y[keep]
    order = cell_order(x, y, scene.get("numerics.h"), Box.square(length))
    return x[order], y[order]


def build_initial_state(scene: Scene, seed: int, check: bool = True) -> xr.Dataset:
    """Positions, masses and initial stress of ``seed``. ``check=False`` keeps masses that miss
    spec check 3's bounds (their report is in the attributes): studies of more disordered
    positions than the solve can make consistent (benchmarks/drying_initial_disorder.py)."""
    rng = np.random.default_rng(seed)
    length, h, rho0 = (float(scene.get(key))
                       for key in ("domain.box_length", "numerics.h", "material.rho0"))
    x, y = initial_positions(scene, rng)
    n = x.size
    solve = scene.get("numerics.mass_solve")
    attrs: dict[str, object] = {}
    if solve["method"] in ("truncated_cg", "clamped_cg"):
        bounds = MassBounds(rtol=solve["rtol"], min_mass_fraction=solve["min_mass_fraction"])
        mass, report = consistent_masses(
            x, y, length, h, rho0, kernel=scene.get("numerics.kernel"), bounds=bounds,
            max_iterations=solve["max_iterations"],
            shepard_spacing=solve["shepard_spacing"] * h,
            check=check and not scene.get("particles.excluded_bands"),
            method=solve["method"])
        attrs.update(asdict(report))
    else:
        # Sites are placed over the whole box and excluded bands removed afterwards, so each
        # particle stands for L^2 / particles.n of area whatever was excluded.
        mass = np.full(n, rho0 * length**2 / scene.get("particles.n"))
        attrs.update(cg_iterations=0, cg_residual=float("nan"), stopped_by="equal_masses")
    # sigma_e ~ U(-a, a) sigma_Y: none without a yield stress (optional without fracture)
    sigma_y = scene.optional("material.yield_stress")
    amplitude = scene.get("material.initial_stress_amplitude") * (
        0.0 if sigma_y is None else sigma_y)
    stress = rng.uniform(-amplitude, amplitude, size=(3, n)) if amplitude > 0 else np.zeros((3, n))
    p = ("particle",)
    ds = xr.Dataset(
        {
            "x": (p, x, {"units": "eta/sqrt(rho0 lambda)", "long_name": "position x"}),
            "y": (p, y, {"units": "eta/sqrt(rho0 lambda)", "long_name": "position y"}),
            "mass": (p, mass, {"units": "rho0 length^2", "long_name": "particle mass"}),
            "rho": (p, np.full(n, rho0), {"units": "rho0", "long_name": "density"}),
            "sigma_e_xx": (p, stress[0], {"units": "lambda", "long_name": "elastic stress xx"}),
            "sigma_e_yy": (p, stress[1], {"units": "lambda", "long_name": "elastic stress yy"}),
            "sigma_e_xy": (p, stress[2], {"units": "lambda", "long_name": "elastic stress xy"}),
        },
        attrs={"h": h, "rho0": rho0, "box_length": length, "n_particles": n, **attrs},
    )
    return ds
