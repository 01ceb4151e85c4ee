"""Builders for small drying-paste engines used by the engine and run tests."""

from __future__ import annotations

import copy

import numpy as np
import pytest
import yaml

from craquelure.drying.engine import DryingEngine
from craquelure.drying.positions import square_lattice
from craquelure.scene import load_scene_text

BASE = {
    "model": "drying",
    "domain": {"box_length": 1.0},
    "particles": {"n": 400, "placement": "square_lattice"},
    "material": {"rho0": 1.0, "lame_lambda": 1.0, "lame_mu": 0.1, "eta": 1.0,
                 "thickness": 0.316, "yield_stress": 5.0e-3, "drying_rate": 2.2e-5,
                 "initial_stress_amplitude": 0.0},
    "numerics": {"h": 0.2, "integrator": "rk4", "dt": 0.004},
    "outputs": {"t_end": 1.0, "times": [1.0]},
    "effects": ["elasticity", "viscosity", "drying", "substrate", "fracture", "xsph",
                "continuity"],
}


def drying_scene(effects=None, **sections):
    """A scene dict based on BASE; ``sections`` update whole sub-mappings key by key."""
    data = copy.deepcopy(BASE)
    for section, values in sections.items():
        data[section].update(values)
    if effects is not None:
        data["effects"] = list(effects)
    return load_scene_text(yaml.safe_dump(data), name="test")


def lattice_engine(scene, sigma_e=None, vx=None, vy=None) -> DryingEngine:
    length = scene.get("domain.box_length")
    side = int(round(np.sqrt(scene.get("particles.n"))))
    x, y = square_lattice(side, length)
    n = x.size
    mass = np.full(n, scene.get("material.rho0") * length**2 / n)
    stress = np.zeros((3, n)) if sigma_e is None else sigma_e
    return DryingEngine(scene, x, y, mass, np.full(n, scene.get("material.rho0")), stress,
                        vx=vx, vy=vy)


@pytest.fixture
def make_scene():
    return drying_scene


@pytest.fixture
def make_lattice_engine():
    return lattice_engine
