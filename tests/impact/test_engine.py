"""The impact engine. Checks 3, 4, 5, 8 (spec section 10): conservation with zero masses, wave
speeds, Benz invariance, artificial stress against clumping (small sizes); checks 3, 4, 5, 9, 10
and 11 in 3D; the plane stress option; no subnormal stalls (one section each below)."""

import dataclasses
import functools
import math

import numba
import numpy as np
import pytest

from craquelure.impact import analysis, api
from craquelure.impact.api import initial_state, settings, simulate
from craquelure.impact.effects.artificial_stress import auto_epsilon
from craquelure.impact.engine import Engine, Settings, State, kernels_for
from craquelure.impact.initial_state import build_specimen
from craquelure.impact.material import standard_concrete
from craquelure.scene import load_scene
from craquelure.sph.kernels import CUBIC, kernel_dwdr_array
from tests.impact.test_api import states_by_threads

NO_CONTACT = ("[elasticity, plasticity, damage, artificial_viscosity, artificial_stress, "
              "variable_smoothing_length]")
MAT = standard_concrete()


def small_scene(*overrides):
    return load_scene("impact/default", ["particles.diameter_cells=16", *overrides])


def test_momentum_conserved_with_zero_masses_translation_and_spin():
    scene = small_scene("particles.masses.distribution=poisson", f"effects={NO_CONTACT}")
    sp = build_specimen(scene, 3)
    assert (sp.mass == 0).any()
    st = initial_state(scene, sp)
    rng = np.random.default_rng(0)
    omega = 400.0  # rad/s: rim speed 32 m/s
    xc, yc = sp.x.mean(), sp.y.mean()
    st.vx[:] = rng.normal(0, 5) - omega * (st.y - yc)
    st.vy[:] = rng.normal(0, 5) + omega * (st.x - xc)
    eng = Engine(settings(scene), st)
    p0 = np.array(eng.momentum())
    scale = float(np.dot(st.m, np.hypot(st.vx, st.vy)))
    for _ in range(2000):
        eng.step()
    eng.check()
    p1 = np.array(eng.momentum())
    assert np.abs(p1 - p0).max() < 1e-12 * scale
    zero = np.flatnonzero(st.m == 0)
    massive = np.flatnonzero(st.m > 0)
    for i in zero:
        d = np.hypot(st.x[massive] - st.x[i], st.y[massive] - st.y[i])
        assert d.min() < 2 * st.h[i]


def periodic_block(nx, ny, spacing=0.004, effects=("elasticity", "artificial_viscosity",
                                                   "artificial_stress"), as_epsilon=0.3,
                   noise=0.0, seed=0, kappa=1.0, plane_stress=False):
    ix, iy = np.meshgrid(np.arange(nx), np.arange(ny), indexing="xy")
    x = (ix.ravel() + 0.5) * spacing
    y = (iy.ravel() + 0.5) * spacing
    rng = np.random.default_rng(seed)
    x = x + noise * spacing * rng.uniform(-1, 1, x.size)
    y = y + noise * spacing * rng.uniform(-1, 1, y.size)
    rho0 = 2400.0
    st = State.grid(x, y, 0.0, 0.0, np.full(x.size, rho0 * spacing**2), rho0,
                      kappa * 1.2 * spacing)
    s = Settings(material=MAT, rho0=rho0, spacing=spacing, effects=tuple(effects),
                 av_alpha=1.0, av_beta=2.0, as_epsilon=as_epsilon,
                 periodic_box=(nx * spacing, ny * spacing), plane_stress=plane_stress)
    return s, st


def front_position(x, v, level, x_max):
    """Largest x < x_max where the column-averaged profile v(x) still exceeds ``level``."""
    cols = np.rint(x / 0.004 - 0.5).astype(int)
    xs = np.unique(cols)
    prof = np.array([v[cols == c].mean() for c in xs])
    xs = (xs + 0.5) * 0.004
    above = np.flatnonzero((prof > level) & (xs < x_max))
    k = above.max()
    return xs[k] + (prof[k] - level) / (prof[k] - prof[k + 1]) * (xs[k + 1] - xs[k])


