"""Checks 1 and 2 (spec section 10): kernel normalisation and the mass sampling."""

import math

import numpy as np
import pytest
from scipy import integrate, stats
from scipy.spatial import cKDTree

from craquelure.errors import SceneError
from craquelure.impact.api import initial_state, settings
from craquelure.impact.engine import Engine
from craquelure.impact.initial_state import (
    build_specimen,
    draw_weights,
    grid,
    initial_smoothing_length,
    rings,
)
from craquelure.scene import load_scene
from craquelure.sph.kernels import CUBIC, kernel_w_array, w


@pytest.mark.parametrize("dim", [2, 3])
def test_cubic_kernel_has_unit_integral(dim):
    h = 1.3
    s = 2 * h
    shell = (lambda r: 2 * math.pi * r) if dim == 2 else (lambda r: 4 * math.pi * r * r)
    val, _ = integrate.quad(lambda r: w("cubic", np.array([r]), s, dim)[0] * shell(r), 0, s,
                            points=[h], epsabs=1e-14, epsrel=1e-13)
    assert val == pytest.approx(1.0, abs=1e-10)


def test_lattice_partition_of_unity_at_kappa_1():
    spacing = 1.0
    h = 1.2 * spacing
    ij = np.arange(-5, 6)
    gx, gy = np.meshgrid(ij, ij)
    r = np.hypot(gx, gy).ravel() * spacing
    total = kernel_w_array(CUBIC, r, 2 * h, 2).sum() * spacing**2
    assert total == pytest.approx(1.0, abs=1e-3)


def test_disc_has_1264_particles():
    x, _ = grid("disc", 40, 1, 0.004)
    assert x.size == 1264


SCENE = load_scene("impact/default")


@pytest.mark.parametrize("dist", ["uniform", "normal", "poisson"])
def test_masses_total_positive_mean_one_and_shape(dist):
    scene = SCENE.with_overrides([f"particles.masses.distribution={dist}"])
    homo = build_specimen(SCENE, 0)
    mbar = scene.get("material.rho0") * scene.get("particles.spacing") ** 2
    omegas = []
    for seed in range(20):
        sp = build_specimen(scene, seed)
        assert sp.mass.sum() == pytest.approx(homo.mass.sum(), rel=1e-12)
        assert (sp.mass >= 0).all()
        assert np.array_equal(sp.x, homo.x) and np.array_equal(sp.y, homo.y)
        omega = sp.mass / mbar
        assert omega.mean() == pytest.approx(1.0, rel=1e-12)
        omegas.append(omega)
        st = initial_state(scene, sp)
        assert (st.rho == scene.get("material.rho0")).all()
        assert st.h == pytest.approx(1.2 * 1.0 * 0.004, rel=1e-14)
    omega = np.concatenate(omegas)
    if dist == "uniform":
        p = stats.kstest(omega, stats.uniform(0, 2).cdf).pvalue
        # 0.5 % below 0.01 mbar (20 x 1264 draws: sd 0.044 %)
        assert np.mean(omega < 0.01) == pytest.approx(0.005, abs=0.002)
    elif dist == "normal":
        a = (0 - 1.0) / 0.3
        p = stats.kstest(omega, stats.truncnorm(a, np.inf, loc=1.0, scale=0.3).cdf).pvalue
    else:
        # m_i = k_i M / sum k: the smallest positive mass is k = 1 (P(k=1) = 7 %)
        k = np.concatenate([np.rint(o / o[o > 0].min()) for o in omegas]).astype(int)
        assert np.allclose(np.concatenate([o / o[o > 0].min() for o in omegas]), k, atol=1e-9)
        assert np.mean(k == 0) == pytest.approx(math.exp(-4.0), abs=0.004)
        counts = np.bincount(k, minlength=12)[:12]
        expected = stats.poisson(4.0).pmf(np.arange(12)) * k.size
        counts[-1] += (k >= 12).sum()
        expected[-1] += stats.poisson(4.0).sf(11) * k.size
        p = stats.chisquare(counts, expected * counts.sum() / expected.sum()).pvalue
    assert p > 0.01


@pytest.mark.parametrize("kappa", [0.7, 1.0, 1.5])
def test_initial_smoothing_length_is_kappa_1_2_spacing(kappa):
    scene = SCENE.with_overrides([f"numerics.kappa={kappa}"])
    assert initial_smoothing_length(scene) == pytest.approx(1.2 * kappa * 0.004)


@pytest.mark.parametrize("layout,expected_angle", [("pf1", 0.0), ("pf2", 30.0), ("pf3", 0.0)])
def test_precrack_layouts_are_zero_mass_lines(layout, expected_angle):
    from craquelure.impact.measure import principal_axis

    sp = build_specimen(SCENE.with_overrides([f"particles.precrack={layout}"]), 0)
    homo = build_specimen(SCENE, 0)
    assert (sp.mass[sp.precrack] == 0).all()
    assert np.array_equal(sp.mass[~sp.precrack], homo.mass[~sp.precrack])  # not renormalised
    extent, angle, _ = principal_axis(sp.x[sp.precrack], sp.y[sp.precrack])
    assert extent == pytest.approx(sp.radius, abs=2 * sp.spacing)  # length R
    assert angle == pytest.approx(expected_angle, abs=3.0)
    # one particle column wide: exactly one zero-mass particle in every grid row it spans
    rows, counts = np.unique(np.round(sp.y[sp.precrack] / sp.spacing), return_counts=True)
    assert (counts == 1).all()
    assert rows.size == pytest.approx(sp.radius * math.cos(math.radians(expected_angle))
                                      / sp.spacing, abs=1.01)


