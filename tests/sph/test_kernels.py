"""SPH kernels (drying spec section 5 and check 13.1): normalisation, moments, derivative,
oddness of the gradient and continuity at the spline knots."""

from __future__ import annotations

import math

import numpy as np
import pytest
from numba import njit

from craquelure.sph import kernels
from craquelure.sph.kernels import dwdr, w

KERNELS = ["quintic", "cubic", "wendland_c2"]
# Knots of the piecewise definitions, as fractions of the support radius s.
KNOTS = {"quintic": (1 / 3, 2 / 3, 1.0), "cubic": (0.5, 1.0), "wendland_c2": (1.0,)}


def radial_integral(name: str, s: float, dim: int, power: int = 0) -> float:
    """Integral of r^power W over R^dim by Gauss-Legendre quadrature on each polynomial piece
    (16 nodes are exact for degree <= 31; the integrands have degree <= 10), so the only error
    is rounding."""
    shell = 2 * math.pi if dim == 2 else 4 * math.pi
    nodes, weights = np.polynomial.legendre.leggauss(16)
    edges = [0.0, *(k * s for k in KNOTS[name])]
    total = 0.0
    for a, b in zip(edges[:-1], edges[1:], strict=True):
        r = 0.5 * (b - a) * nodes + 0.5 * (a + b)
        f = shell * r ** (dim - 1 + power) * w(name, r, s, dim)
        total += 0.5 * (b - a) * float(weights @ f)
    return total


@pytest.mark.parametrize("dim", [2, 3])
@pytest.mark.parametrize("name", KERNELS)
@pytest.mark.parametrize("s", [0.2, 1.0, 3.7])
def test_kernel_integrates_to_one(name, dim, s):
    # Spec 13.1: 1 +- 1e-10 (the quadrature itself is exact to ~1e-15 on polynomial pieces).
    assert radial_integral(name, s, dim) == pytest.approx(1.0, abs=1e-10)


def test_kernel_vanishes_outside_support():
    for name in KERNELS:
        r = np.array([1.0, 1.0 + 1e-12, 1.5, 10.0]) * 0.2
        assert np.all(w(name, r, 0.2) == 0.0)
        assert np.all(dwdr(name, r, 0.2) == 0.0)


def test_quintic_central_value_and_second_moment():
    # Spec 5: W(0) = 2.76890/h^2, int r^2 W d^2x = 0.107353 h^2 (6 significant digits).
    for h in (0.2, 1.0):
        assert float(w("quintic", 0.0, h)) * h * h == pytest.approx(2.76890, abs=5e-6)
        assert radial_integral("quintic", h, 2, power=2) / h**2 == pytest.approx(
            0.107353, abs=5e-7)


def test_quintic_matches_spec_formula():
    # W = 63/(478 pi h^2) [(3-3x)_+^5 - 6(2-3x)_+^5 + 15(1-3x)_+^5] written independently.
    h = 0.2
    x = np.linspace(0, 1.2, 1001)

    def pos5(a):
        return np.maximum(a, 0.0) ** 5

    ref = 63 / (478 * np.pi * h * h) * (pos5(3 - 3 * x) - 6 * pos5(2 - 3 * x)
                                         + 15 * pos5(1 - 3 * x))
    np.testing.assert_allclose(w("quintic", x * h, h), ref, rtol=1e-13, atol=1e-13 * ref[0])


@pytest.mark.parametrize("dim", [2, 3])
@pytest.mark.parametrize("name", KERNELS)
def test_derivative_matches_centred_difference(name, dim):
    s = 0.2
    knots = np.array(KNOTS[name]) * s
    r = np.linspace(0.003, 0.997, 400) * s
    # Keep the finite-difference stencil away from the knots (the second derivative jumps).
    eps = 1e-6 * s
    r = r[np.min(np.abs(r[:, None] - knots[None, :]), axis=1) > 10 * eps]
    fd = (w(name, r + eps, s, dim) - w(name, r - eps, s, dim)) / (2 * eps)
    exact = dwdr(name, r, s, dim)
    scale = np.abs(dwdr(name, np.linspace(0, s, 2001), s, dim)).max()
    # Relative to the derivative (1e-6), with a floor near the zero of dW/dr at r = 0 and
    # near r = s where both go to zero (truncation error O(eps^2 W''') and rounding O(u W/eps)).
    err = np.abs(fd - exact) / np.maximum(np.abs(exact), 1e-2 * scale)
    assert err.max() < 1e-6


