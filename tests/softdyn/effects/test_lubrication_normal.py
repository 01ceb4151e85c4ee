"""Normal lubrication (spec check 6, coefficients): zeta_t/zeta_n = (2/3) h^2/a^2, and rigid
spheres give Reynolds' zeta_n = (3 pi/2) eta R^2/h."""

import math

import numpy as np
import pytest

from craquelure.scene import load_scene
from craquelure.softdyn.initial_state import build

from ..test_engine import random_t1_state, t1_setup


def test_friction_ratio_and_reynolds_limit():
    """Check 6 (coefficients): zeta_t/zeta_n = (2/3) h^2/a^2; rigid spheres (a^2 = R h) give
    Reynolds' zeta_n = (3 pi/2) eta R^2/h."""
    rng = np.random.default_rng(8)
    setup = t1_setup()
    ev = setup.system.evaluate(0.0, random_t1_state(setup, rng))
    ratio = ev["zeta_t"] / ev["zeta_n"]
    assert np.allclose(ratio, (2 / 3) * ev["h"] ** 2 / ev["a"] ** 2, rtol=1e-13, atol=0)
    rigid = build(load_scene("softdyn/two_sphere_approach",
                             ["effects=[lubrication_normal, lubrication_tangential]"]))
    ev = rigid.system.evaluate(1.0 * rigid.tau, rigid.system.initial_state())
    h = ev["h"][0]
    assert ev["zeta_n"][0] == pytest.approx(1.5 * math.pi / h, rel=1e-14)
    # rigid approach under F: dh/dt = -F/zeta_n exactly (no deflection stage)
    v = ev["v"]
    hdot = ev["n"][0] @ (v[0] - v[1])
    assert hdot == pytest.approx(-rigid.force / ev["zeta_n"][0], rel=1e-12)
