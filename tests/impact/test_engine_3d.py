"""Spec checks 3, 4, 5, 9, 10 and 11 in 3D (domain.dim 3, issue 16): momentum with zero masses
under translation and spin, P and S wave speeds, Benz h rho^(1/3) invariance, the elastic disc's
contact (impulse, penetration, restitution, energy), zero masses on the base, mirror symmetry
of the homogeneous disc. Coarse 3D discs (10-20 cells across, 3-4 layers) keep them cheap: each
property is a local one that does not need the source's 40 x 8 resolution."""

import numba
import numpy as np
import pytest

from craquelure.impact.api import initial_state, probe_settings, settings, simulate
from craquelure.impact.engine import Engine, State
from craquelure.impact.initial_state import build_specimen
from craquelure.impact.material import standard_concrete
from craquelure.scene import load_scene
from craquelure.sph.kernels import CUBIC, kernel_dwdr_array
from tests.impact.test_api import states_by_threads

NO_CONTACT = ("[elasticity, plasticity, damage, artificial_viscosity, artificial_stress, "
              "variable_smoothing_length]")
MAT = standard_concrete()
DELTA = 0.004


def small_disc(*overrides, cells=10, layers=4):
    return load_scene("impact/disc3d", [f"particles.diameter_cells={cells}",
                                        f"particles.thickness_cells={layers}", *overrides])


def test_momentum_conserved_with_zero_masses_translation_and_spin():
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


def periodic_block(nx, ny, nz, effects=("elasticity",), as_epsilon=0.0):
    g = np.meshgrid(np.arange(nx), np.arange(ny), np.arange(nz), indexing="ij")
    x, y, z = ((a.ravel() + 0.5) * DELTA for a in g)
    rho0 = 2400.0
    st = State.grid(x, y, 0.0, 0.0, np.full(x.size, rho0 * DELTA**3), rho0, 1.2 * DELTA, z=z)
    s = probe_settings(material=MAT, rho0=rho0, spacing=DELTA, effects=tuple(effects),
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
    s, st = periodic_block(nx, 5, 5)
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
