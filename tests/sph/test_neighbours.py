"""Cell-list neighbour search against the O(N^2) reference, on periodic and open boxes,
including the awkward positions (cell edges, box edges, pairs exactly at the radius)."""

from __future__ import annotations

import numpy as np
import pytest

from craquelure.sph.neighbours import (
    Box,
    bin_particles,
    cell_order,
    cells_per_side,
    cluster_pairs,
    neighbour_list,
)

from .reference import brute_force_pairs


def csr_pairs(offsets: np.ndarray, index: np.ndarray) -> set[tuple[int, int]]:
    rows = np.repeat(np.arange(offsets.size - 1), np.diff(offsets))
    return {(int(i), int(j)) for i, j in zip(rows, index, strict=True)}


def check_against_brute_force(x, y, radius, box, active=None):
    offsets, index = neighbour_list(x, y, radius, box, active)
    assert offsets.shape == (x.size + 1,)
    assert offsets[0] == 0 and np.all(np.diff(offsets) >= 0) and offsets[-1] == index.size
    got = csr_pairs(offsets, index)
    # Every row lists each neighbour once.
    assert len(got) == index.size
    ref = brute_force_pairs(x, y, radius, box)
    if active is not None:
        ref = {(i, j) for i, j in ref if active[i] and active[j]}
    assert got == ref
    # Symmetric: J is a neighbour of I iff I is a neighbour of J.
    assert got == {(j, i) for i, j in got}
    return got


