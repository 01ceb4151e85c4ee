"""The elasticity fragments with the full symmetric 3x3 stress (domain.dim 3): the Jaumann rate
against the matrix product, the objectivity of the secant energy density (rotating the input
leaves it unchanged) and what it gives back. Components (xx, yy, xy, zz, xz, yz)."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from craquelure.impact.effects.elasticity import jaumann_trial, secant_energy_density
from craquelure.impact.material import standard_concrete

from .tensors import components, matrix, random_stress, rotate

MAT = standard_concrete()


def elastic_energy_density(s, bulk, shear):
    """p^2/(2K) + s:s/(4G) of an effective stress s = (xx, yy, xy, zz, xz, yz) (J/m^3)."""
    sxx, syy, sxy, szz, sxz, syz = s
    p = -(sxx + syy + szz) / 3.0
    dxx, dyy, dzz = sxx + p, syy + p, szz + p
    ss = dxx * dxx + dyy * dyy + dzz * dzz + 2.0 * (sxy * sxy + sxz * sxz + syz * syz)
    return 0.5 * p * p / bulk + 0.25 * ss / shear


def test_jaumann_trial_is_the_matrix_formula():
    """σ + Δt (λ tr D 1 + 2G D + Ωσ − σΩ) with Ω = (L − Lᵀ)/2, D = (L + Lᵀ)/2."""
    rng = np.random.default_rng(0)
    dt = 2e-7
    lam = MAT.bulk - 2 * MAT.shear / 3
    for _ in range(20):
        sig = random_stress(rng)
        grad = rng.normal(0, 1e3, (3, 3))
        d, om = 0.5 * (grad + grad.T), 0.5 * (grad - grad.T)
        got = jaumann_trial(sig, components(d), (om[0, 1], om[0, 2], om[1, 2]), MAT.bulk,
                            MAT.shear, dt)
        s = matrix(sig)
        want = s + dt * (lam * np.trace(d) * np.eye(3) + 2 * MAT.shear * d + om @ s - s @ om)
        assert np.allclose(matrix(got), want, rtol=0, atol=1e-12 * np.abs(want).max())


def test_jaumann_in_plane_matches_the_2d_terms():
    """With xz = yz = 0 and in-plane spin only, the 3D formula reduces bit for bit to the 2D
    one (2D results unchanged): zz keeps λ tr D + 2G D_zz and xz, yz stay zero."""
    sig = (1e6, -2e6, 0.5e6, 3e5, 0.0, 0.0)
    out = jaumann_trial(sig, (10.0, -4.0, 3.0, 0.0, 0.0, 0.0), (7.0, 0.0, 0.0), MAT.bulk,
                        MAT.shear, 1e-7)
    assert out[4] == 0.0 and out[5] == 0.0
    lam = MAT.bulk - 2 * MAT.shear / 3
    assert out[3] == sig[3] + 1e-7 * (lam * 6.0 + 2.0 * MAT.shear * 0.0)


def test_secant_energy_density_is_objective():
    rng = np.random.default_rng(5)
    s = random_stress(rng)
    r = rotate(s, Rotation.random(random_state=5).as_matrix())
    assert secant_energy_density(r, r, MAT.bulk, MAT.shear) == pytest.approx(
        secant_energy_density(s, s, MAT.bulk, MAT.shear), rel=1e-12)


def test_secant_energy_is_what_a_damaged_point_gives_back():
    """½ σ : C⁻¹σ̃: undamaged = the elastic energy; uniaxial tension fully cracked = 0 (an open
    crack stores nothing); a cracked point in compression keeps all its compressive energy
    (the former (1 − D_t) x energy booked it as damage dissipation)."""
    from craquelure.impact.effects.damage import damage_update

    rng = np.random.default_rng(11)
    s = random_stress(rng)
    assert secant_energy_density(s, s, MAT.bulk, MAT.shear) == pytest.approx(
        elastic_energy_density(s, MAT.bulk, MAT.shear), rel=1e-12)
    tension = (3e6, 0.0, 0.0, 0.0, 0.0, 0.0)
    _, dmg, nom = damage_update(tension, 2 * MAT.eps_f, MAT.young, MAT.eps_0, MAT.eps_f)
    assert dmg == 1.0
    assert secant_energy_density(nom, tension, MAT.bulk, MAT.shear) == pytest.approx(0.0,
                                                                                    abs=1e-9)
    compression = (-30e6, -5e6, 2e6, -5e6, 0.0, 0.0)
    _, dmg, nom = damage_update(compression, 2 * MAT.eps_f, MAT.young, MAT.eps_0,
                                MAT.eps_f)
    assert dmg == 1.0
    assert secant_energy_density(nom, compression, MAT.bulk, MAT.shear) == pytest.approx(
        elastic_energy_density(compression, MAT.bulk, MAT.shear), rel=1e-9)
