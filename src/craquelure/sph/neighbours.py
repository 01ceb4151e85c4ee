"""O(N) cell-list neighbour search in 2D for periodic and open boxes.

Particles are binned into square cells of side >= the search radius; each particle's
neighbours are found in its own and the 8 surrounding cells (wrapped in a periodic box, where
the minimum image gives the pair vector). The result is a CSR list (``offsets``, ``index``):
the neighbours of I are ``index[offsets[I]:offsets[I+1]]``, every pair appears in both rows
(gather-style loops, safe under ``prange``), I itself is excluded. Inactive particles
(``active == 0``) neither have nor are neighbours.

``cell_order`` gives the permutation that sorts particles by cell, for memory locality.

``cluster_pairs`` groups the particles into clusters of a fixed width (SIMD lanes) for pair
loops that do not gather: the particles are binned into columns of about a cluster's width,
sorted along each column and cut into clusters of ``width`` consecutive slots (a column's last
cluster padded with empty slots), so a cluster is a compact patch. Each cluster lists, as
slots in ascending order, the union of its members' neighbours (:func:`neighbour_list` rows):
a pair loop holds a cluster's members in contiguous lanes and broadcasts each listed J to all
of them. A pair within the radius is always listed; a lane whose particle is farther from J is
a masked visit (the kernel's value there is 0).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
from numba import njit, prange

from craquelure.periodic import minimum_image


@dataclass(frozen=True)
class Box:
    """Axis-aligned box [lo_x, lo_x + length_x) x [lo_y, lo_y + length_y), periodic or open.

    For an open box particles outside the bounds are binned into the edge cells, so the bounds
    only need to be approximately right for performance, never for correctness.
    """

    length_x: float
    length_y: float
    periodic: bool = True
    lo_x: float = 0.0
    lo_y: float = 0.0

    @classmethod
    def square(cls, length: float, periodic: bool = True) -> Box:
        return cls(float(length), float(length), periodic)

    @classmethod
    def around(cls, x: np.ndarray, y: np.ndarray, pad: float) -> Box:
        lo_x, lo_y = float(x.min()) - pad, float(y.min()) - pad
        return cls(float(x.max()) + pad - lo_x, float(y.max()) + pad - lo_y, False, lo_x, lo_y)


def cells_per_side(box: Box, radius: float) -> tuple[int, int]:
    if radius <= 0:
        raise ValueError(f"search radius must be > 0, got {radius}")
    if box.periodic and (box.length_x < 2 * radius or box.length_y < 2 * radius):
        raise ValueError(
            f"periodic box {box.length_x} x {box.length_y} is smaller than twice the search "
            f"radius {radius}: the minimum image is ambiguous")
    nx = max(1, int(box.length_x / radius))
    ny = max(1, int(box.length_y / radius))
    return nx, ny


@njit(inline="always", cache=True)
def _cell_coord(v, lo, length, n, periodic):
    c = int(np.floor((v - lo) / length * n))
    if periodic:
        c %= n
    elif c < 0:
        c = 0
    elif c >= n:
        c = n - 1
    return c


@njit(cache=True)
def bin_particles(x, y, active, lo_x, lo_y, lx, ly, nx, ny, periodic):
    """Counting sort into cells: particles of cell c are ``order[start[c]:start[c+1]]``."""
    n = x.size
    cell = np.empty(n, np.int64)
    count = np.zeros(nx * ny + 1, np.int64)
    for i in range(n):
        if active[i]:
            cx = _cell_coord(x[i], lo_x, lx, nx, periodic)
            cy = _cell_coord(y[i], lo_y, ly, ny, periodic)
            cell[i] = cy * nx + cx
            count[cell[i] + 1] += 1
        else:
            cell[i] = -1
    start = np.cumsum(count)
    fill = start[:-1].copy()
    order = np.empty(start[-1], np.int64)
    for i in range(n):
        if cell[i] >= 0:
            order[fill[cell[i]]] = i
            fill[cell[i]] += 1
    return cell, start, order


@njit(inline="always", cache=True)
def _neighbour_cells(c, nx, ny, periodic, out):
    """Distinct cells around cell c (itself included); returns how many were written."""
    cx, cy = c % nx, c // nx
    k = 0
    for dy in range(-1, 2):
        for dx in range(-1, 2):
            ix, iy = cx + dx, cy + dy
            if periodic:
                ix %= nx
                iy %= ny
            elif ix < 0 or ix >= nx or iy < 0 or iy >= ny:
                continue
            cc = iy * nx + ix
            seen = False
            for j in range(k):
                if out[j] == cc:
                    seen = True
            if not seen:
                out[k] = cc
                k += 1
    return k


@njit(inline="always", cache=True)
def _difference(d, length, periodic):
    return minimum_image(d, length) if periodic else d


@njit(parallel=True, cache=True)
def _scan(x, y, cell, start, order, nx, ny, lx, ly, periodic, r2max, offsets, index, fill):
    """Pairs closer than sqrt(r2max): counted into offsets[i + 1] (``fill`` false), or
    written into index from offsets[i] on (``fill`` true, offsets the prefix sums)."""
    n = x.size
    for i in prange(n):
        if cell[i] < 0:
            continue
        cells = np.empty(9, np.int64)
        nc = _neighbour_cells(cell[i], nx, ny, periodic, cells)
        k = offsets[i] if fill else 0
        for a in range(nc):
            c = cells[a]
            for p in range(start[c], start[c + 1]):
                j = order[p]
                if j == i:
                    continue
                dx = _difference(x[i] - x[j], lx, periodic)
                dy = _difference(y[i] - y[j], ly, periodic)
                if dx * dx + dy * dy < r2max:
                    if fill:
                        index[k] = j
                    k += 1
        if not fill:
            offsets[i + 1] = k


def _points(x, y, active) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Coordinates as contiguous float64 arrays, and the active flags (default: all)."""
    x = np.ascontiguousarray(x, dtype=np.float64)
    y = np.ascontiguousarray(y, dtype=np.float64)
    return x, y, np.ones(x.size, np.bool_) if active is None else active


