"""Monaghan / Gray-Monaghan-Swift artificial stress (spec section 3): the tensor R_i from the
principal tensile components of the total nominal stress, and the pair term f_ij^n (R_i + R_j)
with f_ij = W(r_ij; h_ij)/W(Delta; h_ij), Delta the initial spacing (not h, not the current
spacing), as the compiled force pass applies it; check 8 (spec section 10): the artificial
stress against clumping in a block under tension, and the automatic epsilon."""

import functools
import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from craquelure.impact.api import probe_settings
from craquelure.impact.effects.artificial_stress import artificial_stress_tensor, auto_epsilon
from craquelure.impact.engine import Engine, kernels_for
from craquelure.impact.material import standard_concrete
from craquelure.sph.kernels import CUBIC, kernel_dwdr
from tests.impact.test_engine import MAT, periodic_block

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
                         as_epsilon=EPS).params()
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


def tension_block(nx, as_epsilon, effects=("elasticity", "artificial_viscosity",
                                           "artificial_stress"), noise=0.0, frozen=False,
                  kappa=1.0):
    """Periodic block in biaxial tension 0.8 f_t, plane strain (sigma_zz = 2 nu t), at rest."""
    s, st = periodic_block(nx, nx, effects=effects, as_epsilon=as_epsilon, noise=noise,
                           kappa=kappa)
    tension = 0.8 * MAT.f_t
    st.sig[:, 0] = st.sig[:, 1] = st.nom[:, 0] = st.nom[:, 1] = tension
    st.sig[:, 3] = st.nom[:, 3] = 2 * MAT.poisson * tension
    eng = FrozenArtificialStress(s, st, tension) if frozen else Engine(s, st)
    return s, st, eng


def project_epsilon(kappa):
    """eps_AS of ``numerics.as_epsilon: auto`` at this kappa (h(0) = 1.2 kappa Delta)."""
    return auto_epsilon(1.2 * kappa)


@functools.cache
def clumping_run(as_epsilon, frozen=False, kappa=1.0):
    """Check 8 run: (min pair distance / Δ over the run, max rms velocity in steps 100-500 after
    the release of the 1 % noise, rms velocity at step 2000, stress std at 500 and 2000)."""
    s, st, eng = tension_block(16, as_epsilon, noise=0.01, frozen=frozen, kappa=kappa)
    early = 0.0
    min_dist = np.inf
    sig_early = 0.0
    for n in range(2000):
        eng.step()
        rms = math.sqrt(float(np.mean(st.vx**2 + st.vy**2)))
        if 100 <= n <= 500:
            early = max(early, rms)
        if n == 500:
            sig_early = float(st.sig[:, 0].std())
        if n % 100 == 0 or n == 1999:
            eng.check_health()
            dx = st.x[:, None] - st.x[None, :]
            dy = st.y[:, None] - st.y[None, :]
            dx -= s.periodic_box[0] * np.rint(dx / s.periodic_box[0])
            dy -= s.periodic_box[1] * np.rint(dy / s.periodic_box[1])
            d = np.hypot(dx, dy)
            np.fill_diagonal(d, np.inf)
            min_dist = min(min_dist, d.min())
    return min_dist / s.spacing, early, rms, sig_early, float(st.sig[:, 0].std())


@pytest.mark.parametrize("kappa", [0.7, 1.0, 1.5])
def test_artificial_stress_check8(kappa, capsys):
    """Check 8 at the project's eps_AS (``auto``: 0.2 / 0.15 / 0 at kappa = 0.7 / 1 / 1.5; the
    decision is documented in craquelure.impact.effects.artificial_stress): the minimum pair
    distance stays >= 0.7 Delta and the rms velocity at step 2000 is not above its maximum over
    steps 100-500 (the transient of the released 1 % position noise). Measured: 0.98 Delta
    and x0.58 / x0.57 / x0.36."""
    eps = project_epsilon(kappa)
    dmin, early, final, sig_early, sig_final = clumping_run(eps, kappa=kappa)
    with capsys.disabled():
        print(f"\n[check 8] kappa = {kappa}, eps_AS = {eps}: min distance {dmin:.3f} Delta, rms "
              f"velocity {early:.3g} -> {final:.3g} m/s (x{final / early:.2f}), stress std "
              f"{sig_early:.3g} -> {sig_final:.3g} Pa")
    assert dmin >= 0.7
    assert final <= early


