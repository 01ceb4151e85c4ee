"""The impact engine. Checks 3 and 4 (spec section 10): conservation with zero masses, wave
speeds (small sizes); checks 3, 4, 9, 10 and 11 in 3D; the plane stress option (one section
each below). Check 5 is in effects/test_variable_smoothing_length.py, check 8 in
effects/test_artificial_stress.py."""

import math

import numba
import numpy as np
import pytest

from craquelure.impact.api import initial_state, probe_settings, settings
from craquelure.impact.engine import Engine, State, kernels_for
from craquelure.impact.initial_state import build_specimen
from craquelure.impact.material import standard_concrete
from craquelure.scene import load_scene
from craquelure.sph.kernels import CUBIC, kernel_dwdr_array
from tests.impact.runs import simulate
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
    eng.check_health()
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
    eng.check_health()
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
    mod = kernels_for(("elasticity", "plasticity"), periodic=False, plane_stress=True, dim=2)
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
