"""Binarisation of run snapshots and periodic fragment labelling (drying spec section 9;
section 13, checks 12 and 13)."""

import numpy as np
import pytest
from skimage.measure import label as sk_label

from craquelure.drying.binarise import (
    edge_depth,
    fragment_areas,
    label_periodic,
    snapshot_image,
)
from craquelure.drying.field import mesh_field

from .synthetic_run import lattice_run

L, N_SIDE, H = 2.0, 40, 0.2
DELTA = L / N_SIDE  # particle spacing h/4


def test_edge_depth_matches_spec():
    # Spec section 9 [V]: phi = phi0 = 0.8 is reached d* = 0.199 h inside a free edge.
    assert edge_depth(0.8, "quintic", 1.0) == pytest.approx(0.199, abs=5e-4)
    assert edge_depth(0.8, "quintic", H) == pytest.approx(0.199 * H, abs=1e-4)
    # phi0 -> 1/2 puts the threshold on the edge itself.
    assert edge_depth(0.5 + 1e-9, "quintic", 1.0) < 1e-6


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
    image, spacing = snapshot_image(run, 0, 0.05, 0.8, "quintic")
    assert image.all()
    assert spacing == pytest.approx(0.01)
    volume = np.full(N_SIDE**2, DELTA**2)
    phi = mesh_field(run["x"].values[0], run["y"].values[0], volume, L, H, 0.01, "quintic")
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
    image, spacing = snapshot_image(run, 0, 0.02, 0.8, "quintic")
    labels, n = label_periodic(image)
    assert n == expected
    d_star = edge_depth(0.8, "quintic", H)
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
    ref_image, ref_spacing = snapshot_image(run, 0, 0.005, 0.8, "quintic")
    ref = np.sort(fragment_areas(ref_image, ref_spacing))
    assert ref.size == 4
    d_star = edge_depth(0.8, "quintic", H)
    # Material rectangles 0.6 x 0.6, 0.6 x 0.8 (twice), 0.8 x 0.8.
    perimeter = 2 * (0.6 + 0.8)
    errors = []
    for spacing_h in (0.08, 0.04, 0.02):
        image, spacing = snapshot_image(run, 0, spacing_h, 0.8, "quintic")
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


# --- fragments: periodic labelling (check 13) ----------------------------------------------

M = 40  # synthetic image side (pixels)
DX = 0.25  # pixel spacing, so the image side is 10
L_IMAGE = M * DX


def areas(image):
    return np.sort(fragment_areas(image, DX))


# --- check 13 -----------------------------------------------------------------------------

def test_all_ones_is_one_fragment_of_area_l2():
    a = areas(np.ones((M, M), bool))
    assert a.tolist() == [pytest.approx(L_IMAGE * L_IMAGE)]


def test_one_crack_row_leaves_one_fragment():
    image = np.ones((M, M), bool)
    image[7, :] = False
    assert areas(image).tolist() == [pytest.approx((M - 1) * M * DX * DX)]


def test_row_and_column_leave_one_fragment():
    image = np.ones((M, M), bool)
    image[7, :] = False
    image[:, 30] = False
    assert areas(image).tolist() == [pytest.approx((M - 1) ** 2 * DX * DX)]


def test_two_rows_give_two_with_expected_areas():
    image = np.ones((M, M), bool)
    image[5, :] = False
    image[20, :] = False  # strips of 14 rows (6..19) and 24 rows (21..39, 0..4)
    assert areas(image) == pytest.approx(np.array([14, 24]) * M * DX * DX)


def test_two_rows_two_columns_give_four():
    image = np.ones((M, M), bool)
    image[[5, 20], :] = False
    image[:, [10, 35]] = False  # column strips of 24 (11..34) and 14 (36..39, 0..9)
    expected = np.sort(np.outer([14, 24], [24, 14]).ravel()) * DX * DX
    assert areas(image) == pytest.approx(expected)


