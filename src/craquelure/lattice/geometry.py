"""Triangular lattices of discs and their bonds (lattice spec section 2).

Rows run along x with spacing L; row r sits at y = r sqrt(3)/2 L and is shifted by L/2 when r
is odd, so every interior node has 6 neighbours at distance L. Bonds join particles of the
same body closer than 1.1 L (the spec's 1.1 (r_i + r_j) for d = L). Optional disorder [C]:
remove a random fraction of the bonds at start (removed bonds are kept in the list with state
``REMOVED`` so that a re-freezing pass never re-forms them). A periodic x direction (period
n_x L) is supported for the Glen and wave tests (bonds then use the minimum image).
Decision [D]: polydisperse packings are not implemented.
"""

import math

import numpy as np

from craquelure.sph.neighbours import Box, neighbour_list

ROW = math.sqrt(3.0) / 2.0
INTACT, BROKEN, REMOVED = 1, 0, 2


def triangular_block(nx: int, ny: int, L: float = 1.0, x0: float = 0.0,  # noqa: N803
                     y0: float = 0.0) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Positions of an nx x ny block (row-major) and the row index of each particle."""
    row, col = np.divmod(np.arange(nx * ny), nx)
    x = x0 + L * (col + 0.5 * (row % 2))
    y = y0 + L * ROW * row
    return x.astype(np.float64), y.astype(np.float64), row.astype(np.int64)


def half_disc(radius: float, cx: float, cy: float, L: float = 1.0  # noqa: N803
              ) -> tuple[np.ndarray, np.ndarray]:
    """Lattice points of the lower half-disc |r - c| <= radius, y <= cy (flat side on top)."""
    n_rows = int(radius / (L * ROW)) + 1
    xs, ys = [], []
    for k in range(n_rows):
        y = cy - k * L * ROW
        half = math.sqrt(max(radius**2 - (cy - y) ** 2, 0.0))
        shift = 0.5 * L * (k % 2)
        i0 = math.ceil((-half - shift) / L - 1e-9)
        i1 = math.floor((half - shift) / L + 1e-9)
        for i in range(i0, i1 + 1):
            xs.append(cx + shift + i * L)
            ys.append(y)
    return np.array(xs), np.array(ys)


def find_bonds(x: np.ndarray, y: np.ndarray, body: np.ndarray, L: float = 1.0,  # noqa: N803
               period_x: float = 0.0, cutoff: float = 1.1) -> tuple[np.ndarray, np.ndarray]:
    """Pairs i < j of the same body closer than cutoff L (minimum image along x if
    period_x > 0), sorted."""
    radius = cutoff * L
    offsets, index = neighbour_list(x, y, radius, search_box(x, y, radius, period_x))
    i = np.repeat(np.arange(x.size), np.diff(offsets))
    j = index
    keep = (i < j) & (body[i] == body[j])
    order = np.lexsort((j[keep], i[keep]))
    return i[keep][order].astype(np.int64), j[keep][order].astype(np.int64)


def search_box(x: np.ndarray, y: np.ndarray, radius: float, period_x: float) -> Box:
    """The neighbour-search box of a block: periodic along x (x within one period of x.min())
    if ``period_x`` > 0, else open around the particles."""
    if period_x > 0:
        pad = 3 * radius
        return Box(period_x, float(y.max() - y.min()) + 2 * pad, True, float(x.min()),
                   float(y.min()) - pad)
    return Box.around(x, y, radius)


def remove_fraction(n_bonds: int, fraction: float, rng: np.random.Generator) -> np.ndarray:
    """Indices of round(fraction n_bonds) bonds chosen at random (disorder)."""
    k = int(round(fraction * n_bonds))
    return np.sort(rng.choice(n_bonds, size=k, replace=False)) if k else np.zeros(0, np.int64)
