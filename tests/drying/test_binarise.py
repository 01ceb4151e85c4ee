"""Binarisation of run snapshots (drying spec section 9; section 13, check 12)."""

import numpy as np
import pytest

from craquelure.drying.binarise import binarise, edge_depth, phi_field, snapshot_image
from craquelure.drying.fragments import fragment_areas, label_periodic
from craquelure.sph.field import mesh_field

from .synthetic_run import lattice_run

L, N_SIDE, H = 2.0, 40, 0.2
DELTA = L / N_SIDE  # particle spacing h/4


def test_edge_depth_matches_spec():
    # Spec section 9 [V]: phi = phi0 = 0.8 is reached d* = 0.199 h inside a free edge.
    assert edge_depth(0.8) == pytest.approx(0.199, abs=5e-4)
    assert edge_depth(0.8, h=H) == pytest.approx(0.199 * H, abs=1e-4)
    # phi0 -> 1/2 puts the threshold on the edge itself.
    assert edge_depth(0.5 + 1e-9) < 1e-6


def test_mesh_field_is_direct_sum():
    """The neighbour-search field equals the O(mesh x N) minimum-image sum."""
    from craquelure.sph.kernels import w

    rng = np.random.default_rng(3)
    x, y = rng.uniform(0, 1.0, 60), rng.uniform(0, 1.0, 60)
    v = rng.uniform(0.5, 1.5, 60)
    active = rng.random(60) > 0.2
    phi = mesh_field(x, y, v, 1.0, 0.3, 0.05, active=active)
    g = np.arange(20) * 0.05
    px, py = np.meshgrid(g, g)
    dx = px[..., None] - x
    dy = py[..., None] - y
    dx -= np.rint(dx)
    dy -= np.rint(dy)
    direct = (w("quintic", np.hypot(dx, dy), 0.3) * (v * active)).sum(axis=-1)
    np.testing.assert_allclose(phi, direct, rtol=1e-12, atol=1e-12)


def test_intact_lattice_is_all_paste():
    # Check 12: an intact configuration gives an all-ones image (Shepard sum 1 +- 1e-4).
    run = lattice_run(N_SIDE, L)
    image, spacing = snapshot_image(run, 0, spacing_h=0.05)
    assert image.all()
    assert spacing == pytest.approx(0.01)
    volume = np.full(N_SIDE**2, DELTA**2)
    phi = phi_field(run["x"].values[0], run["y"].values[0], volume, L, H, 0.01)
    assert np.abs(phi - 1.0).max() < 1e-4


@pytest.mark.parametrize(
    ("bands", "expected"),
    [
        ([("y", 0.5, 0.8)], 1),                       # one band: a wrapped annulus
        ([("y", 0.5, 0.8), ("y", 1.4, 1.7)], 2),      # two parallel bands
        ([("y", 0.5, 0.8), ("y", 1.4, 1.7), ("x", 0.2, 0.5), ("x", 1.1, 1.4)], 4),
    ],
)
def test_bands_give_expected_fragments_and_widths(bands, expected):
    """Check 12: fragment count, and each fragment's width = particle-free complement minus
    2 d* within +-0.5 Delta per edge."""
    run = lattice_run(N_SIDE, L, bands_per_time=(bands,))
    image, spacing = snapshot_image(run, 0, spacing_h=0.02)
    labels, n = label_periodic(image)
    assert n == expected
    d_star = edge_depth(0.8, h=H)
    # Material extent per axis: particles represent cells of width Delta, so a strip between
    # two bands has width (number of lattice rows in it) x Delta.
    rows = (np.arange(N_SIDE) + 0.5) * DELTA
    for axis in ("x", "y"):
        cuts = sorted((lo, hi) for a, lo, hi in bands if a == axis)
        if not cuts:
            continue
        # Widths of the material strips between consecutive bands (cyclically).
        removed = np.zeros(N_SIDE, bool)
        for lo, hi in cuts:
            removed |= (rows >= lo) & (rows < hi)
        expected_widths = []
        for k in range(len(cuts)):
            lo = cuts[k][1]
            hi = cuts[(k + 1) % len(cuts)][0] + (L if k == len(cuts) - 1 else 0.0)
            r = np.concatenate([rows, rows + L])
            expected_widths.append(np.sum((r >= lo) & (r < hi)) * DELTA - 2 * d_star)
        # Measured widths: runs of paste pixels along a line through the fragments' middles.
        # ... in the middle of the wrapped-around material strip of the other axis.
        other = sorted((lo, hi) for a, lo, hi in bands if a != axis)
        line_at = 0.0 if not other else 0.5 * (other[-1][1] + other[0][0] + L)
        k_line = int(round(line_at / spacing)) % image.shape[0]
        line = image[:, k_line] if axis == "y" else image[k_line, :]
        # Cyclic runs of ones.
        start = np.argmin(line)  # a crack pixel, so runs do not wrap
        line = np.roll(line, -start)
        edges = np.flatnonzero(np.diff(np.concatenate([[0], line.astype(int), [0]])))
        widths = (edges[1::2] - edges[::2]) * spacing
        assert len(widths) == len(cuts)
        np.testing.assert_allclose(sorted(widths), sorted(expected_widths), atol=DELTA)


def test_mesh_refinement_converges_areas():
    """Areas of the four fragments converge as the mesh is refined: the rasterisation error is
    at most perimeter x (spacing + reference spacing), and shrinks with the spacing."""
    bands = [("y", 0.5, 0.8), ("y", 1.4, 1.7), ("x", 0.2, 0.5), ("x", 1.1, 1.4)]
    run = lattice_run(N_SIDE, L, bands_per_time=(bands,))
    ref_image, ref_spacing = snapshot_image(run, 0, spacing_h=0.005)
    ref = np.sort(fragment_areas(ref_image, ref_spacing))
    assert ref.size == 4
    d_star = edge_depth(0.8, h=H)
    # Material rectangles 0.6 x 0.6, 0.6 x 0.8 (twice), 0.8 x 0.8.
    perimeter = 2 * (0.6 + 0.8)
    errors = []
    for spacing_h in (0.08, 0.04, 0.02):
        image, spacing = snapshot_image(run, 0, spacing_h=spacing_h)
        areas = np.sort(fragment_areas(image, spacing))
        err = np.abs(areas - ref).max()
        assert err <= perimeter * (spacing + ref_spacing)
        errors.append(err)
    assert errors[-1] < errors[0]
    # Reference against the edge-bias prediction: (a - 2d*)(b - 2d*), up to the rounding of the
    # four corners (each < d*^2) and the rasterisation of the reference (perimeter x spacing).
    widths = np.array([0.6, 0.8]) - 2 * d_star
    predicted = np.sort(np.outer(widths, widths).ravel())
    np.testing.assert_allclose(ref, predicted, atol=4 * d_star**2 + perimeter * ref_spacing)


def test_binarise_threshold():
    phi = np.array([0.79, 0.8, 0.81])
    assert binarise(phi, 0.8).tolist() == [False, True, True]