def test_blob_cut_by_both_edges_counts_once():
    """A disc centred on the corner is four pieces for plain labelling, one on the torus."""
    j, i = np.mgrid[0:M, 0:M]
    dj = np.minimum(j, M - j)
    di = np.minimum(i, M - i)
    image = di**2 + dj**2 <= 8**2
    assert sk_label(image, connectivity=1).max() == 4
    labels, n = label_periodic(image)
    assert n == 1
    assert fragment_areas(image, DX)[0] == pytest.approx(image.sum() * DX * DX)
    # The pixel count approximates the disc area pi R^2 within the boundary pixels.
    assert image.sum() == pytest.approx(np.pi * 64, abs=2 * np.pi * 8)


def test_blob_wrapping_across_one_edge():
    j, i = np.mgrid[0:M, 0:M]
    di = np.minimum(i, M - i)  # centre on the x = 0 | L edge
    image = (di**2 + (j - 20) ** 2 <= 6**2) | ((i - 20) ** 2 + (j - 5) ** 2 <= 3**2)
    assert sk_label(image, connectivity=1).max() == 3
    labels, n = label_periodic(image)
    assert n == 2
    sizes = np.bincount(labels.ravel())[1:]
    wrapped = (di**2 + (j - 20) ** 2 <= 6**2).sum()
    assert sorted(sizes.tolist()) == sorted([wrapped, image.sum() - wrapped])


def test_blocks_touching_at_a_corner_are_two():
    image = np.zeros((M, M), bool)
    image[10:15, 10:15] = True
    image[15:20, 15:20] = True
    assert label_periodic(image)[1] == 2
    # ... also when they touch diagonally across the periodic corner.
    image = np.zeros((M, M), bool)
    image[0:3, 0:3] = True
    image[M - 3:, M - 3:] = True
    assert label_periodic(image)[1] == 2


def test_empty_image_has_no_fragment():
    assert label_periodic(np.zeros((M, M), bool))[1] == 0
    assert fragment_areas(np.zeros((M, M), bool), DX).size == 0


# --- periodic Voronoi-like tessellation ---------------------------------------------------

def test_periodic_voronoi_tessellation():
    """Cells of a periodic Voronoi tessellation separated by one-pixel cracks: one fragment per
    cell, each with exactly its cell's paste pixels (cells cut by the edges count once)."""
    size, n_cells = 160, 14
    rng = np.random.default_rng(7)
    seeds = []
    while len(seeds) < n_cells:  # well separated seeds, so no cell is thinner than a crack
        p = rng.uniform(0, size, 2)
        d = [np.abs((p - q + size / 2) % size - size / 2) for q in seeds]
        if all(np.hypot(*dd) > 30 for dd in d):
            seeds.append(p)
    seeds = np.array(seeds)
    j, i = np.mgrid[0:size, 0:size]
    dx = (i[..., None] + 0.5 - seeds[:, 0] + size / 2) % size - size / 2
    dy = (j[..., None] + 0.5 - seeds[:, 1] + size / 2) % size - size / 2
    owner = np.argmin(dx**2 + dy**2, axis=-1)
    crack = (owner != np.roll(owner, -1, axis=1)) | (owner != np.roll(owner, -1, axis=0))
    image = ~crack
    labels, n = label_periodic(image)
    assert n == n_cells
    assert sk_label(image, connectivity=1).max() > n_cells  # some cells do wrap
    for k in range(1, n + 1):
        owners = np.unique(owner[labels == k])
        assert owners.size == 1  # a fragment is one cell ...
        assert (labels == k).sum() == np.sum(image & (owner == owners[0]))  # ... all of it


def test_labels_numbered_in_raster_order_of_first_pixel():
    rng = np.random.default_rng(2)
    image = rng.random((120, 120)) > 0.45  # near the percolation threshold: many clusters
    labels, n = label_periodic(image)
    assert n > 10
    values, first = np.unique(labels.ravel(), return_index=True)
    assert values.tolist() == list(range(n + 1))
    assert np.all(np.diff(first[1:]) > 0)