# -- 3D disc -------------------------------------------------------------------------------
# The source's 3D disc (spec sections 1 and 4, check 2 in 3D, issue 16): 40 cells across,
# 8 deep, axis horizontal, 10 112 particles; masses at fixed total; pre-cracks as zero-mass
# planes one column wide through the thickness; the kernel-weighted spread of uniform masses
# at kappa = 0.7 / 1 / 1.5 (0.32 / 0.16 / 0.08 in 3D against 0.38 / 0.24 / 0.16 in 2D).

DELTA = 0.004


def disc3d(*overrides):
    return load_scene("impact/disc3d", list(overrides))


def test_the_source_count_and_geometry():
    """8 x 1264 = 10 112 particles (the source's count), layers at z = (k - 3.5) Delta, every
    layer the 2D disc's grid, lowest centre r_c + 0.1 Delta above the base, rho0 Delta^3 each."""
    sp = build_specimen(disc3d(), 0)
    flat = build_specimen(load_scene("impact/default"), 0)
    assert sp.n == 10112 == 8 * flat.n
    assert np.allclose(np.unique(sp.z), (np.arange(8) - 3.5) * DELTA)
    for z in np.unique(sp.z):
        layer = sp.z == z
        assert np.array_equal(sp.x[layer], flat.x) and np.array_equal(sp.y[layer], flat.y)
    assert sp.y.min() == pytest.approx(0.5 * DELTA + 0.1 * DELTA, rel=1e-12)
    assert np.allclose(sp.mass, 2400.0 * DELTA**3, rtol=1e-14)


@pytest.mark.parametrize("distribution", ["uniform", "normal", "poisson"])
def test_heterogeneous_total_mass_fixed(distribution):
    sp = build_specimen(disc3d(f"particles.masses.distribution={distribution}"), 7)
    total = sp.n * 2400.0 * DELTA**3
    assert sp.mass.sum() == pytest.approx(total, rel=1e-12)
    assert (sp.mass >= 0).all()
    assert sp.mass.std() > 0.2 * sp.mass.mean()
    # positions identical to the homogeneous grid
    hom = build_specimen(disc3d(), 7)
    assert np.array_equal(sp.x, hom.x) and np.array_equal(sp.z, hom.z)


@pytest.mark.parametrize("layout", ["pf1", "pf2", "pf3"])
def test_precrack_is_a_zero_mass_plane_through_the_thickness(layout):
    """The 2D line (one particle per grid row) in every layer: the same (x, y) set at each z,
    massless, the others at the homogeneous mass (total not renormalised)."""
    sp = build_specimen(disc3d(f"particles.precrack={layout}"), 0)
    flat = build_specimen(load_scene("impact/default", [f"particles.precrack={layout}"]), 0)
    assert sp.precrack.sum() == 8 * flat.precrack.sum() > 0
    for z in np.unique(sp.z):
        layer = sp.z == z
        assert np.array_equal(sp.precrack[layer], flat.precrack)
    assert (sp.mass[sp.precrack] == 0).all()
    assert np.allclose(sp.mass[~sp.precrack], 2400.0 * DELTA**3, rtol=1e-14)


def test_dimension_other_than_2_or_3_is_refused():
    with pytest.raises(SceneError, match="domain.dim: 4 is not allowed; allowed values: 2, 3"):
        disc3d("domain.dim=4")
    with pytest.raises(SceneError, match="domain.plane"):
        disc3d("domain.plane=stress")


def lattice_weights(kappa, n=18, seed=0, dim=3):
    """Kernel-weighted uniform masses sum_j m_j W_ij / sum_j W_ij (self included) on a periodic
    n^dim lattice, with the specimen's own weights (draw_weights)."""
    g = (np.arange(n) + 0.5) * DELTA
    pts = np.array(np.meshgrid(*([g] * dim), indexing="ij")).reshape(dim, -1).T
    m = draw_weights("uniform", len(pts), np.random.default_rng(seed), 0.3, 4.0)
    h = 1.2 * kappa * DELTA
    tree = cKDTree(pts, boxsize=n * DELTA)
    pairs = tree.query_pairs(2 * h, output_type="ndarray")
    i = np.r_[pairs[:, 0], pairs[:, 1], np.arange(len(pts))]
    j = np.r_[pairs[:, 1], pairs[:, 0], np.arange(len(pts))]
    d = pts[i] - pts[j]
    d -= n * DELTA * np.rint(d / (n * DELTA))
    w = kernel_w_array(CUBIC, np.linalg.norm(d, axis=1), 2 * h, dim)
    return np.bincount(i, w * m[j], len(pts)) / np.bincount(i, w, len(pts)), w, i