def front_speed(eng, x, v, v0, length):
    """Speed of the front (``front_position`` at 25 % of the step ``v0``) fitted from 15 to
    60 us; ``x`` and ``v`` are the engine's arrays (updated in place)."""
    times, fronts = [], []
    while eng.t < 60e-6:
        eng.step()
        if eng.t > 15e-6 and eng.step_count % 20 == 0:
            times.append(eng.t)
            fronts.append(front_position(x, v, 0.25 * v0, 0.55 * length))
    return np.polyfit(times, fronts, 1)[0]


@pytest.mark.parametrize("kind,expected", [("p", 3616.0), ("s", 2320.0)])
def test_wave_speeds_plane_strain(kind, expected):
    nx, ny, spacing = 240, 6, 0.004
    s, st = periodic_block(nx, ny, spacing, as_epsilon=0.0)
    v0 = 0.1
    step = st.x < 0.2 * nx * spacing  # fronts: right one at 0.2 L + ct, left one wraps
    (st.vx if kind == "p" else st.vy)[step] = v0
    eng = Engine(s, st)
    speed = front_speed(eng, st.x, st.vx if kind == "p" else st.vy, v0, nx * spacing)
    assert speed == pytest.approx(expected, rel=0.03)


@pytest.mark.parametrize("rate", [2000.0, -2000.0])
def test_benz_h_rho_invariant(rate):
    scene = small_scene(f"effects={NO_CONTACT}")
    sp = build_specimen(scene, 0)
    st = initial_state(scene, sp)
    xc, yc = sp.x.mean(), sp.y.mean()
    st.vx[:] = rate * (st.x - xc)
    st.vy[:] = rate * (st.y - yc)
    eng = Engine(settings(scene), st)
    inv0 = st.h * np.sqrt(st.rho)
    eng.step()
    # interior particles follow the imposed uniform volume change: d ln rho/dt = -2 rate
    # (first step only: stresses then change the velocity field)
    inner = np.hypot(sp.x - xc, sp.y - yc) < 0.4 * sp.radius
    assert np.log(st.rho[inner] / 2400.0) / eng.t == pytest.approx(-2 * rate, rel=0.02)
    for _ in range(60):
        eng.step()
    eng.check()
    assert np.abs(st.h / st.h0 - 1).max() > 5e-3  # h really changed, before the clamp
    assert (st.h > 0.2 * st.h0).all() and (st.h < 2.0 * st.h0).all()
    assert st.h * np.sqrt(st.rho) == pytest.approx(inv0, rel=1e-6)


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
            eng.check()
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


# -- 3D ------------------------------------------------------------------------------------
# Spec checks 3, 4, 5, 9, 10 and 11 in 3D (domain.dim 3, issue 16): momentum with zero masses
# under translation and spin, P and S wave speeds, Benz h rho^(1/3) invariance, the elastic disc's
# contact (impulse, penetration, restitution, energy), zero masses on the base, mirror symmetry
# of the homogeneous disc. Coarse 3D discs (10-20 cells across, 3-4 layers) keep them cheap: each
# property is a local one that does not need the source's 40 x 8 resolution.
DELTA = 0.004


def small_disc(*overrides, cells=10, layers=4):
    return load_scene("impact/disc3d", [f"particles.diameter_cells={cells}",
                                        f"particles.thickness_cells={layers}", *overrides])


def test_momentum_conserved_with_zero_masses_translation_and_spin_3d():
    """Check 3 in 3D: Poisson-like masses with exact zeros, contact off, a random translation
    and a spin about a tilted axis (rim speed ~20 m/s), 2000 steps: sum m v constant to
    1e-12 of sum m |v|; no NaN; every zero mass stays within 2h of a massive particle."""
    scene = small_disc("particles.masses.distribution=poisson", f"effects={NO_CONTACT}")
    sp = build_specimen(scene, 3)
    assert (sp.mass == 0).any()
    st = initial_state(scene, sp)
    rng = np.random.default_rng(0)
    omega = np.array([150.0, -200.0, 400.0])  # rad/s
    rel = np.column_stack([st.x - sp.x.mean(), st.y - sp.y.mean(), st.z - sp.z.mean()])
    v = rng.normal(0, 5, 3) + np.cross(omega, rel)
    st.vx[:], st.vy[:], st.vz[:] = v.T
    eng = Engine(settings(scene), st)
    p0 = np.array(eng.momentum())
    assert p0.size == 3
    scale = float(np.dot(st.m, np.linalg.norm(v, axis=1)))
    for _ in range(2000):
        eng.step()
    eng.check()
    p1 = np.array(eng.momentum())
    assert np.abs(p1 - p0).max() < 1e-12 * scale
    pos = np.column_stack([st.x, st.y, st.z])
    massive = st.m > 0
    for i in np.flatnonzero(st.m == 0):
        assert np.linalg.norm(pos[massive] - pos[i], axis=1).min() < 2 * st.h[i]


