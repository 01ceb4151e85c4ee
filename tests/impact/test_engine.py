"""Checks 3, 4, 5, 8 (spec section 10): conservation with zero masses, wave speeds, Benz
invariance, artificial stress against clumping. Small sizes."""

import functools
import math

import numpy as np
import pytest

from craquelure.impact.api import initial_state, probe_settings, settings
from craquelure.impact.effects.artificial_stress import auto_epsilon
from craquelure.impact.engine import Engine, State
from craquelure.impact.initial_state import build_specimen
from craquelure.impact.material import standard_concrete
from craquelure.scene import load_scene

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
    s = probe_settings(material=MAT, rho0=rho0, spacing=spacing, effects=tuple(effects),
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