@pytest.mark.parametrize("kappa,issue", [(0.7, 0.32), (1.0, 0.16), (1.5, 0.08)])
def test_kernel_weighted_mass_spread_in_3d(kappa, issue):
    """For i.i.d. weights of CV c the kernel-weighted mass has CV c sqrt(sum W^2)/sum W. On the
    3D lattice that is 0.321 / 0.157 / 0.084 (the issue's 0.32 / 0.16 / 0.08, to its two
    digits: |difference| < 0.005), and the specimen's uniform masses on a periodic 24^3
    lattice (13 824 particles) reproduce it within 8 %: the sample CV scatters over seeds by
    about 1 / 1.7 / 3.5 % (sd, kappa = 0.7 / 1 / 1.5, measured on 18^3 with 8 seeds; x 0.65 on
    24^3), so 8 % is > 3 sd at every kappa. (On the 8-layer disc itself the spread is higher,
    0.33 / 0.17 / 0.10, because the supports of the surface particles are cut.) Partition of
    unity of the lattice: sum_j V W_ij within 1e-3 of 1 at kappa = 1 (1.0008 in 3D; 0.99976 in
    2D)."""
    _, w, i = lattice_weights(kappa, n=8, seed=0)
    w0 = w[i == 0]
    theory = np.sqrt(1.0 / 3.0) * np.sqrt((w0**2).sum()) / w0.sum()
    assert abs(theory - issue) < 0.005
    if kappa == 1.0:
        assert abs(w0.sum() * DELTA**3 - 1.0) < 1e-3
    q, _, _ = lattice_weights(kappa, n=24, seed=1)
    assert q.std() / q.mean() == pytest.approx(theory, rel=0.08)
    # 2D for contrast: the same kappa smooths less (0.38 / 0.24 / 0.16)
    _, w2, i2 = lattice_weights(kappa, n=10, dim=2)
    w20 = w2[i2 == 0]
    assert np.sqrt(1.0 / 3.0) * np.sqrt((w20**2).sum()) / w20.sum() > 1.15 * theory


# -- rings ---------------------------------------------------------------------------------
# The ``impact/rings`` scene: PySPH's colliding rings in the impact engine.
@pytest.mark.parametrize(("spacing", "count"), [(5e-4, 17592), (2.5e-4, 70320)])
def test_the_grid_has_pysphs_particle_counts(spacing, count):
    x, y, side = rings(0.03, 0.04, 0.041, spacing)
    assert x.size == count
    r = np.hypot(x - 0.041 * side, y)
    assert r.min() >= 0.03 - 1e-12 and r.max() < 0.04 + 1e-12


def test_scene_is_elastic_with_av_and_as_and_rings_approach():
    scene = load_scene("impact/rings")
    assert set(scene.effects) == {"elasticity", "artificial_viscosity", "artificial_stress"}
    st = settings(scene)
    assert (st.av_alpha, st.av_beta, st.as_epsilon) == (1.0, 1.0, 0.3)
    young = 9 * st.material.bulk * st.material.shear / (3 * st.material.bulk
                                                         + st.material.shear)
    assert young == pytest.approx(1e7, rel=1e-9)
    sp = build_specimen(scene, 0)
    assert sp.n == 17592
    # 0.059 c0 with PySPH's c0 = sqrt(K / rho0)
    assert scene.get("particles.rings.speed") == pytest.approx(
        0.059 * np.sqrt(st.material.bulk / st.rho0), rel=1e-5)
    left = sp.x < sp.x.mean()
    assert (sp.vx[left] > 0).all() and (sp.vx[~left] < 0).all()


@pytest.mark.slow
def test_rings_collide_symmetrically_and_conserve_momentum():
    """Coarse rings (Delta = 2 mm) through first contact: total momentum stays zero and the
    two centres of mass mirror each other."""
    scene = load_scene("impact/rings", ["particles.spacing=0.002"])
    sp = build_specimen(scene, 0)
    eng = Engine(settings(scene), initial_state(scene, sp))
    left = sp.vx > 0
    m = eng.state.m
    centre = 0.5 * (sp.x[left].mean() + sp.x[~left].mean())
    scale = float(np.sum(m * np.abs(eng.state.vx)))
    while eng.t < 1.2e-5:  # contact at ~4 us
        eng.step()
    st = eng.state
    assert abs(float(np.sum(m * st.vx))) < 1e-9 * scale
    xl = np.sum(m[left] * st.x[left]) / m[left].sum()
    xr = np.sum(m[~left] * st.x[~left]) / m[~left].sum()
    assert xl - centre == pytest.approx(-(xr - centre), rel=1e-9)
    # they have met: the left ring has slowed down
    ul = np.sum(m[left] * st.vx[left]) / m[left].sum()
    assert ul < 0.99 * scene.get("particles.rings.speed")
    assert abs(eng.balance_error()) < 0.05