def periodic_block_3d(nx, ny, nz, effects=("elasticity",), as_epsilon=0.0):
    g = np.meshgrid(np.arange(nx), np.arange(ny), np.arange(nz), indexing="ij")
    x, y, z = ((a.ravel() + 0.5) * DELTA for a in g)
    rho0 = 2400.0
    st = State.grid(x, y, 0.0, 0.0, np.full(x.size, rho0 * DELTA**3), rho0, 1.2 * DELTA, z=z)
    s = Settings(material=MAT, rho0=rho0, spacing=DELTA, effects=tuple(effects),
                 av_alpha=1.0, av_beta=2.0, as_epsilon=as_epsilon,
                 periodic_box=(nx * DELTA, ny * DELTA, nz * DELTA), dim=3)
    return s, st


def lattice_gradient_factor_3d(kappa):
    """g = -sum_j V_j x_ij dW/dx_i on the unit cubic lattice (exact 1): a long wave travels at
    g c (the SPH gradient without correction, at fixed h/Delta; 2D: 0.9908 at kappa = 1)."""
    support = 2.4 * kappa
    n = int(np.ceil(support))
    g = np.arange(-n, n + 1)
    pts = np.array(np.meshgrid(g, g, g)).reshape(3, -1).T.astype(float)
    r = np.linalg.norm(pts, axis=1)
    inside = (r > 0) & (r < support)
    dwdr = kernel_dwdr_array(CUBIC, r[inside], support, 3)
    return float(-np.sum(pts[inside, 0] ** 2 * dwdr / r[inside]))


@pytest.mark.parametrize("kind,expected", [("p", 3616.0), ("s", 2320.0)])
def test_wave_speeds_3d(kind, expected):
    """Check 4 in 3D: the fundamental P (v_x) and S (v_z) modes of a periodic 40 x 5 x 5 elastic
    bar, v = v0 sin(kx), kappa = 1 (laterally periodic: uniaxial strain, so P runs at
    sqrt((K + 4G/3)/rho) = 3616 m/s, not the bar speed); omega from two zero crossings of the
    modal amplitude, c = omega/k within 3 % (the spec's tolerance). The SPH gradient's lattice
    factor is g = 0.982 in 3D at h = 1.2 Delta (0.991 in 2D), so long waves run 1.8 % slow;
    the mode at k Delta = 2 pi/40 adds its dispersion (P measured 2026-12-01: 3532 m/s, -2.3 %,
    0.5 % below g c_p), bounded here by 1 % below g c. A step front
    tracked at 25 % of its height (the 2D test's method) is biased by the step's short waves
    here: 3548 / 2247 m/s with the artificial viscosity, 3500 / 2271 m/s without."""
    nx = 40
    s, st = periodic_block_3d(nx, 5, 5)
    k = 2 * np.pi / (nx * DELTA)
    v = st.vx if kind == "p" else st.vz
    v[:] = 0.01 * np.sin(k * st.x)
    weight = st.m * np.sin(k * st.x)
    eng = Engine(s, st)
    crossings, prev_t, prev_a = [], 0.0, 1.0
    while len(crossings) < 2:
        eng.step()
        a = float(np.dot(weight, v))
        if (a < 0.0) != (prev_a < 0.0):
            crossings.append(prev_t + (eng.t - prev_t) * prev_a / (prev_a - a))
        prev_t, prev_a = eng.t, a
        assert eng.t < 4 * np.pi / (k * expected * 0.9)
    speed = np.pi / (crossings[1] - crossings[0]) / k
    assert speed == pytest.approx(expected, rel=0.03)
    assert 0.99 < speed / (lattice_gradient_factor_3d(1.0) * expected) <= 1.0
    # kinetic + internal energy conserved up to the leapfrog's error
    assert abs(eng.balance_error()) < 1e-3


