"""The drying kernel template: each effect set compiles to its own specialisation, and removed
particles left in the neighbour list add nothing to the rates."""

from __future__ import annotations

import numpy as np
import pytest

from craquelure.drying.engine import VX, VY, X, compile_rate


def test_effect_sets_compile_to_distinct_specialisations():
    """Each effect set gets its own generated module whose flags are compile-time constants."""
    full = compile_rate(("elasticity", "viscosity", "drying"), "quintic")
    visc = compile_rate(("viscosity",), "quintic")
    assert full is not visc
    assert full.ELASTICITY and full.DRYING and not full.SUBSTRATE
    assert visc.VISCOSITY and not visc.ELASTICITY and not visc.DRYING
    assert compile_rate(("viscosity",), "quintic") is visc


@pytest.mark.parametrize("effects", [
    ["elasticity", "viscosity", "drying", "substrate", "fracture", "xsph", "continuity"],
    ["elasticity", "viscosity", "drying", "substrate", "fracture", "continuity",
     "gradient_correction"]])
def test_removed_particles_left_in_the_neighbour_list_add_nothing(make_scene, effects):
    """A removal does not rebuild the neighbour list (the removed particles keep their rows and
    stay as neighbours, with zero mass, until the next regular rebuild): the rates of every
    present particle equal those from a fresh list without them to round-off (only the sums'
    grouping differs), and the removed particles' rates are exactly 0."""
    from craquelure.drying.api import engine_from_initial
    from craquelure.drying.initial_state import build_initial_state

    scene = make_scene(effects=effects, particles={"placement": "rsa"},
                       material={"drying_rate": 2e-3})
    eng = engine_from_initial(scene, build_initial_state(scene, seed=5))
    rng = np.random.default_rng(2)
    eng.state[VX:VY + 1] = rng.uniform(-1e-4, 1e-4, size=(2, eng.n))
    eng.t = 1.5
    eng.rebuild()
    # remove a band of particles and a few scattered ones, as a crack would
    doomed = np.flatnonzero((np.abs(eng.state[X] - 0.5 * eng.box_length) < 0.1)
                            | (rng.random(eng.n) < 0.02))
    eng.alive[doomed] = False
    eng.mass[doomed] = 0.0
    eng.state[VX:VY + 1, doomed] = 0.0
    listed = eng.pairs.jlist.size
    stale = eng.evaluate(eng.state, eng.t)
    stale_stress = eng.stress.copy()
    eng._build_neighbours()
    assert eng.pairs.jlist.size < listed
    fresh = eng.evaluate(eng.state, eng.t)
    alive = eng.alive
    for row in range(stale.shape[0]):
        scale = np.abs(fresh[row, alive]).max()
        np.testing.assert_allclose(stale[row, alive], fresh[row, alive], rtol=0,
                                   atol=1e-13 * scale + 1e-300)
    np.testing.assert_allclose(stale_stress, eng.stress, rtol=0,
                               atol=1e-13 * np.abs(eng.stress).max())
    assert np.all(stale[:, ~alive] == 0.0)
