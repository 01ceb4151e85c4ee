"""Check 6 (spec section 10): the concrete material point, strain-driven, no SPH."""

import math

import numpy as np
import pytest

from craquelure.impact.material import MATERIAL_CONSTANTS, standard_concrete
from craquelure.registry import kernel_parameters, known_effects
from tests.impact.material_point import drive

MAT = standard_concrete()


def ramp(component: int, target: float, n: int = 400, start: float = 0.0) -> np.ndarray:
    path = np.zeros((n, 4))
    path[:, component] = np.linspace(start, target, n)
    return path


def test_uniaxial_compression_peak_is_f_c():
    _, sig = drive(MAT, ramp(1, -6e-3), free=("xx", "zz"))
    assert -sig[:, 1].min() == pytest.approx(MAT.f_c, rel=1e-2)
    # lateral directions really are stress-free
    assert np.abs(sig[:, [0, 3]]).max() < 1e-6 * MAT.f_c


def test_equibiaxial_compression_peak_is_1_16_f_c():
    path = ramp(1, -6e-3)
    path[:, 0] = path[:, 1]
    _, sig = drive(MAT, path, free=("zz",))
    assert -sig[:, 1].min() == pytest.approx(1.16 * MAT.f_c, rel=1e-2)
    assert sig[:, 0] == pytest.approx(sig[:, 1], rel=1e-9)


def tension_curve(n: int = 4000):
    # fine steps around the peak: the peak strain eps_0 is 1 % of eps_f
    strain = np.concatenate([np.linspace(0, 2 * MAT.eps_0, n // 2),
                             np.linspace(2 * MAT.eps_0, 1.05 * MAT.eps_f, n // 2)[1:]])
    path = np.zeros((strain.size, 4))
    path[:, 1] = strain
    return drive(MAT, path, free=("xx", "zz"))


def test_uniaxial_tension_peak_and_fracture_energy():
    eps, sig = tension_curve()
    assert sig[:, 1].max() == pytest.approx(MAT.f_t, rel=1e-2)
    # fully softened at eps_f, energy density x crack band = G_F
    assert abs(sig[-1, 1]) < 1e-6 * MAT.f_t
    energy = np.trapezoid(sig[:, 1], eps[:, 1]) * MAT.band
    assert energy == pytest.approx(MAT.G_F, rel=1e-2)
    peak = int(np.argmax(sig[:, 1]))
    post = np.trapezoid(sig[peak:, 1], eps[peak:, 1]) * MAT.band
    expected_post = MAT.G_F - 0.5 * MAT.f_t * MAT.eps_0 * MAT.band
    assert post == pytest.approx(expected_post, rel=1e-2)


def test_unloading_during_softening_is_secant():
    up = np.linspace(0, 0.3 * MAT.eps_f, 3000)
    down = np.linspace(0.3 * MAT.eps_f, 0.0, 300)[1:]
    path = np.zeros((up.size + down.size, 4))
    path[:, 1] = np.concatenate([up, down])
    eps, sig = drive(MAT, path, free=("xx", "zz"))
    unload = slice(up.size, None)
    secant = sig[up.size - 1, 1] / eps[up.size - 1, 1]
    assert secant < 0.1 * MAT.young  # well into softening
    ratio = sig[unload, 1][:-1] / eps[unload, 1][:-1]
    assert ratio == pytest.approx(secant, rel=1e-6)
    assert abs(sig[-1, 1]) < 1e-3 * MAT.f_t  # back to the origin


def test_fully_cracked_point_carries_compression():
    up = np.linspace(0, 1.2 * MAT.eps_f, 2000)
    down = np.linspace(1.2 * MAT.eps_f, -1e-3, 2000)[1:]
    path = np.zeros((up.size + down.size, 4))
    path[:, 1] = np.concatenate([up, down])
    eps, sig = drive(MAT, path, free=("xx", "zz"))
    assert abs(sig[up.size - 1, 1]) < 1e-6 * MAT.f_t  # cracked: no tension
    # crack closed (secant to the origin), then elastic compression with the intact modulus:
    # sigma = E eps at eps = -1e-3 (29.7 MPa, below f_c)
    assert np.all(sig[up.size:, 1] <= 1e-6 * MAT.f_t)
    assert sig[-1, 1] == pytest.approx(MAT.young * eps[-1, 1], rel=1e-2)


def test_material_constants_are_read_by_the_effects_that_require_them():
    """Each constant of the concrete is declared by effects (which then require its scene key),
    with a neutral value for when they are all off."""
    declared = kernel_parameters("impact")
    for name in MATERIAL_CONSTANTS:
        param, owners = declared[name]
        assert owners and math.isfinite(param.neutral), name
        for effect in owners:
            assert param.path in known_effects("impact")[effect].requires, (name, effect)