@pytest.mark.parametrize("rate", [2000.0, -2000.0])
def test_benz_h_rho_invariant_3d(rate):
    """Check 5 in 3D: uniform expansion / compression; d ln rho/dt = -3 rate in the interior on
    the first step, and h rho^(1/3) constant to 1e-6 for every particle (h changes > 0.5 %)."""
    scene = small_disc(f"effects={NO_CONTACT}", cells=12, layers=5)
    sp = build_specimen(scene, 0)
    st = initial_state(scene, sp)
    c = np.array([sp.x.mean(), sp.y.mean(), sp.z.mean()])
    st.vx[:] = rate * (st.x - c[0])
    st.vy[:] = rate * (st.y - c[1])
    st.vz[:] = rate * (st.z - c[2])
    eng = Engine(settings(scene), st)
    inv0 = st.h * np.cbrt(st.rho)
    eng.step()
    inner = np.hypot(sp.x - c[0], sp.y - c[1]) < 0.3 * sp.radius
    inner &= np.abs(sp.z - c[2]) < 0.5 * DELTA
    assert inner.any()
    assert np.log(st.rho[inner] / 2400.0) / eng.t == pytest.approx(-3 * rate, rel=0.02)
    for _ in range(60):
        eng.step()
    eng.check()
    # h really changed (by ~0.5 %: a third of the volume change, against half in 2D), far
    # beyond the invariant's tolerance
    assert np.abs(st.h / st.h0 - 1).max() > 2e-3
    assert st.h * np.cbrt(st.rho) == pytest.approx(inv0, rel=1e-6)


def test_elastic_disc_contact_3d():
    """Check 9 in 3D (bulk formula, half-cell stiffness): an elastic 16-cell disc, 3 layers, at
    1 m/s: the contact is over by 160 us, impulse = M (v_out - v_in) within 1 %, penetration
    < 0.2 Delta, restitution >= 0.8, energy balance within 2 %."""
    scene = small_disc("particles.impact_velocity=1.0", "particles.gap=0.0",
                       "outputs.t_end=1.6e-4", "outputs.series_dt=1.0e-6",
                       "outputs.snapshot_times=[]",
                       "effects=[elasticity, artificial_viscosity, contact_bulk]",
                       cells=16, layers=3)
    sp, eng, series, _ = simulate(scene, 0, progress=False)
    mass = sp.mass.sum()
    v_out = series["vcm_y"][-1]
    assert series["contact_force"][-1] == 0.0
    assert eng.impulse == pytest.approx(mass * (v_out + 1.0), rel=1e-2)
    assert eng.max_penetration < 0.2 * sp.spacing
    assert v_out >= 0.8
    assert np.abs(series["balance_error"]).max() < 0.02


FULL = ("[elasticity, plasticity, damage, artificial_viscosity, artificial_stress, "
        "variable_smoothing_length, contact_bulk]")


def zero_mass_run(contact):
    """Poisson-like masses and the PF#1 zero-mass plane on a 16-cell, 3-layer disc, kappa = 1,
    15 m/s, 0.15 ms (as in 2D), with the given contact effect; the first seed with a zero mass
    in the bottom row. Returns (specimen, engine, zero masses of the bottom row)."""
    scene = small_disc("particles.masses.distribution=poisson", "particles.precrack=pf1",
                       "outputs.t_end=1.5e-4", "outputs.snapshot_times=[]",
                       f"effects={FULL.replace('contact_bulk', contact)}", cells=16, layers=3)

    def bottom_zeros(sp):
        return (sp.mass == 0) & (sp.y <= sp.y.min() + 0.5 * sp.spacing)

    seed = next(s for s in range(100) if bottom_zeros(build_specimen(scene, s)).any())
    sp, eng, _, _ = simulate(scene, seed, progress=False)
    return sp, eng, bottom_zeros(sp)


