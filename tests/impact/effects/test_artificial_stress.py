"""Monaghan / Gray-Monaghan-Swift artificial stress (spec section 3): the tensor R_i from the
principal tensile components of the total nominal stress, and the pair term f_ij^n (R_i + R_j)
with f_ij = W(r_ij; h_ij)/W(Delta; h_ij), Delta the initial spacing (not h, not the current
spacing), as the compiled force pass applies it."""

import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from craquelure.impact.api import probe_settings
from craquelure.impact.effects.artificial_stress import artificial_stress_tensor
from craquelure.impact.engine import kernels_for
from craquelure.impact.material import standard_concrete
from craquelure.sph.kernels import CUBIC, kernel_dwdr

from .tensors import components, matrix

RHO = 2400.0
EPS = 0.3


def rotated(s1, s2, theta):
    """In-plane stress with principal values s1 along (cos, sin) theta and s2 normal to it."""
    c, s = math.cos(theta), math.sin(theta)
    return (c * c * s1 + s * s * s2, s * s * s1 + c * c * s2, c * s * (s1 - s2))


def plane(sxx, syy, sxy, szz=0.0):
    """The 2D stress as the fragment's six components (xz = yz = 0)."""
    return (sxx, syy, sxy, szz, 0.0, 0.0)


def tensor_2d(*s):
    """In-plane R (xx, yy, xy) of an in-plane stress, as the 2D kernels store it."""
    return artificial_stress_tensor(plane(*s), RHO, EPS)[:3]


def test_biaxial_tension_uses_total_stress():
    """Equal principal tensions: R = -eps sigma / rho^2 times the identity (a deviatoric R would
    vanish here)."""
    r = tensor_2d(2.0e6, 2.0e6, 0.0)
    assert r == pytest.approx((-EPS * 2.0e6 / RHO**2, -EPS * 2.0e6 / RHO**2, 0.0), rel=1e-14)


def test_compression_contributes_nothing():
    assert tensor_2d(-3.0e6, -1.0e6, 0.5e6) == (0.0, 0.0, 0.0)


@pytest.mark.parametrize("theta", [0.0, 0.3, math.pi / 6, math.pi / 4, 1.2, 2.0])
def test_only_the_tensile_principal_component_rotated_back(theta):
    """sigma = s1 n n^T + s2 m m^T with s1 > 0 > s2: R = -eps s1/rho^2 n n^T exactly."""
    s1, s2 = 2.5e6, -7.0e6
    rxx, ryy, rxy = tensor_2d(*rotated(s1, s2, theta))
    a = -EPS * s1 / RHO**2
    c, s = math.cos(theta), math.sin(theta)
    scale = abs(a)
    assert rxx == pytest.approx(a * c * c, abs=1e-12 * scale)
    assert ryy == pytest.approx(a * s * s, abs=1e-12 * scale)
    assert rxy == pytest.approx(a * c * s, abs=1e-12 * scale)


def cubic_shape(q):
    """Spec's cubic B-spline shape in q = r/h, without its normalisation."""
    if q < 1.0:
        return 1.0 - 1.5 * q * q + 0.75 * q**3
    if q < 2.0:
        return 0.25 * (2.0 - q) ** 3
    return 0.0


@pytest.mark.parametrize("h_over_delta,r_over_delta", [(1.2, 1.0), (1.2, 1.3), (1.8, 1.0),
                                                       (1.8, 0.8), (0.84, 1.1)])
def test_pair_term_weight_and_antisymmetry(h_over_delta, r_over_delta):
    """Two particles, stress off, only the AS bracket: a_0 = m f^4 (R_0 + R_1) . grad_0 W with
    f = W(r)/W(Delta) at the same h (normalisation cancels; f(Delta) = 1 whatever h), and
    a_1 = -a_0 (equal masses: momentum conserved)."""
    delta = 0.004
    k = kernels_for(("elasticity", "artificial_stress"), periodic=False, plane_stress=False,
                    dim=2)
    prm = probe_settings(material=standard_concrete(), rho0=RHO, spacing=delta,
                         effects=("elasticity", "artificial_stress"), av_alpha=1.0, av_beta=2.0,
                         as_epsilon=EPS).params(k)
    h = h_over_delta * delta
    r = r_over_delta * delta
    x = np.array([0.01, 0.01 + r * math.cos(0.4)])
    y = np.array([0.02, 0.02 + r * math.sin(0.4)])
    zero = np.zeros(2)
    m = np.full(2, RHO * delta**2)
    rst = np.array([tensor_2d(*rotated(2.0e6, -1.0e6, 0.7)), tensor_2d(3.0e6, 1.0e6, 0.4e6)])
    out = [np.zeros(2) for _ in range(6)]
    k.force_pass(x, y, zero, zero, zero, zero, m, np.full(2, RHO), np.full(2, h),
                 np.zeros((2, 4)), rst, np.array([0, 1, 2]), np.array([1, 0]), prm, *out)
    ax, ay = out[0], out[1]
    f4 = (cubic_shape(r / h) / cubic_shape(delta / h)) ** 4
    dwdr = kernel_dwdr(CUBIC, r, 2.0 * h, 2)
    gx, gy = dwdr * (x[0] - x[1]) / r, dwdr * (y[0] - y[1]) / r
    rs = rst[0] + rst[1]
    exp_x = m[1] * f4 * (rs[0] * gx + rs[2] * gy)
    exp_y = m[1] * f4 * (rs[2] * gx + rs[1] * gy)
    assert abs(exp_x) + abs(exp_y) > 0.0
    assert ax[0] == pytest.approx(exp_x, rel=1e-12)
    assert ay[0] == pytest.approx(exp_y, rel=1e-12)
    assert ax[1] == pytest.approx(-ax[0], rel=1e-12)
    assert ay[1] == pytest.approx(-ay[0], rel=1e-12)


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