def test_check8_reported_without_and_with_spec_epsilon(capsys):
    """Check 8's report of the eps_AS = 0 run, and the spec's eps_AS = 0.3 at kappa = 1, the
    reason for the decision: both keep the pairs apart (0.98 Delta), but with 0.3 the velocity
    noise grows (measured x2.2, stress std 0.24 -> 0.97 MPa) where 0 decays (x0.30)."""
    dmin0, e0, f0, _, _ = clumping_run(0.0)
    dmin3, e3, f3, s3, s3f = clumping_run(0.3)
    with capsys.disabled():
        print(f"\n[check 8] kappa = 1: eps_AS = 0: min distance {dmin0:.3f} Delta, rms velocity "
              f"{e0:.3g} -> {f0:.3g} m/s; eps_AS = 0.3: {dmin3:.3f} Delta, {e3:.3g} -> "
              f"{f3:.3g} m/s (x{f3 / e3:.2f}), stress std {s3:.3g} -> {s3f:.3g} Pa")
    assert dmin0 >= 0.7 and dmin3 >= 0.7
    assert f0 <= e0
    assert f3 > 1.5 * e3


def test_frozen_artificial_stress_noise_decays(capsys):
    """Mechanism of the growth at eps_AS = 0.3 (kappa = 1): the same check 8 run with R_i
    frozen at the value of the uniform tension (Monaghan's repulsion without its response to
    the stress fluctuations) lets the noise decay (measured x0.35, eps_AS = 0: x0.30) and
    still keeps the pairs apart (>= 0.7 Delta)."""
    dmin, early, final, sig_early, sig_final = clumping_run(0.3, frozen=True)
    with capsys.disabled():
        print(f"\n[check 8] eps_AS = 0.3, R frozen: rms velocity {early:.3g} -> {final:.3g} m/s "
              f"(x{final / early:.2f}), stress std {sig_early:.3g} -> {sig_final:.3g} Pa, "
              f"min distance {dmin:.3f} Delta")
    assert final <= early
    assert dmin >= 0.7


def one_step_growth(as_epsilon, frozen=False, nx=8, kappa=1.0):
    """Largest |eigenvalue| of the Jacobian of one leapfrog step about the uniform biaxial
    tension 0.8 f_t (elasticity + artificial stress, no AV, whose switch at v_ij . r_ij = 0 has
    no derivative), by central differences; returns (growth rate 1/s, wavevector of the
    fastest mode's v_x in units of pi/Delta)."""
    s, st, eng = tension_block(nx, as_epsilon, ("elasticity", "artificial_stress"),
                               frozen=frozen, kappa=kappa)
    dt = eng.dt
    n = st.x.size

    def pack():
        return np.concatenate([st.x, st.y, st.vx, st.vy, *st.sig.T, st.rho])

    def step_map(z):
        st.x[:], st.y[:], st.vx[:], st.vy[:] = z[:4 * n].reshape(4, n)
        st.sig[:] = z[4 * n:8 * n].reshape(4, n).T
        st.nom[:] = st.sig
        st.rho[:] = z[8 * n:]
        eng._neighbours(force=True)
        eng._forces(dt)
        eng.step(dt)
        return pack()

    z0 = pack().copy()
    scale = np.repeat([1e-7 * s.spacing, 1e-7 * s.spacing, 1e-5, 1e-5, 10.0, 10.0, 10.0, 10.0,
                       1e-5], n)
    jac = np.empty((z0.size, z0.size))
    for j in range(z0.size):
        e = np.zeros(z0.size)
        e[j] = scale[j]
        jac[:, j] = (step_map(z0 + e) - step_map(z0 - e)) / (2.0 * scale[j])
    lam, vec = np.linalg.eig(jac)
    top = np.argmax(np.abs(lam))
    vx = np.abs(np.fft.fft2(vec[2 * n:3 * n, top].reshape(nx, nx)))  # [k_y, k_x]
    ky, kx = np.unravel_index(np.argmax(vx), vx.shape)
    wave = tuple(float(2.0 * min(k, nx - k) / nx) for k in (kx, ky))
    return math.log(abs(lam[top])) / dt, wave