def test_zero_masses_safe_with_bulk_contact_3d():
    """Check 10 in 3D: Poisson-like masses and the PF#1 zero-mass plane, kappa = 1, 15 m/s,
    bulk contact with the kinematic fallback: no NaN, no particle below r_c - 0.5 Delta; the
    zero masses that reach the base are held at the kinematic floor r_c - 0.05 Delta."""
    sp, eng, reached = zero_mass_run("contact_bulk")
    st = eng.state
    assert (sp.mass[sp.precrack] == 0).all() and sp.precrack.sum() == 3 * 8
    assert all(np.isfinite(a).all() for a in (st.x, st.y, st.z, st.sig))
    assert st.y.min() >= 0.0  # r_c - 0.5 Delta = 0
    assert reached.any()
    assert (st.y[reached] >= 0.45 * sp.spacing * (1 - 1e-12)).all()


def test_zero_masses_fall_through_with_mass_contact_3d():
    """Check 10's documented failure mode in 3D: with k = a m / dt^2 the zero masses that reach
    the base get no force and end below it; the massive particles do not."""
    sp, eng, reached = zero_mass_run("contact_mass")
    st = eng.state
    assert reached.any()
    assert (st.y[reached] < 0.0).all()
    assert st.y[sp.mass > 0].min() > 0.0


def test_homogeneous_disc_damage_is_mirror_symmetric_3d():
    """Check 11 in 3D: the homogeneous 20-cell disc, 4 layers, at 15 m/s: D_t mirror-symmetric
    about x = 0 and about the mid-plane z = 0 within 0.05 up to 50 us, with damage started."""
    scene = small_disc("outputs.t_end=5.0e-5", "outputs.snapshot_times=[]", cells=20, layers=4)
    sp, eng, _, _ = simulate(scene, 0, progress=False)
    ix = np.rint(2 * sp.x / DELTA).astype(int)
    iy = np.rint((sp.y - sp.y.min()) / DELTA).astype(int)
    iz = np.rint(2 * sp.z / DELTA).astype(int)
    key = {k: i for i, k in enumerate(zip(ix, iy, iz, strict=True))}
    d = eng.state.dmg
    assert d.max() > 0.1
    for mirror in ([key[(-a, b, c)] for a, b, c in zip(ix, iy, iz, strict=True)],
                   [key[(a, b, -c)] for a, b, c in zip(ix, iy, iz, strict=True)]):
        assert np.abs(d - d[np.array(mirror)]).max() <= 0.05


@pytest.mark.skipif(numba.config.NUMBA_NUM_THREADS < 2, reason="needs 2 numba threads")
def test_3d_run_is_independent_of_the_thread_count():
    """The tiny 3D CI disc with uniform masses, 1 and 2 threads: bit-identical fields (gather
    loops in a fixed neighbour order; the k-d tree's rows are sorted; the artificial-stress
    pass is per particle)."""
    scene = load_scene("impact/ci3d", ["particles.masses.distribution=uniform",
                                       "outputs.t_end=5.0e-5", "outputs.snapshot_times=[]"])
    out = states_by_threads(scene, 3)
    for key in ("x", "y", "z", "vx", "vy", "vz", "rho", "h", "sig", "dmg"):
        assert np.array_equal(getattr(out[0], key), getattr(out[1], key)), key



# -- plane stress --------------------------------------------------------------------------
# Plane stress option (``domain.plane: stress``; impact spec open doubt 5 and check 4's plane
# stress figure): sigma_zz stays zero through the trial and the Drucker-Prager return.
def test_plane_stress_p_wave_speed():
    """Check 4's plane-stress value: P front at sqrt(E/((1 - nu^2) rho)) = 3559 m/s within 3 %
    (plane strain: 3616 m/s, test_wave_speeds_plane_strain)."""
    nx, ny, spacing, v0 = 240, 6, 0.004, 0.1
    s, st = periodic_block(nx, ny, spacing, as_epsilon=0.0, plane_stress=True)
    assert s.wave_speed == pytest.approx(3559.0, rel=2e-3)
    st.vx[st.x < 0.2 * nx * spacing] = v0
    eng = Engine(s, st)
    times, fronts = [], []
    while eng.t < 60e-6:
        eng.step()
        if eng.t > 15e-6 and eng.step_count % 20 == 0:
            times.append(eng.t)
            fronts.append(front_position(st.x, st.vx, 0.25 * v0, 0.55 * nx * spacing))
    assert np.polyfit(times, fronts, 1)[0] == pytest.approx(3559.0, rel=0.03)
    assert np.abs(st.sig[:, 3]).max() == 0.0