@pytest.mark.parametrize("name", KERNELS)
def test_derivative_is_zero_at_origin_and_negative_inside(name):
    s = 1.0
    assert float(dwdr(name, 0.0, s)) == pytest.approx(0.0, abs=1e-12)
    r = np.linspace(1e-3, 0.999, 500)
    assert np.all(dwdr(name, r, s) < 0)


@pytest.mark.parametrize("name", KERNELS)
def test_gradient_is_odd(name):
    # grad_I W_IJ = dW/dr r_IJ/|r_IJ| must equal -grad_J W_JI for every pair.
    rng = np.random.default_rng(3)
    s = 0.2
    ri = rng.uniform(0, 1, (200, 2))
    rj = ri + rng.uniform(-s, s, (200, 2))

    def grad(a, b):
        d = a - b
        r = np.linalg.norm(d, axis=1)
        return (dwdr(name, r, s) / r)[:, None] * d

    g_ij = grad(ri, rj)
    g_ji = grad(rj, ri)
    assert np.abs(g_ij).max() > 0
    np.testing.assert_array_equal(g_ij, -g_ji)


@pytest.mark.parametrize("dim", [2, 3])
@pytest.mark.parametrize("name", KERNELS)
def test_continuity_at_knots(name, dim):
    # Spec 13.1: relative jump of W and dW/dr across h/3, 2h/3, h below 1e-12.
    s = 0.2
    w_scale = float(w(name, 0.0, s, dim))
    d_scale = np.abs(dwdr(name, np.linspace(0, s, 2001), s, dim)).max()
    for knot in KNOTS[name]:
        r = knot * s
        lo, hi = np.nextafter(r, 0.0), np.nextafter(r, np.inf)
        for f, scale in ((w, w_scale), (dwdr, d_scale)):
            left, right = float(f(name, lo, s, dim)), float(f(name, hi, s, dim))
            assert abs(left - right) / scale < 1e-12, (name, knot, f.__name__, left, right)


def test_unknown_kernel_lists_allowed_values():
    with pytest.raises(ValueError, match="allowed values: quintic, cubic, wendland_c2"):
        kernels.kernel_kind("gaussian")


@njit
def _w_g(kind, r2, s):
    w_out = np.empty_like(r2)
    g_out = np.empty_like(r2)
    for k in range(r2.size):
        w_out[k], g_out[k] = kernels.kernel_w_g(kind, r2[k], s, 1.0 / s)
    return w_out, g_out


@pytest.mark.parametrize("name", KERNELS)
@pytest.mark.parametrize("s", [0.2, 1.0])
def test_branch_free_pair_kernel_equals_piecewise_one(name, s):
    # The drying pair loops take (W, (dW/dr)/r) from r^2 through kernel_w_g (branch-free for
    # the quintic: (k - 3x)_+ as clamps, one formula for all pieces). Against the piecewise
    # kernel_w / kernel_dwdr / r at 20 001 radii and at the knots: equal to round-off (a few
    # ulp of the largest value: the branch-free form reaches x by r2 / sqrt(r2) and 1/r by a
    # reciprocal), exactly 0 from r = s on, W(0) exact and g = 0 at r = 0.
    kind = kernels.kernel_kind(name)
    r = np.concatenate([np.linspace(0.0, 1.2 * s, 20001),
                        [k * s for k in KNOTS[name]], [s * (1 - 1e-15), s * (1 + 1e-15)]])
    w_bf, g_bf = _w_g(kind, r * r, s)
    inside = r > 0
    w_ref = w(name, r, s, 2)
    g_ref = np.zeros_like(r)
    g_ref[inside] = dwdr(name, r[inside], s, 2) / r[inside]
    np.testing.assert_allclose(w_bf, w_ref, rtol=0, atol=1e-14 * np.abs(w_ref).max())
    np.testing.assert_allclose(g_bf, g_ref, rtol=0, atol=1e-13 * np.abs(g_ref).max())
    assert np.all(w_bf[r >= s] == 0.0) and np.all(g_bf[r >= s] == 0.0)
    assert w_bf[0] == w_ref[0] and g_bf[0] == 0.0
