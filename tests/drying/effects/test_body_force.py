"""Body force: the centre of mass of a layer without substrate accelerates at g; at g = 0 the
effect changes nothing."""

from __future__ import annotations

import numpy as np
import pytest

from craquelure.drying.engine import VX, VY, X, Y

EFFECTS = ["elasticity", "viscosity", "xsph", "continuity"]


def _run(make_scene, make_lattice_engine, effects, g=None, steps=50):
    material = {} if g is None else {"body_force": list(g)}
    scene = make_scene(effects=effects, material=material)
    rng = np.random.default_rng(3)
    eng = make_lattice_engine(scene, sigma_e=rng.uniform(-1e-3, 1e-3, (3, 400)))
    for _ in range(steps):
        eng.step()
    return eng


def test_centre_of_mass_accelerates_at_g(make_scene, make_lattice_engine):
    """The pair sums cancel in the total momentum (antisymmetric), so the mean velocity is g t
    and, RK4 being exact on a quadratic, the mean displacement 1/2 g t^2, to round-off (1e-12
    of g t, the momentum sums being rounded per particle), while the paste deforms."""
    g = (2e-3, -1e-3)
    eng = _run(make_scene, make_lattice_engine, [*EFFECTS, "body_force"], g)
    m = eng.mass / eng.mass.sum()
    for row, pos, gk in ((VX, X, g[0]), (VY, Y, g[1])):
        assert float(m @ eng.state[row]) == pytest.approx(gk * eng.t, rel=1e-12)
        shift = float(m @ (eng.state[pos] - eng.x0 if pos == X else eng.state[pos] - eng.y0))
        assert shift == pytest.approx(0.5 * gk * eng.t**2, rel=1e-9)
    assert np.ptp(eng.state[VX]) > 1e-6  # the stresses act too: not a rigid translation


def test_without_it_nothing_changes(make_scene, make_lattice_engine):
    """At g = 0 the run is bit-identical to the same run without the effect."""
    on = _run(make_scene, make_lattice_engine, [*EFFECTS, "body_force"], (0.0, 0.0), steps=10)
    off = _run(make_scene, make_lattice_engine, EFFECTS, steps=10)
    assert np.array_equal(on.state, off.state)


def test_the_runaway_guard_counts_its_energy(make_scene, make_lattice_engine):
    """Free fall at g over t_end gives 1/2 M g^2 t_end^2 of kinetic energy: the guard's bound
    holds it, so the run is not stopped."""
    g = (0.3, 0.0)
    eng = _run(make_scene, make_lattice_engine, [*EFFECTS, "body_force"], g, steps=250)
    assert eng.health() is None
    free_fall = 0.5 * eng.mass.sum() * g[0] ** 2 * eng.t**2
    assert eng.kinetic_energy() == pytest.approx(free_fall, rel=1e-3)
    assert eng.energy_bound >= free_fall