def _cone(sig):
    """Drucker-Prager f = sqrt(J2) + alpha I1 - k per particle (plane stress: zz = 0)."""
    alpha, k = MAT.dp
    i1 = sig[:, 0] + sig[:, 1] + sig[:, 3]
    m = i1 / 3.0
    j2 = 0.5 * ((sig[:, 0] - m) ** 2 + (sig[:, 1] - m) ** 2 + (sig[:, 3] - m) ** 2) \
        + sig[:, 2] ** 2
    return np.sqrt(j2) + alpha * i1 - k, i1


def test_plane_stress_dzz_solves_the_plastic_return():
    """The out-of-plane rate found by the secant iteration leaves |sigma_zz| <= 1e-9 of the
    stress scale after trial + return, for states far beyond the cone (uniaxial and biaxial
    compression rates up to 1e4 1/s, shear, spin); the returned stress is on the cone."""
    mod = kernels_for(("elasticity", "plasticity"), plane_stress=True)
    prm = np.zeros(mod.N_PARAMS)
    prm[mod.P_BULK], prm[mod.P_SHEAR] = MAT.bulk, MAT.shear
    prm[mod.P_ALPHA_DP], prm[mod.P_K_DP] = MAT.dp
    rng = np.random.default_rng(1)
    dt = 2e-7
    returned = 0
    for _ in range(200):
        s0 = rng.uniform(-40e6, 5e6, 3)  # xx, yy, xy (zz = 0)
        dxx, dyy, dxy = rng.uniform(-1e4, 2e3, 3)
        w = rng.uniform(-1e3, 1e3)
        d = mod.plane_stress_dzz(s0[0], s0[1], s0[2], 0.0, 0.0, 0.0, dxx, dyy, dxy, w, dt,
                                 prm)
        trial = mod.jaumann_trial((s0[0], s0[1], s0[2], 0.0, 0.0, 0.0),
                                  (dxx, dyy, dxy, d, 0.0, 0.0), (w, 0.0, 0.0), MAT.bulk,
                                  MAT.shear, dt)
        out = np.array([mod.dp_return(trial, *MAT.dp, MAT.shear)[0][:4]])
        assert abs(out[0, 3]) <= 1e-9 * (np.abs(s0).sum() + MAT.dp[1]) * 1.0001
        f, i1 = _cone(out)
        if i1[0] < 0:
            assert f[0] <= 1e-6 * MAT.dp[1]
        returned += int(mod.dp_return(trial, *MAT.dp, MAT.shear)[1] > 0)
    assert returned > 50  # most samples really went through the plastic branch


def test_plane_stress_disc_impact_stays_on_the_cone():
    """Full effect set, 20-cell disc at 15 m/s, 0.15 ms in plane stress: no NaN (the run checks
    every 50 steps), sigma_zz = 0, every compressive particle inside the Drucker-Prager cone
    (a failed sigma_zz solve would leave it outside after zz is zeroed), energy balance < 2 %;
    the plane-stress disc is softer (c_p 3559 vs 3616 m/s), so its peak contact force is
    below the plane-strain one."""
    base = ["particles.diameter_cells=20", "outputs.t_end=1.5e-4", "outputs.snapshot_times=[]"]
    _, eng, series, _ = simulate(load_scene("impact/default", [*base, "domain.plane=stress"]),
                                 0, progress=False)
    f, i1 = _cone(eng.state.sig)
    assert np.abs(eng.state.sig[:, 3]).max() == 0.0
    assert f[i1 < 0].max() <= 1e-6 * MAT.dp[1]
    assert np.abs(series["balance_error"]).max() < 0.02
    assert eng.state.epsp.max() > 0  # the return was active
    _, strain, _, _ = simulate(load_scene("impact/default", base), 0, progress=False)
    assert eng.force_peak < strain.force_peak
    assert math.isfinite(eng.force_peak)


