"""The substrate effect (drying spec section 13 check 4): the frequency of the uniform mode on
the substrate spring."""

from __future__ import annotations

import math

import numpy as np
import pytest

from craquelure.drying.engine import VX

from .oscillation import quarter_period


def test_substrate_frequency(make_scene, make_lattice_engine):
    """Check 4: uniform displacement mode with the substrate spring: omega0 = 1.0007 +- 0.5 %."""
    scene = make_scene(effects=["elasticity", "substrate", "continuity", "xsph"])
    eng = make_lattice_engine(scene, vx=np.full(400, 1e-4))
    quarter = quarter_period(eng, lambda e: float(e.state[VX].mean()), 3.0)
    omega0 = math.sqrt(0.1 / 0.316**2)
    assert math.pi / 2 / quarter == pytest.approx(omega0, rel=0.005)
