"""The XSPH effect (drying spec section 13 check 6): momentum is conserved with XSPH on."""

from __future__ import annotations

import numpy as np

from craquelure.drying.engine import VX, VY


def test_momentum_conserved_with_xsph(make_scene):
    """Check 6: substrate off, random velocities on an RSA configuration, XSPH on:
    |sum m v(t) - sum m v(0)| <= 1e-12 sum m |v| after 1000 steps."""
    from craquelure.drying.api import engine_from_initial
    from craquelure.drying.initial_state import build_initial_state

    scene = make_scene(effects=["elasticity", "viscosity", "xsph", "continuity"],
                       particles={"placement": "rsa"}, numerics={"integrator": "abm4"})
    eng = engine_from_initial(scene, build_initial_state(scene, seed=3))
    rng = np.random.default_rng(0)
    eng.state[VX:VY + 1] = rng.uniform(-1e-3, 1e-3, size=(2, eng.n))
    eng.rebuild()
    p0 = np.array(eng.momentum())
    scale = float(np.sum(eng.mass * np.hypot(eng.state[VX], eng.state[VY])))
    for _ in range(1000):
        eng.step()
    assert np.abs(np.array(eng.momentum()) - p0).max() <= 1e-12 * scale