def test_plane_stress_scene_is_the_default_scene_in_plane_stress():
    """impact/plane_stress (the campaign scene of the README's plane-stress comparison) differs
    from impact/default in domain.plane and the description only, so the comparison isolates
    the 2D idealisation."""
    default = load_scene("impact/default").data
    stress = load_scene("impact/plane_stress").data
    assert default["domain"]["plane"] == "strain" and stress["domain"]["plane"] == "stress"
    for data in (default, stress):
        data.pop("description")
        data["domain"].pop("plane")
    assert stress == default


# -- subnormals ----------------------------------------------------------------------------
# No subnormal stalls: the impact kernels flush accelerations, stresses and pair powers below
# ``Settings.flush_below`` (1e-100 SI) where they are produced, and the results do not change.
TINY = np.finfo(float).tiny


def subnormals(eng: Engine) -> int:
    st = eng.state
    arrays = (st.vx, st.vy, st.sig, st.nom, st.eint, st.eel, eng.ax, eng.ay, eng.pav, eng.pas)
    return sum(int(np.sum((a != 0) & (np.abs(a) < TINY))) for a in arrays)


def column_engine(flush: float) -> Engine:
    """A 4 x 300-cell column on the base: the precursor ahead of the compression wave crosses
    ~100 neighbour shells and goes subnormal after about 180 steps."""
    scene = load_scene("impact/ci", ["particles.shape=rectangle", "particles.diameter_cells=4",
                                     "particles.height_cells=300"])
    sp = build_specimen(scene, 0)
    return Engine(dataclasses.replace(settings(scene), flush_below=flush),
                  initial_state(scene, sp))


def test_flushing_removes_the_subnormals_and_changes_nothing_else():
    plain, flushed = column_engine(0.0), column_engine(1e-100)
    seen = 0
    for _ in range(240):
        plain.step()
        flushed.step()
        seen = max(seen, subnormals(plain))
        assert subnormals(flushed) == 0
    assert seen > 50  # the case does make subnormals without the flush
    for key, value in plain.energies().items():
        assert flushed.energies()[key] == pytest.approx(value, rel=1e-12, abs=1e-12), key
    for name in ("x", "y", "vx", "vy", "rho", "sig"):
        np.testing.assert_allclose(getattr(flushed.state, name), getattr(plain.state, name),
                                   rtol=1e-12, atol=1e-12 * np.abs(getattr(plain.state, name))
                                   .max())


def test_default_run_summary_equal_with_and_without_the_flush(monkeypatch):
    """The CI scene run end to end (its series and every run metric) with the default flush and
    with none: equal to round-off."""
    scene = load_scene("impact/ci")
    runs = {}
    for flush in (1e-100, 0.0):
        def patched(sc, flush=flush):
            return dataclasses.replace(settings(sc), flush_below=flush)

        monkeypatch.setattr(api, "settings", patched)
        sp, eng, series, snaps = api.simulate(scene, 0, progress=False)
        runs[flush] = api.run_dataset(scene, 0, sp, eng, series, snaps)
        # what write_run adds: the stored scene and the runner's step count
        runs[flush].attrs.update(scene=scene.text, run_steps=eng.step_count)
    a, b = runs[1e-100], runs[0.0]
    ma, mb = analysis.run_metrics(a), analysis.run_metrics(b)
    assert ma["steps"] == mb["steps"]
    assert a.attrs["run_dt_min"] == pytest.approx(b.attrs["run_dt_min"], rel=1e-10)
    for key, value in mb.items():
        if isinstance(value, float):
            assert ma[key] == pytest.approx(value, rel=1e-10, abs=1e-12), key
        else:
            assert ma[key] == value, key
    for name in b.data_vars:
        if name.startswith("series_"):
            np.testing.assert_allclose(a[name].values, b[name].values, rtol=1e-10,
                                       atol=1e-12 * float(np.abs(b[name].values).max() or 1))
