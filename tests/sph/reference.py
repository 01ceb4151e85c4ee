"""O(N^2) references the tests check the neighbour search against."""

import numpy as np

from craquelure.periodic import minimum_image
from craquelure.sph.neighbours import Box


def brute_force_pairs(x, y, radius, box: Box) -> set[tuple[int, int]]:
    """All ordered pairs (i, j), i != j, closer than radius."""
    dx = x[:, None] - x[None, :]
    dy = y[:, None] - y[None, :]
    if box.periodic:
        dx = minimum_image(dx, box.length_x)
        dy = minimum_image(dy, box.length_y)
    close = (dx * dx + dy * dy < radius * radius)
    np.fill_diagonal(close, False)
    return {(int(i), int(j)) for i, j in zip(*np.nonzero(close), strict=True)}
