"""The effect fragments with the full symmetric 3x3 stress (domain.dim 3): the Jaumann rate
against the matrix product, the Jacobi eigen-decomposition against numpy, and the objectivity
of the plastic returns, the damage and the artificial stress (rotating the input rotates the
output). Components (xx, yy, xy, zz, xz, yz)."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from craquelure.impact.effects.artificial_stress import artificial_stress_tensor
from craquelure.impact.effects.cap_plasticity import cap_return
from craquelure.impact.effects.damage import damage_update, principal
from craquelure.impact.effects.elasticity import elastic_energy_density, jaumann_trial
from craquelure.impact.effects.plasticity import dp_return
from craquelure.impact.material import standard_concrete

MAT = standard_concrete()
RHO = 2400.0


def matrix(s):
    xx, yy, xy, zz, xz, yz = s
    return np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])


def components(a):
    return (a[0, 0], a[1, 1], a[0, 1], a[2, 2], a[0, 2], a[1, 2])


def random_stress(rng, lo=-60e6, hi=10e6):
    return components(matrix(rng.uniform(lo, hi, 6)))


def rotate(s, q):
    return components(q @ matrix(s) @ q.T)


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


def test_principal_matches_numpy():
    rng = np.random.default_rng(1)
    for k in range(50):
        s = random_stress(rng)
        if k % 10 == 0:  # degenerate: two equal principal values, rotated
            q = Rotation.random(random_state=k).as_matrix()
            s = rotate((3e6, 3e6, 0.0, -1e6, 0.0, 0.0), q)
        lam, vec = principal(s)
        want = np.linalg.eigvalsh(matrix(s))
        assert np.allclose(np.sort(lam), want, atol=1e-9 * np.abs(want).max())
        # orthonormal axes that diagonalise s
        assert np.allclose(vec.T @ vec, np.eye(3), atol=1e-12)
        assert np.allclose(vec.T @ matrix(s) @ vec, np.diag(lam),
                           atol=1e-9 * np.abs(want).max())


@pytest.mark.parametrize("seed", range(6))
def test_damage_is_objective_and_keeps_compression(seed):
    """Rotating an in-plane state out of the plane (xz, yz non-zero: the Jacobi branch) gives
    the rotated result of the closed-form branch; the nominal stress is σ − D Σ <σ_a>+ n nᵀ, so
    compressive principal values are untouched."""
    rng = np.random.default_rng(seed)
    eps_0, eps_f = MAT.eps_0, MAT.eps_f
    s = (rng.uniform(-5e6, 8e6), rng.uniform(-20e6, 4e6), rng.uniform(-3e6, 3e6),
         rng.uniform(-10e6, 2e6), 0.0, 0.0)
    eps_max0 = 3 * eps_0
    k2, d2, n2 = damage_update(s, eps_max0, MAT.young, eps_0, eps_f)
    q = Rotation.random(random_state=seed).as_matrix()
    k3, d3, n3 = damage_update(rotate(s, q), eps_max0, MAT.young, eps_0, eps_f)
    assert k3 == pytest.approx(k2, rel=1e-12)
    assert d3 == pytest.approx(d2, rel=1e-12)
    assert np.allclose(matrix(n3), q @ matrix(n2) @ q.T, atol=1e-9 * np.abs(s).max())
    lam_s = np.linalg.eigvalsh(matrix(s))
    lam_n = np.linalg.eigvalsh(matrix(n3))
    want = np.sort(lam_s - d2 * np.maximum(lam_s, 0))
    assert np.allclose(lam_n, want, atol=1e-9 * np.abs(s).max())


@pytest.mark.parametrize("seed", range(6))
def test_artificial_stress_3d_is_objective(seed):
    """R = −ε Σ_a <σ_a>+ n_a n_aᵀ / ρ² for a full 3x3 stress."""
    rng = np.random.default_rng(seed)
    lam = np.array([rng.uniform(0, 5e6), rng.uniform(-5e6, 5e6), rng.uniform(-9e6, 0)])
    q = Rotation.random(random_state=10 + seed).as_matrix()
    s = components(q @ np.diag(lam) @ q.T)
    got = matrix(artificial_stress_tensor(s, RHO, 0.3))
    want = q @ np.diag(-0.3 * np.maximum(lam, 0) / RHO**2) @ q.T
    assert np.allclose(got, want, atol=1e-12 * np.abs(want).max())


@pytest.mark.parametrize("seed", range(4))
def test_plastic_returns_are_objective(seed):
    """Drucker-Prager and the cap model depend on I1, J2 (and J3 for the cap's Lode angle):
    returning a rotated trial stress gives the rotated return, and the same plastic strain."""
    rng = np.random.default_rng(20 + seed)
    q = Rotation.random(random_state=20 + seed).as_matrix()
    s = random_stress(rng, -150e6, 5e6)
    alpha, k = MAT.dp
    a, deps_a, _ = dp_return(s, alpha, k, MAT.shear)
    b, deps_b, _ = dp_return(rotate(s, q), alpha, k, MAT.shear)
    assert deps_b == pytest.approx(deps_a, rel=1e-9, abs=1e-15)
    assert np.allclose(matrix(b), q @ matrix(a) @ q.T, atol=1e-9 * np.abs(s).max())
    c = MAT.cap_vector()
    args = (0.0, c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7], c[8], c[18], c[19], MAT.bulk,
            MAT.shear, 1.0, 1.0)
    a, dv_a, deps_a, _ = cap_return(s, *args)
    b, dv_b, deps_b, _ = cap_return(rotate(s, q), *args)
    assert dv_b == pytest.approx(dv_a, rel=1e-9, abs=1e-15)
    assert deps_b == pytest.approx(deps_a, rel=1e-9, abs=1e-15)
    assert np.allclose(matrix(b), q @ matrix(a) @ q.T, atol=1e-9 * np.abs(s).max())


def test_elastic_energy_density_is_objective():
    rng = np.random.default_rng(5)
    s = random_stress(rng)
    q = Rotation.random(random_state=5).as_matrix()
    assert elastic_energy_density(rotate(s, q), MAT.bulk, MAT.shear) == pytest.approx(
        elastic_energy_density(s, MAT.bulk, MAT.shear), rel=1e-12)


def test_secant_energy_is_what_a_damaged_point_gives_back():
    """½ σ : C⁻¹σ̃: undamaged = the elastic energy; uniaxial tension fully cracked = 0 (an open
    crack stores nothing); a cracked point in compression keeps all its compressive energy
    (the former (1 − D_t) x energy booked it as damage dissipation)."""
    from craquelure.impact.effects.damage import damage_update
    from craquelure.impact.effects.elasticity import secant_energy_density

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
