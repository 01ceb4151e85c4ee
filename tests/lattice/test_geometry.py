"""Triangular lattices and their bonds (lattice spec section 2): every bond has the lattice
spacing, interior nodes have 6 neighbours, the bond count of an nx x ny block is
ny (nx - 1) + (ny - 1)(2 nx - 1), bodies are never bonded to each other, the periodic x
direction closes the rows, a half disc holds exactly its lattice points, and the disorder
removes round(f n) distinct bonds."""

import math

import numpy as np
import pytest

from craquelure.lattice.geometry import find_bonds, half_disc, remove_fraction, triangular_block


@pytest.mark.parametrize("nx, ny, spacing", [(8, 6, 1.0), (5, 9, 0.37)])
def test_block_bonds_have_the_spacing_and_six_neighbours(nx, ny, spacing):
    x, y, row = triangular_block(nx, ny, spacing)
    assert x.size == nx * ny and np.array_equal(np.bincount(row), np.full(ny, nx))
    i, j = find_bonds(x, y, np.zeros(x.size, np.int64), spacing)
    assert (i < j).all() and len(set(zip(i.tolist(), j.tolist(), strict=True))) == i.size
    assert np.hypot(x[i] - x[j], y[i] - y[j]) == pytest.approx(spacing, rel=1e-12)
    assert i.size == ny * (nx - 1) + (ny - 1) * (2 * nx - 1)
    degree = np.bincount(np.r_[i, j], minlength=x.size)
    col = np.arange(x.size) % nx
    interior = (row > 0) & (row < ny - 1) & (col > 0) & (col < nx - 1)
    assert (degree[interior] == 6).all() and degree.max() == 6


def test_bodies_are_not_bonded_and_the_periodic_rows_close():
    nx, ny = 10, 4
    x, y, row = triangular_block(nx, ny)
    body = (np.arange(x.size) % nx >= nx // 2).astype(np.int64)
    i, j = find_bonds(x, y, body)
    assert (body[i] == body[j]).all()
    free = find_bonds(x, y, np.zeros(x.size, np.int64))[0].size
    wrapped_i, wrapped_j = find_bonds(x, y, np.zeros(x.size, np.int64), period_x=nx * 1.0)
    # each row gains its closing bond and each pair of rows the two across the seam
    assert wrapped_i.size == free + ny + (ny - 1)
    dx = np.abs(x[wrapped_i] - x[wrapped_j])
    dist = np.hypot(np.minimum(dx, nx - dx), y[wrapped_i] - y[wrapped_j])
    assert dist == pytest.approx(1.0, rel=1e-12)


def test_half_disc_points_lie_on_the_lattice_inside_the_lower_half():
    radius, cx, cy = 6.3, 2.0, 10.0
    x, y = half_disc(radius, cx, cy)
    assert (np.hypot(x - cx, y - cy) <= radius + 1e-9).all() and (y <= cy + 1e-12).all()
    rows = np.rint((cy - y) / (math.sqrt(3) / 2)).astype(int)
    np.testing.assert_allclose(cy - y, rows * math.sqrt(3) / 2, atol=1e-12)
    shift = np.mod(x - cx - 0.5 * (rows % 2), 1.0)
    assert np.minimum(shift, 1 - shift).max() < 1e-9
    # exactly the points of the lattice (rows down from cy, odd rows shifted) in the half disc:
    # brute force over a large patch of it
    k, i = np.meshgrid(np.arange(0, 12), np.arange(-20, 21), indexing="ij")
    bx, by = cx + i + 0.5 * (k % 2), cy - k * math.sqrt(3) / 2
    inside = np.hypot(bx - cx, by - cy) <= radius + 1e-9
    assert x.size == inside.sum()
    assert set(zip(np.round(x, 9), np.round(y, 9), strict=True)) == set(
        zip(np.round(bx[inside], 9), np.round(by[inside], 9), strict=True))


def test_remove_fraction_draws_distinct_bonds():
    rng = np.random.default_rng(4)
    out = remove_fraction(1000, 0.123, rng)
    assert out.size == 123 and np.unique(out).size == 123
    assert out.min() >= 0 and out.max() < 1000 and (np.diff(out) > 0).all()
    assert remove_fraction(1000, 0.0, rng).size == 0
