"""Initial particle positions: random sequential addition (RSA) in a periodic box, and
regular lattices.

RSA (drying spec section 7): candidates uniform in the box, accepted if no accepted point lies
closer than ``d_min`` (minimum image). A grid of cells of side ``d_min / sqrt(2)`` holds at
most one point per cell, so each test looks at a fixed 5 x 5 block of cells. Candidates come
from a seeded :class:`numpy.random.Generator`, so the same seed gives the same points."""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from craquelure.errors import CraquelureError
from craquelure.periodic import minimum_image


class PackingError(CraquelureError, RuntimeError):
    """RSA cannot place the requested points (near jamming); the CLI prints the message."""


@njit(cache=True)
def _rsa_accept(cand_x, cand_y, px, py, n_placed, n_target, grid, ng, csize, length, d2):
    for k in range(cand_x.size):
        if n_placed >= n_target:
            break
        x, y = cand_x[k], cand_y[k]
        gx, gy = int(x / csize) % ng, int(y / csize) % ng
        ok = True
        for oy in range(-2, 3):
            if not ok:
                break
            for ox in range(-2, 3):
                q = grid[(gy + oy) % ng, (gx + ox) % ng]
                if q >= 0:
                    dx = minimum_image(x - px[q], length)
                    dy = minimum_image(y - py[q], length)
                    if dx * dx + dy * dy < d2:
                        ok = False
                        break
        if ok:
            px[n_placed] = x
            py[n_placed] = y
            grid[gy, gx] = n_placed
            n_placed += 1
    return n_placed


def random_sequential_addition(n: int, box_length: float, d_min: float, rng: np.random.Generator,
                               max_attempts_per_particle: int = 2000
                               ) -> tuple[np.ndarray, np.ndarray]:
    """``n`` points in the periodic square ``[0, L)^2`` with pairwise distance >= ``d_min``."""
    # Cells no larger than d_min/sqrt(2) hold at most one point; with >= 5 cells per side a
    # point's rivals lie within 2 cells (d_min/csize <= sqrt(2) * ng/(ng-1) < 2).
    ng = int(math.ceil(box_length / (d_min / math.sqrt(2.0))))
    if ng < 5:
        raise ValueError("box too small for RSA: need L >= 5 d_min / sqrt(2)")
    csize = box_length / ng
    grid = -np.ones((ng, ng), np.int64)
    px, py = np.empty(n), np.empty(n)
    placed, attempts, batch = 0, 0, max(1024, 4 * n)
    while placed < n:
        if attempts > max_attempts_per_particle * n:
            raise PackingError(
                f"RSA placed only {placed} of {n} particles with minimum separation {d_min:g} "
                f"after {attempts} attempts: the packing is near jamming; lower "
                f"particles.rsa_min_separation")
        cand = rng.random((2, batch)) * box_length
        placed = _rsa_accept(cand[0], cand[1], px, py, placed, n, grid, ng, csize,
                             float(box_length), d_min * d_min)
        attempts += batch
    return px, py


def square_lattice(n_side: int, box_length: float) -> tuple[np.ndarray, np.ndarray]:
    """Cell-centred square lattice of ``n_side**2`` points in ``[0, L)^2``."""
    spacing = box_length / n_side
    g = (np.arange(n_side) + 0.5) * spacing
    xx, yy = np.meshgrid(g, g)
    return xx.ravel().copy(), yy.ravel().copy()
