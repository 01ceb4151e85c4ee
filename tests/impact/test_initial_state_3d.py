"""The source's 3D disc (spec sections 1 and 4, check 2 in 3D, issue 16): 40 cells across,
8 deep, axis horizontal, 10 112 particles; masses at fixed total; pre-cracks as zero-mass
planes one column wide through the thickness; the kernel-weighted spread of uniform masses
at kappa = 0.7 / 1 / 1.5 (0.32 / 0.16 / 0.08 in 3D against 0.38 / 0.24 / 0.16 in 2D)."""

import numpy as np
import pytest
from scipy.spatial import cKDTree

from craquelure.errors import SceneError
from craquelure.impact.initial_state import build_specimen, draw_weights
from craquelure.scene import load_scene
from craquelure.sph.kernels import CUBIC, kernel_w_array

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
