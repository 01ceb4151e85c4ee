"""The drying effect on demand: without ``drying`` an unstressed paste stays at rest."""

from __future__ import annotations

import numpy as np

from craquelure.drying.engine import SXX, SYY, VX, VY


def test_without_drying_unstressed_paste_stays_at_rest(make_scene):
    """Effects on demand: without `drying`, an unstressed paste (RSA, consistent masses) does
    not move at all."""
    from craquelure.drying.api import engine_from_initial
    from craquelure.drying.initial_state import build_initial_state

    scene = make_scene(effects=["elasticity", "viscosity", "substrate", "fracture", "xsph",
                                "continuity"], particles={"placement": "rsa"})
    eng = engine_from_initial(scene, build_initial_state(scene, seed=1))
    for _ in range(50):
        eng.step()
    assert np.all(eng.state[VX:VY + 1] == 0.0)
    assert np.all(eng.state[SXX:SYY + 1] == 0.0)
