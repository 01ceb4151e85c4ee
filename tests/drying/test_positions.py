"""Initial positions: random sequential addition and the square lattice."""

from __future__ import annotations

import numpy as np
import pytest

from craquelure.drying.positions import PackingError, random_sequential_addition, square_lattice
from craquelure.sph.neighbours import Box

from ..sph.reference import brute_force_pairs


def min_image_distances(x, y, length):
    dx = x[:, None] - x[None, :]
    dy = y[:, None] - y[None, :]
    dx -= length * np.rint(dx / length)
    dy -= length * np.rint(dy / length)
    d = np.hypot(dx, dy)
    np.fill_diagonal(d, np.inf)
    return d


@pytest.mark.parametrize("n,length,fraction", [(400, 1.0, 0.8), (1600, 2.0, 0.8),
                                                (900, 3.0, 0.5)])
def test_rsa_respects_the_minimum_distance_with_minimum_image(n, length, fraction):
    d_min = fraction * length / np.sqrt(n)
    x, y = random_sequential_addition(n, length, d_min, np.random.default_rng(n))
    assert x.size == y.size == n
    assert np.all((x >= 0) & (x < length) & (y >= 0) & (y < length))
    d = min_image_distances(x, y, length)
    assert d.min() >= d_min
    # The minimum image matters: some pairs are close only across the boundary.
    across = brute_force_pairs(x, y, 1.5 * d_min, Box.square(length, periodic=True))
    direct = brute_force_pairs(x, y, 1.5 * d_min, Box.square(length, periodic=False))
    assert len(across - direct) > 0
    # RSA at 0.8 of the spacing is close-packed enough that the minimum is nearly reached.
    assert d.min() < 1.05 * d_min


def test_rsa_same_seed_same_points_different_seed_different_points():
    args = (1600, 2.0, 0.04)
    a = random_sequential_addition(*args, np.random.default_rng(5))
    b = random_sequential_addition(*args, np.random.default_rng(5))
    c = random_sequential_addition(*args, np.random.default_rng(6))
    np.testing.assert_array_equal(a[0], b[0])
    np.testing.assert_array_equal(a[1], b[1])
    assert not np.array_equal(a[0], c[0])


def test_rsa_is_statistically_uniform():
    # Counts in 4 x 4 blocks of the box: each holds N/16 +- a few (RSA is sub-Poissonian).
    n, length = 6400, 4.0
    x, y = random_sequential_addition(n, length, 0.8 * 0.05, np.random.default_rng(1))
    counts, _, _ = np.histogram2d(x, y, bins=4, range=[[0, length], [0, length]])
    assert np.abs(counts - n / 16).max() < 4 * np.sqrt(n / 16)


def test_rsa_near_jamming_fails_clearly():
    with pytest.raises(PackingError, match="near jamming"):
        random_sequential_addition(400, 1.0, 1.0 / 20, np.random.default_rng(0),
                                   max_attempts_per_particle=20)


def test_square_lattice():
    x, y = square_lattice(8, 2.0)
    assert x.size == 64
    np.testing.assert_allclose(np.unique(x), (np.arange(8) + 0.5) * 0.25)
    d = min_image_distances(x, y, 2.0)
    np.testing.assert_allclose(d.min(), 0.25)