def test_artificial_stress_linear_growth_mode(capsys):
    """Linear stability of the discrete scheme (the code itself, 8 x 8 periodic lattice) about
    biaxial tension 0.8 f_t: without AV, eps_AS = 0 has the tensile instability (measured
    1.4e4 1/s); Monaghan's repulsion alone (R frozen) slows it (6.0e3 1/s); the full AS with
    R_j following the stress is faster than no AS at all (4.7e4 1/s), its fastest mode being
    v_x with k Delta = (pi/2, pi) (the nearest-neighbour weight of the x-gradient, reduced by
    (1 - eps_AS f^4 = 0.7), no longer outweighs the diagonal ones of opposite sign at
    k_y Delta = pi: scalar estimate of the threshold eps_AS = 0.25)."""
    rate0, _ = one_step_growth(0.0)
    rate_frozen, _ = one_step_growth(0.3, frozen=True)
    rate, wave = one_step_growth(0.3)
    with capsys.disabled():
        print(f"\n[check 8] linear growth rates: eps_AS = 0 {rate0:.3g}, 0.3 frozen R "
              f"{rate_frozen:.3g}, 0.3 {rate:.3g} 1/s; fastest mode k Delta/pi = {wave}")
    assert rate_frozen < 0.7 * rate0
    assert rate > 2.0 * rate0
    assert wave == (0.5, 1.0)


@pytest.mark.parametrize("kappa", [0.7, 1.0, 1.5])
def test_auto_epsilon_minimises_linear_growth(kappa, capsys):
    """The decision behind ``as_epsilon: auto``: at each of the paper's supports the chosen
    eps_AS has a smaller linearised growth rate (8 x 8 lattice, 0.8 f_t biaxial tension, no AV)
    than eps_AS -/+ 0.05 and than the spec's 0.3; at kappa = 1.5 (nearest neighbour inside the
    kernel's inflection point) the scheme is neutral without AS (rate ~ 0) and AS only adds
    growth. Measured 1/s: kappa 0.7: 1.3e4 / 7.0e3 / 7.7e3 (0.15 / 0.2 / 0.25), 8.3e3 at 0.3;
    kappa 1: 8.7e3 (0.1) / 4.2e3 / 2.1e4 (0.2), 4.7e4 at 0.3; kappa 1.5: 0.26 (0) / 0.26
    (0.05), 4.1e3 (0.1), 1.5e4 at 0.3."""
    eps = project_epsilon(kappa)
    grid = sorted({max(eps - 0.05, 0.0), eps, eps + 0.05, 0.3})
    rates = {e: one_step_growth(e, kappa=kappa)[0] for e in grid}
    with capsys.disabled():
        print(f"\n[check 8] kappa = {kappa}: linear growth " + ", ".join(
            f"eps_AS {e:.2f}: {r:.3g}" for e, r in rates.items()) + " 1/s")
    others = [r for e, r in rates.items() if e != eps]
    # + 10 1/s: 'neutral' (a factor e^0.01 over the 1 ms impact); at kappa = 1.5 both 0 and 0.05
    # are neutral (0.26 and 0.26 1/s), growth starts between 0.05 and 0.1 (4.1e3 1/s)
    assert rates[eps] < min(others) + 10.0


class FrozenArtificialStress(Engine):
    """Diagnostic engine: R_i fixed at the value of the uniform initial stress ``tension`` for
    every particle (Monaghan's repulsion kept, its dependence on the stress fluctuations
    removed). Used only to isolate the mechanism of check 8's noise growth."""

    def __init__(self, settings, state, tension):
        self.r_frozen = -settings.as_epsilon * tension / settings.rho0**2
        super().__init__(settings, state)

    def _forces(self, dt):
        st, k = self.state, self.k
        self.rst[:, 0] = self.rst[:, 1] = self.r_frozen
        self.rst[:, 2] = 0.0
        k.force_pass(st.x, st.y, st.z, st.vx, st.vy, st.vz, st.m, st.rho, st.h, st.nom, self.rst,
                     self.offsets, self.index, self.prm, self.ax, self.ay, self.az, self.pav,
                     self.pas, self.mumax)