def random_layout(rng, n, length, radius):
    """Uniform points plus points placed exactly on cell edges and box edges."""
    x, y = rng.uniform(0, length, n), rng.uniform(0, length, n)
    nx, _ = cells_per_side(Box.square(length), radius)
    edges = np.arange(nx + 1) * (length / nx)  # includes 0 and L
    k = min(n // 4, 3 * edges.size)
    x[:k] = rng.choice(edges, k)
    y[k // 2:k + k // 2] = rng.choice(edges, k)
    return x, y


@pytest.mark.parametrize("n", [2, 10, 300, 2000])
@pytest.mark.parametrize("periodic", [True, False])
def test_random_layouts_match_brute_force(n, periodic):
    rng = np.random.default_rng(n + 7 * periodic)
    length, radius = 2.0, 0.2
    x, y = random_layout(rng, n, length, radius)
    got = check_against_brute_force(x, y, radius, Box.square(length, periodic))
    if n >= 300:
        assert len(got) > n  # the test exercises real pairs


@pytest.mark.parametrize("length,radius", [(1.0, 0.5), (1.0, 0.3), (3.0, 0.25), (2.3, 0.7)])
def test_few_cells_and_non_divisible_boxes(length, radius):
    # 2 or 3 cells per side: the 3x3 block of cells wraps onto itself in a periodic box.
    rng = np.random.default_rng(11)
    for periodic in (True, False):
        x, y = random_layout(rng, 200, length, radius)
        check_against_brute_force(x, y, radius, Box.square(length, periodic))


def test_rectangular_box():
    rng = np.random.default_rng(5)
    box = Box(3.0, 1.2, periodic=True)
    x, y = rng.uniform(0, 3.0, 500), rng.uniform(0, 1.2, 500)
    x[:10], y[10:20] = 3.0, 0.0
    check_against_brute_force(x, y, 0.25, box)


def test_particles_at_zero_and_at_box_length_are_images():
    # Periodic: x = 0 and x = L are the same point (distance 0 by minimum image).
    length, radius = 2.0, 0.2
    x = np.array([0.0, length, 0.0, length, 1.0, 0.1, length - 0.05])
    y = np.array([0.0, 0.0, length, length, 1.0, 0.0, length])
    got = check_against_brute_force(x, y, radius, Box.square(length))
    assert {(0, 1), (0, 2), (0, 3), (1, 3), (0, 5), (0, 6)} <= got
    assert not any(4 in pair for pair in got)
    # Open box: the two are L apart, not neighbours.
    got_open = check_against_brute_force(x, y, radius, Box.square(length, periodic=False))
    assert (0, 1) not in got_open and (0, 5) in got_open


def test_pairs_exactly_at_the_radius_are_excluded():
    # |r_IJ| < radius strictly; dyadic numbers make the distances exact in floating point.
    radius = 0.25
    x = np.array([0.5, 0.75, 0.5, 0.5 + 0.125, 1.0 - 2.0**-40])
    y = np.array([0.5, 0.5, 0.75, 0.5, 0.5])
    for periodic in (True, False):
        got = check_against_brute_force(x, y, radius, Box.square(2.0, periodic))
        assert (0, 1) not in got and (0, 2) not in got  # exactly at the radius
        assert (0, 3) in got and (1, 4) in got  # just inside
    # Across the periodic boundary, exactly at the radius and just inside.
    x = np.array([0.125, 2.0 - 0.125, 2.0 - 0.125 + 2.0**-30])
    y = np.zeros(3)
    got = check_against_brute_force(x, y, radius, Box.square(2.0))
    assert (0, 1) not in got and (0, 2) in got


def test_lattice_on_cell_edges():
    # A square lattice whose rows and columns sit exactly on the cell edges, spacing = radius/2:
    # every particle has the same 8 neighbours inside the radius (distances radius/2, radius/sqrt 2,
    # and those at exactly radius excluded).
    length, radius = 2.0, 0.25
    g = np.arange(16) * 0.125
    x, y = (a.ravel() for a in np.meshgrid(g, g))
    offsets, index = neighbour_list(x, y, radius, Box.square(length))
    assert np.all(np.diff(offsets) == 8)
    check_against_brute_force(x, y, radius, Box.square(length))
    check_against_brute_force(x, y, radius, Box.square(length, periodic=False))


def test_inactive_particles_neither_have_nor_are_neighbours():
    rng = np.random.default_rng(2)
    length, radius = 2.0, 0.2
    x, y = random_layout(rng, 800, length, radius)
    active = rng.random(800) < 0.7
    for periodic in (True, False):
        offsets, index = neighbour_list(x, y, radius, Box.square(length, periodic), active)
        assert np.all(np.diff(offsets)[~active] == 0)
        assert np.all(active[index])
        check_against_brute_force(x, y, radius, Box.square(length, periodic), active)


def test_open_box_with_particles_outside_the_bounds():
    # Particles outside the nominal bounds are binned into edge cells: still correct.
    rng = np.random.default_rng(9)
    x, y = rng.uniform(-0.5, 2.5, 600), rng.uniform(-0.5, 2.5, 600)
    check_against_brute_force(x, y, 0.2, Box.square(2.0, periodic=False))
    box = Box.around(x, y, pad=0.0)
    check_against_brute_force(x, y, 0.2, box)


def test_periodic_box_with_unwrapped_positions():
    # Positions outside [0, L) (a particle that moved before being wrapped) are binned by
    # their periodic image and paired by minimum image.
    rng = np.random.default_rng(12)
    x, y = rng.uniform(-0.5, 2.5, 1200), rng.uniform(-3.0, 5.0, 1200)
    x[:4] = [-1e-17, 2.0 + 1e-15, -2.0, 4.0]
    check_against_brute_force(x, y, 0.2, Box.square(2.0))


def test_periodic_box_too_small_is_rejected():
    with pytest.raises(ValueError, match="minimum image is ambiguous"):
        neighbour_list(np.zeros(3), np.zeros(3), 0.6, Box.square(1.0))
    with pytest.raises(ValueError, match="must be > 0"):
        neighbour_list(np.zeros(3), np.zeros(3), 0.0, Box.square(1.0))


@pytest.mark.parametrize("periodic", [True, False])
def test_cell_order_is_a_permutation_sorting_by_cell(periodic):
    rng = np.random.default_rng(4)
    length, radius = 2.0, 0.2
    x, y = random_layout(rng, 1000, length, radius)
    box = Box.square(length, periodic)
    order = cell_order(x, y, radius, box)
    assert np.array_equal(np.sort(order), np.arange(x.size))
    nx, ny = cells_per_side(box, radius)
    cell, start, _ = bin_particles(x, y, np.ones(x.size, bool), 0.0, 0.0, length, length,
                                   nx, ny, periodic)
    sorted_cells = cell[order]
    assert np.all(np.diff(sorted_cells) >= 0)
    # The cells are the floor of position / cell size (row-major, y slowest).
    cx = np.minimum(np.floor(x / (length / nx)).astype(int), nx - 1) % nx
    cy = np.minimum(np.floor(y / (length / ny)).astype(int), ny - 1) % ny
    if periodic:  # x = L wraps to cell 0
        cx = np.floor(x / (length / nx)).astype(int) % nx
        cy = np.floor(y / (length / ny)).astype(int) % ny
    np.testing.assert_array_equal(cell, cy * nx + cx)
    # Stable within a cell, and the neighbour list is the same after reordering.
    for c in np.unique(sorted_cells):
        members = order[sorted_cells == c]
        assert np.all(np.diff(members) > 0)
        assert start[c + 1] - start[c] == members.size
    off_a, idx_a = neighbour_list(x, y, radius, box)
    off_b, idx_b = neighbour_list(x[order], y[order], radius, box)
    relabel = {(int(order[i]), int(order[j])) for i, j in csr_pairs(off_b, idx_b)}
    assert relabel == csr_pairs(off_a, idx_a)


@pytest.mark.parametrize("periodic", [True, False])
@pytest.mark.parametrize("width", [1, 8])
def test_cluster_pairs_cover_every_pair_within_the_radius(periodic, width):
    """cluster_pairs: every active particle in exactly one slot, clusters of ``width`` slots
    that are compact patches, and each cluster's J list (ascending, each slot once) holds every
    active neighbour of each of its members; the lists hold nothing else."""
    rng = np.random.default_rng(3 + width)
    length, radius = 2.0, 0.2
    x, y = random_layout(rng, 1500, length, radius)
    x[:5] += length  # unwrapped positions
    active = rng.random(x.size) < 0.9
    box = Box.square(length, periodic)
    perm, start, jlist, outside = cluster_pairs(x, y, radius, box, width, active)
    real = perm[perm >= 0]
    assert np.array_equal(np.sort(real), np.flatnonzero(active))
    assert np.array_equal(outside, np.flatnonzero(~active))
    assert perm.size % width == 0 and start.size == perm.size // width + 1
    slot = np.full(x.size, -1)
    slot[real] = np.flatnonzero(perm >= 0)
    want = {}
    for i, j in brute_force_pairs(x, y, radius, box):
        if active[i] and active[j]:
            want.setdefault(slot[i] // width, set()).add(int(slot[j]))
    extent = []
    for c in range(start.size - 1):
        listed = jlist[start[c]:start[c + 1]]
        assert np.all(np.diff(listed) > 0)
        assert set(listed.tolist()) == want.get(c, set())
        members = perm[c * width:(c + 1) * width]
        members = members[members >= 0]
        if members.size > 1:
            dx = x[members] - x[members[0]]
            dy = y[members] - y[members[0]]
            if periodic:
                dx, dy = dx - length * np.rint(dx / length), dy - length * np.rint(dy / length)
            extent.append(np.hypot(dx, dy).max())
    if width > 1:  # patches about sqrt(width / density) across, not strips of the box
        assert np.median(extent) < 3 * np.sqrt(width * length**2 / active.sum())


@pytest.mark.parametrize("periodic", [False, True])
def test_point_list_matches_brute_force_in_3d(periodic):
    """neighbour_list_points (k-d tree, any dimension; the 3D impact engine's search): every
    ordered pair closer than the radius once, rows sorted, minimum image when periodic."""
    from craquelure.sph.neighbours import neighbour_list_points

    rng = np.random.default_rng(4)
    length, radius = 1.0, 0.21
    pts = rng.uniform(0, length, (300, 3))
    box = (length, length, length) if periodic else None
    offsets, index = neighbour_list_points(pts, radius, box)
    d = pts[:, None, :] - pts[None, :, :]
    if periodic:
        d -= length * np.rint(d / length)
    close = np.einsum("ijk,ijk->ij", d, d) < radius * radius
    np.fill_diagonal(close, False)
    for i in range(len(pts)):
        row = index[offsets[i]:offsets[i + 1]]
        assert np.array_equal(row, np.flatnonzero(close[i]))
