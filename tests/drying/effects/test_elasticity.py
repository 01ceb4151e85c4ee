"""The elasticity effect (drying spec section 13 checks 4 and 7): elastic wave frequencies, the
velocity gradient of a rigid rotation is the spin, the Jaumann rate is objective."""

from __future__ import annotations

import math

import numpy as np
import pytest

from craquelure.drying.effects.elasticity import jaumann_rate
from craquelure.drying.engine import SXX, SXY, SYY, VX, VY, X

from .oscillation import quarter_period


@pytest.mark.parametrize("polarisation", ["longitudinal", "transverse"])
def test_elastic_wave_frequency(make_scene, make_lattice_engine, polarisation):
    """Check 4: eta = 0, no substrate, no drying, lattice L = 2, k = 2 pi/L:
    omega = c_L k (longitudinal) and c_T k (transverse) within 1 %."""
    scene = make_scene(effects=["elasticity", "continuity"], domain={"box_length": 2.0},
                       particles={"n": 1600}, numerics={"integrator": "abm4", "dt": 0.004})
    k = 2 * math.pi / 2.0
    eng = make_lattice_engine(scene)
    row = VX if polarisation == "longitudinal" else VY
    mode = np.sin(k * eng.x0)
    eng.state[row] = 1e-4 * mode
    eng.rebuild()
    quarter = quarter_period(eng, lambda e: float(np.sum(e.state[row] * mode)), 3.0)
    c = math.sqrt(1.2) if polarisation == "longitudinal" else math.sqrt(0.1)
    omega = math.pi / 2 / quarter
    assert omega == pytest.approx(c * k, rel=0.01)


def test_rotating_patch_velocity_gradient_is_spin(make_scene, make_lattice_engine):
    """Check 7, SPH part: a rigid rotation v = omega z x (r - r_c) gives, on particles at least
    h inside a lattice patch, L = spin tensor within 2e-3 |omega| (D = 0, so no stress rate
    beyond the Jaumann rotation term)."""
    scene = make_scene(effects=["elasticity"], domain={"box_length": 2.0},
                       particles={"n": 1600})
    eng = make_lattice_engine(scene)
    xc = yc = 1.0
    rx, ry = eng.state[X] - xc, eng.state[X + 1] - yc
    patch = np.hypot(rx, ry) < 0.7
    eng.alive[:] = patch
    eng.mass[~patch] = 0.0
    omega = 1e-2
    eng.state[VX], eng.state[VY] = -omega * ry * patch, omega * rx * patch
    sigma = np.array([2e-3, -1e-3, 5e-4])
    eng.state[SXX:SXY + 1] = sigma[:, None] * patch
    eng.rebuild()
    rates = eng.f_current
    interior = np.hypot(rx, ry) < 0.7 - 0.2 - 0.05
    expected = jaumann_rate(0.0, -omega, omega, 0.0, *sigma, 1.0, 0.1)
    for row, value in zip((SXX, SYY, SXY), expected, strict=True):
        np.testing.assert_allclose(rates[row, interior], value, atol=2e-3 * omega * 1.2 + 1e-12)


def test_jaumann_rotation_is_objective():
    """Check 7, constitutive part: under a pure spin (D = 0) the Jaumann rate rotates sigma_e:
    tr and det constant to 1e-6 over a quarter turn, principal axes turn by 90 degrees."""
    omega = 1.0
    sigma = np.array([3e-3, -1e-3, 1e-3])

    def f(s):
        return np.array(jaumann_rate(0.0, -omega, omega, 0.0, s[0], s[1], s[2], 1.0, 0.1))

    steps = 1500
    dt, s = math.pi / 2 / omega / steps, sigma.copy()
    for _ in range(steps):
        k1 = f(s)
        k2 = f(s + 0.5 * dt * k1)
        k3 = f(s + 0.5 * dt * k2)
        k4 = f(s + dt * k3)
        s = s + dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
    tr0, det0 = sigma[0] + sigma[1], sigma[0] * sigma[1] - sigma[2] ** 2
    assert abs((s[0] + s[1]) - tr0) <= 1e-6 * abs(tr0)
    assert abs((s[0] * s[1] - s[2] ** 2) - det0) <= 1e-6 * abs(det0)
    angle0 = 0.5 * math.atan2(2 * sigma[2], sigma[0] - sigma[1])
    angle1 = 0.5 * math.atan2(2 * s[2], s[0] - s[1])
    turned = (angle1 - angle0) % math.pi
    assert turned == pytest.approx(math.pi / 2, abs=1e-6)
