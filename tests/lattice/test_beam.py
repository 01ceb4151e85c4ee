"""Beam mechanics: spec section 12 checks 1-3 (matrix, cantilever, lattice E and nu)."""

import math

import numpy as np
import pytest

from craquelure.lattice import beam
from craquelure.lattice.geometry import find_bonds, triangular_block

from . import linear_beam


def test_local_matrix_is_the_euler_bernoulli_matrix():
    E_b, w, L = 2.0, 0.7, 1.3  # noqa: N806
    c = beam.euler_bernoulli(E_b, w, L)
    k = linear_beam.local_matrix(c.kn, c.a, c.b, L)
    np.testing.assert_allclose(k, linear_beam.euler_bernoulli_matrix(E_b, c.area, c.inertia, L),
                               rtol=1e-14, atol=1e-14)


@pytest.mark.parametrize("model", ["euler_bernoulli", "shear_beam"])
def test_matrix_symmetric_rank3_rigid_null_space(model):
    c = beam.euler_bernoulli(1.0, 0.7) if model == "euler_bernoulli" else beam.shear_beam(1, .2)
    alpha = 0.7
    kg = linear_beam.global_matrix(linear_beam.local_matrix(c.kn, c.a, c.b, 1.0), alpha)
    np.testing.assert_allclose(kg, kg.T, atol=1e-14)
    assert np.linalg.matrix_rank(kg, tol=1e-10) == 3
    # rigid modes of the two nodes at (0, 0) and (cos a, sin a)
    x2, y2 = math.cos(alpha), math.sin(alpha)
    modes = np.array([[1, 0, 0, 1, 0, 0], [0, 1, 0, 0, 1, 0], [0, 0, 1, -y2, x2, 1]], float)
    np.testing.assert_allclose(kg @ modes.T, 0.0, atol=1e-13)


def test_global_matrix_invariant_under_rotating_the_beam():
    """Rotating the beam by phi rotates K_glob: R^T K(alpha + phi) R = K(alpha)."""
    c = beam.euler_bernoulli(1.0, 0.5)
    kl = linear_beam.local_matrix(c.kn, c.a, c.b, 1.0)
    alpha, phi = 0.3, 1.1
    # global -> rotated frame: rows of the blockdiag rotation by -phi
    r = linear_beam.rotation_matrix(phi)
    np.testing.assert_allclose(r @ linear_beam.global_matrix(kl, alpha + phi) @ r.T,
                               linear_beam.global_matrix(kl, alpha), atol=1e-13)


def test_cantilever_tip_deflection_and_stretch():
    """10 nodes in a line, node 0 clamped, tip load P: P l^3/(3 E I) and P l/(E A)."""
    E_b, w, L, P = 1.0, 0.7, 1.0, 1e-3  # noqa: N806
    c = beam.euler_bernoulli(E_b, w, L)
    x, y = np.arange(10.0) * L, np.zeros(10)
    bi, bj = np.arange(9), np.arange(1, 10)
    K = linear_beam.assemble_global(x, y, bi, bj, c.kn, c.a, c.b)  # noqa: N806
    fixed = np.zeros(30, bool)
    fixed[:3] = True
    ell = 9 * L
    f = np.zeros(30)
    f[3 * 9 + 1] = P
    u = linear_beam.solve_static(K, f, fixed)
    assert u[3 * 9 + 1] == pytest.approx(P * ell**3 / (3 * E_b * c.inertia), rel=1e-2)
    f = np.zeros(30)
    f[3 * 9] = P
    u = linear_beam.solve_static(K, f, fixed)
    assert u[3 * 9] == pytest.approx(P * ell / (E_b * c.area), rel=1e-12)


def uniaxial_moduli(constants, nx=40, ny=46):
    x, y, row = triangular_block(nx, ny)
    bi, bj = find_bonds(x, y, np.zeros(x.size, int))
    K = linear_beam.assemble_global(x, y, bi, bj, constants.kn, constants.a, constants.b)  # noqa: N806
    n = x.size
    first = np.array([r * nx for r in range(ny)])
    last = first + nx - 1
    sigma = 1e-4
    f = np.zeros(3 * n)
    f[3 * last] = sigma * math.sqrt(3) / 2  # one row carries a strip of height sqrt(3)/2 L
    fixed = np.zeros(3 * n, bool)
    fixed[3 * first] = True
    fixed[3 * first[ny // 2] + 1] = True
    u = linear_beam.solve_static(K, f, fixed)
    inner = ((x > 0.25 * nx) & (x < 0.75 * nx) & (y > 0.25 * y.max()) & (y < 0.75 * y.max()))
    design = np.column_stack([x[inner], y[inner], np.ones(inner.sum())])
    exx = np.linalg.lstsq(design, u[0::3][inner], rcond=None)[0][0]
    eyy = np.linalg.lstsq(design, u[1::3][inner], rcond=None)[0][1]
    return sigma / exx, -eyy / exx


@pytest.mark.parametrize("model", ["shear_beam", "euler_bernoulli"])
def test_lattice_E_and_nu_within_2_percent(model):  # noqa: N802
    c = beam.shear_beam(1.0, 0.2) if model == "shear_beam" else beam.euler_bernoulli(1.0, 0.5)
    want = beam.lattice_moduli(c.kn, c.ks)
    E, nu = uniaxial_moduli(c)  # noqa: N806
    assert E == pytest.approx(want["E"], rel=0.02)
    assert nu == pytest.approx(want["nu"], rel=0.02)


def test_moduli_mapping_round_trip():
    kn, ks = beam.stiffness_from_moduli(1.3, 0.25)
    m = beam.lattice_moduli(kn, ks)
    assert m["E"] == pytest.approx(1.3, rel=1e-12)
    assert m["nu"] == pytest.approx(0.25, rel=1e-12)
    assert ks / kn == pytest.approx(0.2, rel=1e-12)
    with pytest.raises(ValueError):
        beam.stiffness_from_moduli(1.0, 0.4)
