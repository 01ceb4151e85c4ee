"""The viscosity effect (drying spec section 13 check 5): the decay rate of a shear and a
longitudinal mode."""

from __future__ import annotations

import math

import numpy as np
import pytest

from craquelure.drying.engine import VX, VY


@pytest.mark.parametrize("polarisation,factor", [("transverse", 0.5), ("longitudinal", 1.0)])
def test_viscous_decay(make_scene, make_lattice_engine, polarisation, factor):
    """Check 5: lambda = mu = 0, eta = 1: decay rate eta k^2/(2 rho0) (transverse) and
    eta k^2/rho0 (longitudinal) within 2 %."""
    scene = make_scene(effects=["viscosity", "continuity"], domain={"box_length": 2.0},
                       particles={"n": 1600},
                       material={"lame_lambda": 0.0, "lame_mu": 0.0, "eta": 1.0},
                       numerics={"dt": 0.002})
    k = 2 * math.pi / 2.0
    eng = make_lattice_engine(scene)
    row = VX if polarisation == "longitudinal" else VY
    mode = np.sin(k * eng.x0)
    eng.state[row] = 1e-4 * mode
    eng.rebuild()
    a0 = float(np.sum(eng.state[row] * mode))
    while eng.t < 0.1 - 1e-9:
        eng.step()
    rate = -math.log(float(np.sum(eng.state[row] * mode)) / a0) / eng.t
    assert rate == pytest.approx(factor * k * k, rel=0.02)
