"""Beam-lattice scene rules a schema cannot state and the memory a run needs; called by
:mod:`craquelure.scene_rules` (``scene_problems``, ``memory_estimate``)."""

import math

from craquelure.lattice.initial_state import beam_constants
from craquelure.scene_rules import SceneView, lookup, steps_problem


def step_estimate(data: dict) -> float:
    """A lower bound of the lattice step dt_factor 2/omega_est (lattice spec section 5) from
    the scene alone: six bonds of the stiffest constant on the lightest disc."""
    c = beam_constants(SceneView(data))
    spacing = float(lookup(data, "particles.spacing"))
    mass = float(lookup(data, "particles.density")) * math.pi * spacing**2 / 4
    inertia = mass * spacing**2 / 8
    k = max(c.kn, 2.0 * (c.a + c.b) / spacing**2)
    w2 = max(2 * 6 * k / mass, 2 * 6 * c.a / inertia)
    return float(lookup(data, "numerics.dt_factor")) * 2 / math.sqrt(w2) if w2 > 0 else math.inf


def scene_problems(data: dict) -> list[str]:
    out = []
    if lookup(data, "domain.pad") is not None and lookup(data, "domain.periodic_x"):
        out.append("domain.pad cannot be used with domain.periodic_x")
    if lookup(data, "material.youngs_modulus") is not None \
            and lookup(data, "material.poisson_ratio") is None:
        out.append("material.youngs_modulus needs material.poisson_ratio")
        return out
    t_end = float(lookup(data, "outputs.t_end"))
    problem = steps_problem("numerics.dt_factor", t_end, step_estimate(data))
    return out + ([problem] if problem else [])


def memory_estimate(data: dict) -> tuple[float, str]:
    n = int(lookup(data, "domain.nx")) * int(lookup(data, "domain.ny"))
    bonds = 3 * n
    steps = float(lookup(data, "outputs.t_end")) / step_estimate(data)
    rows = steps / int(lookup(data, "numerics.series_every")) + 2
    frames = int(lookup(data, "outputs.frames")) + 1
    need = n * 8 * 40 + bonds * 8 * 30 + rows * 17 * 8 * 3 + frames * n * 3 * 8
    return need, f"{n} particles, {bonds} bonds, {rows:.3g} energy-series rows"