def neighbour_list(x: np.ndarray, y: np.ndarray, radius: float, box: Box,
                   active: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """All pairs with ``|r_I - r_J| < radius`` (minimum image if periodic), as CSR arrays."""
    x, y, active = _points(x, y, active)
    nx, ny = cells_per_side(box, radius)
    cell, start, order = bin_particles(x, y, active, box.lo_x, box.lo_y, box.length_x,
                                       box.length_y, nx, ny, box.periodic)
    offsets = np.zeros(x.size + 1, np.int64)
    args = (x, y, cell, start, order, nx, ny, box.length_x, box.length_y, box.periodic,
            radius * radius, offsets)
    _scan(*args, np.empty(0, np.int64), False)
    np.cumsum(offsets, out=offsets)
    index = np.empty(offsets[-1], np.int64)
    _scan(*args, index, True)
    return offsets, index


def cell_order(x: np.ndarray, y: np.ndarray, radius: float, box: Box) -> np.ndarray:
    """Permutation that sorts particles by cell (row-major), stable within a cell."""
    nx, ny = cells_per_side(box, radius)
    cell, _, _ = bin_particles(*_points(x, y, None), box.lo_x, box.lo_y, box.length_x,
                               box.length_y, nx, ny, box.periodic)
    return np.argsort(cell, kind="stable")


class ClusterPairs(NamedTuple):
    """Cluster-pair structure of :func:`cluster_pairs`: ``perm[s]`` is the particle in slot s
    (-1 for an empty slot; cluster c holds slots ``c * width`` to ``c * width + width - 1``),
    the J slots of cluster c are ``jlist[start[c]:start[c + 1]]``, and ``outside`` lists the
    particles in no cluster (inactive at the build)."""

    perm: np.ndarray
    start: np.ndarray
    jlist: np.ndarray
    outside: np.ndarray


@njit(parallel=True, cache=True)
def _cluster_scan(perm, slot, offsets, index, width, start, jlist, fill):
    """Union of the members' neighbour rows per cluster, as slots: counted into start[c + 1]
    (``fill`` false) or written from start[c] on and sorted (``fill`` true)."""
    nclus = perm.size // width
    nchunk = min(nclus, 64)
    for ch in prange(nchunk):
        mark = np.full(perm.size, -1, np.int64)
        for c in range(ch * nclus // nchunk, (ch + 1) * nclus // nchunk):
            k = start[c] if fill else 0
            for s in range(c * width, (c + 1) * width):
                i = perm[s]
                if i < 0:
                    continue
                for q in range(offsets[i], offsets[i + 1]):
                    js = slot[index[q]]
                    if mark[js] != c:
                        mark[js] = c
                        if fill:
                            jlist[k] = js
                        k += 1
            if fill:
                jlist[start[c]:k].sort()
            else:
                start[c + 1] = k


def cluster_pairs(x: np.ndarray, y: np.ndarray, radius: float, box: Box, width: int,
                  active: np.ndarray | None = None) -> ClusterPairs:
    """Clusters of ``width`` slots and the J slots each must visit: every active J closer than
    ``radius`` to one of a cluster's members (module docstring)."""
    x, y, active = _points(x, y, active)
    offsets, index = neighbour_list(x, y, radius, box, active)
    n_active = max(int(active.sum()), 1)
    # square clusters: a column as wide as a cluster of `width` particles at the mean density
    ncol = max(1, round(box.length_x / np.sqrt(width * box.length_x * box.length_y / n_active)))
    # slots: by column, then by y; each column padded with -1 to a multiple of width
    col, _, _ = bin_particles(x, y, active, box.lo_x, box.lo_y, box.length_x, box.length_y,
                              ncol, 1, box.periodic)
    yw = y - box.lo_y
    if box.periodic:
        yw -= box.length_y * np.floor(yw / box.length_y)
    order = np.flatnonzero(active)
    order = order[np.lexsort((yw[order], col[order]))]
    count = np.bincount(col[order], minlength=ncol)
    padded = -(-count // width) * width
    first = np.cumsum(padded) - padded
    perm = np.full(padded.sum(), -1, np.int64)
    perm[np.repeat(first - (np.cumsum(count) - count), count) + np.arange(order.size)] = order
    slot = np.full(x.size, -1, np.int64)
    real = perm >= 0
    slot[perm[real]] = np.flatnonzero(real)
    start = np.zeros(perm.size // width + 1, np.int64)
    _cluster_scan(perm, slot, offsets, index, width, start, np.empty(0, np.int64), False)
    np.cumsum(start, out=start)
    jlist = np.empty(start[-1], np.int64)
    _cluster_scan(perm, slot, offsets, index, width, start, jlist, True)
    return ClusterPairs(perm, start, jlist, np.flatnonzero(~active))


def neighbour_list_points(points: np.ndarray, radius: float,
                          box_lengths: tuple[float, ...] | None = None
                          ) -> tuple[np.ndarray, np.ndarray]:
    """All pairs with ``|r_I - r_J| < radius`` for points of any dimension (rows of
    ``points``), as the CSR arrays of :func:`neighbour_list` (both rows of every pair, each row
    sorted by J, so the order is reproducible). A k-d tree (scipy, single-threaded); with
    ``box_lengths`` the box [0, L_1) x ... is periodic (minimum image). The 3D impact engine
    uses it; the 2D cell list above stays the engines' plane search."""
    from scipy.spatial import cKDTree

    points = np.ascontiguousarray(points, dtype=np.float64)
    n = points.shape[0]
    if radius <= 0:
        raise ValueError(f"search radius must be > 0, got {radius}")
    if box_lengths is not None:
        if min(box_lengths) < 2 * radius:
            raise ValueError(f"periodic box {box_lengths} is smaller than twice the search "
                             f"radius {radius}: the minimum image is ambiguous")
        points = np.mod(points, np.asarray(box_lengths, float))
        # np.mod can round a tiny negative coordinate up to L itself, outside [0, L)
        points[points >= np.asarray(box_lengths, float)] = 0.0
    tree = cKDTree(points, boxsize=box_lengths)
    pairs = tree.query_pairs(radius * (1 - 1e-15), output_type="ndarray")
    i = np.concatenate([pairs[:, 0], pairs[:, 1]]).astype(np.int64)
    j = np.concatenate([pairs[:, 1], pairs[:, 0]]).astype(np.int64)
    order = np.lexsort((j, i))
    offsets = np.zeros(n + 1, np.int64)
    np.cumsum(np.bincount(i, minlength=n), out=offsets[1:])
    return offsets, np.ascontiguousarray(j[order])
