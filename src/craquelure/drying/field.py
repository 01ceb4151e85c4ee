r"""SPH fields sampled on a periodic square mesh, computed with a neighbour search (O(mesh x
neighbours), never O(mesh x N)).

:math:`\phi(\mathbf x) = \sum_J V_J\, W(|\mathbf x - \mathbf r_J|; s)` with :math:`V_J = m_J/\rho_J`
is the Shepard (partition-of-unity) field: 1 inside intact material, about 0.5 on a free edge, 0 in
a crack. The drying model binarises it (:math:`\phi \ge \phi_0`) to find fragments. Mesh point (i,
j) sits at ``(i * spacing, j * spacing)``; the array is indexed ``[j, i]`` (row = y).

Method: particles are sorted by y (a one-dimensional cell list of strips). Each mesh row j
(in parallel) visits only the particles with :math:`|y_J - y_j| < s` (minimum image) and, for
each, only the mesh points of that row inside the support circle,
:math:`|x_i - x_J| \le \sqrt{s^2 - (y_j - y_J)^2}`. Every kernel evaluation therefore lands
inside the support (about :math:`\pi s^2 n` per mesh point for particle number density n), with
no wasted distance tests, and each row is written by one thread only.

A binary image :math:`\phi \ge \phi_0` (:func:`mesh_image`) needs the sum only where
:math:`\phi` can cross :math:`\phi_0`. The mesh is cut into square blocks (side
``BLOCK_SIDE`` x s); since W does not increase with r, the sum of :math:`V_J W` at each
particle's farthest point of a block bounds :math:`\phi` on the block from below, and at its
nearest point from above. Blocks whose lower bound clears :math:`\phi_0` (by ``ROUNDING``, far
above the round-off of either sum) are paste, blocks whose upper bound stays under it are
crack, and only the rest, along the edges of cracks and removed particles, are summed, point by
point exactly as for the whole field: the same terms in the same order, so the same bits."""

from __future__ import annotations

import numpy as np
from numba import njit, prange

from craquelure.periodic import minimum_image
from craquelure.sph.kernels import kernel_kind, kernel_w

# Side of the blocks mesh_image bounds, in units of the support: the lower bound falls short of
# the field by about (half-diagonal) x integral of |grad W| (5.3/s for the quintic), which must
# stay well under 1 - phi0 for the blocks inside the paste to be classified at once.
BLOCK_SIDE = 0.04
# Bounds and field are sums of O(100) terms of O(1) rounded to 1e-16 each: a block is certainly
# above (below) the level only with this margin.
ROUNDING = 1e-9
TABLE = 16384  # points of the table of W in r^2 the block bounds read


@njit(inline="always", cache=True)
def _add_row_range(acc, next_need, next_free, block, x, y, value, order, lo, hi, py, length, s,
                   kind, n_mesh, spacing):
    """Scatter the particles order[lo:hi] into the mesh row at height py, in the column blocks
    of width ``block`` that are needed (``next_need[b]``, ``next_free[b]``: the first block from
    b on that is, that is not). Columns go one run of needed blocks, up to the wrap, at a time:
    no index needs a modulo."""
    for p in range(lo, hi):
        q = order[p]
        dy = minimum_image(py - y[q], length)
        rem = s * s - dy * dy
        if rem <= 0.0:
            continue
        half = np.sqrt(rem)
        xq, vq = x[q], value[q]  # locals: the loop below then vectorises
        i_lo = int(np.ceil((xq - half) / spacing))
        i_hi = int(np.floor((xq + half) / spacing))
        if i_hi - i_lo + 1 > n_mesh:  # support wider than the box: visit each point once
            i_hi = i_lo + n_mesh - 1
        i, c = i_lo, i_lo % n_mesh  # i unwrapped (it sets dx), c its column
        while i <= i_hi:
            b = c // block
            step = min(next_need[b] * block, n_mesh) - c
            if step <= 0:  # c is in a needed block: up to the next block not needed or i_hi
                step = min(next_free[b] * block, n_mesh) - c
                step = min(step, i_hi + 1 - i)
                segment = acc[c:c + step]
                for m in range(step):  # m >= 0: no negative-index wraparound
                    dx = (i + m) * spacing - xq
                    r2 = dx * dx + dy * dy
                    if r2 < s * s:
                        segment[m] += vq * kernel_w(kind, np.sqrt(r2), s, 2)
            i += step
            c += step
            if c == n_mesh:
                c = 0


@njit(parallel=True, cache=True)
def _mesh_sum_rows(x, y, value, order, y_sorted, length, s, kind, n_mesh, spacing, need, block,
                   above, level, field, image):
    """The field on the mesh points of the blocks (``block`` x ``block`` points) where ``need``
    is set, into ``field`` (0 elsewhere) unless it is empty, and the image into ``image`` unless
    it is empty: 1 in the blocks ``above``, field >= level in those summed, 0 elsewhere."""
    n = order.size
    n_block = need.shape[1]
    for j in prange(n_mesh):
        next_need = np.empty(n_block + 1, np.int64)
        next_free = np.empty(n_block + 1, np.int64)
        next_need[n_block] = next_free[n_block] = n_block
        for b in range(n_block - 1, -1, -1):
            needed = need[j // block, b]
            next_need[b] = b if needed else next_need[b + 1]
            next_free[b] = next_free[b + 1] if needed else b
        acc = np.zeros(n_mesh)
        if next_need[0] < n_block:
            py = j * spacing
            lo_y, hi_y = py - s, py + s
            # The strip [py - s, py + s) wrapped into [0, L): one or two index ranges.
            if lo_y < 0.0:
                a = np.searchsorted(y_sorted, lo_y + length)
                _add_row_range(acc, next_need, next_free, block, x, y, value, order, a, n, py,
                               length, s, kind, n_mesh, spacing)
                lo_y = 0.0
            if hi_y > length:
                b = np.searchsorted(y_sorted, hi_y - length, side="right")
                _add_row_range(acc, next_need, next_free, block, x, y, value, order, 0, b, py,
                               length, s, kind, n_mesh, spacing)
                hi_y = length
            a = np.searchsorted(y_sorted, lo_y)
            b = np.searchsorted(y_sorted, hi_y, side="right")
            _add_row_range(acc, next_need, next_free, block, x, y, value, order, a, b, py,
                           length, s, kind, n_mesh, spacing)
        if field.size:
            field[j] = acc
        if image.size:
            bj = j // block
            for bi in range(n_block):
                for i in range(bi * block, min(bi * block + block, n_mesh)):
                    image[j, i] = above[bj, bi] or (need[bj, bi] and acc[i] >= level)


@njit(parallel=True, cache=True)
def _block_bounds(x, y, value, order, y_sorted, length, s, kind, n_mesh, spacing, block):
    """Lower and upper bounds of the field over each block of ``block`` x ``block`` mesh points
    (module docstring), W read from a table in r^2 at the grid point beyond (lower) or before
    (upper). Each block row visits the particles of its strip and, for each, the blocks within
    the support; every block counts as a whole one (the last may be smaller): bounds stay bounds."""
    n = order.size
    n_block = (n_mesh + block - 1) // block
    width = block * spacing
    h = 0.5 * (block - 1) * spacing  # half-width of a block's points
    table = np.empty(TABLE + 1)
    for k in range(TABLE + 1):
        table[k] = kernel_w(kind, s * np.sqrt(k / TABLE), s, 2)
    table[TABLE] = 0.0
    per_r2 = TABLE / (s * s)
    lower = np.zeros((n_block, n_block))
    upper = np.zeros((n_block, n_block))
    for bj in prange(n_block):
        yc = bj * width + h
        if 2.0 * (h + s) >= length:
            a, count = 0, n
        else:
            a = np.searchsorted(y_sorted, (yc - h - s) % length)
            count = (np.searchsorted(y_sorted, (yc + h + s) % length, side="right") - a) % n
        lo, up = lower[bj], upper[bj]
        for t in range(count):
            q = order[(a + t) % n]
            vq = value[q]
            dy = abs(minimum_image(y[q] - yc, length))
            near_y = max(dy - h, 0.0)
            if near_y >= s:
                continue
            far_y2 = (dy + h) * (dy + h)
            reach = np.sqrt(s * s - near_y * near_y)
            # one block more on each side: the last block may be narrower than the others
            b_lo = int(np.floor((x[q] - reach) / width)) - 1
            b_hi = min(int(np.floor((x[q] + reach) / width)) + 1, b_lo + n_block - 1)
            for b in range(b_lo, b_hi + 1):
                bi = b + n_block if b < 0 else (b - n_block if b >= n_block else b)
                dx = abs(minimum_image(x[q] - bi * width - h, length))
                near_x = max(dx - h, 0.0)
                near = (near_x * near_x + near_y * near_y) * per_r2
                if near < TABLE:
                    up[bi] += vq * table[int(near)]
                    far = ((dx + h) * (dx + h) + far_y2) * per_r2
                    if far < TABLE:
                        lo[bi] += vq * table[int(np.ceil(far))]
    return lower, upper


def _prepare(x, y, value, box_length, support, spacing, active):
    if box_length < 2 * support:
        raise ValueError(f"periodic box {box_length} is smaller than twice the kernel support "
                         f"{support}: the minimum image is ambiguous")
    n_mesh = max(1, int(round(box_length / spacing)))
    length = float(box_length)
    keep = np.ones(len(x), np.bool_) if active is None else np.asarray(active).astype(np.bool_)
    # Wrap into [0, L) so the sorted strips and the minimum image agree.
    xw, yw = (np.mod(np.asarray(v, np.float64), length) for v in (x, y))
    order = np.flatnonzero(keep)
    order = order[np.argsort(yw[order], kind="stable")].astype(np.int64)
    return xw, yw, np.asarray(value, np.float64), order, n_mesh, length / n_mesh


def mesh_field(x: np.ndarray, y: np.ndarray, value: np.ndarray, box_length: float,
               support: float, spacing: float, kernel: str = "quintic",
               active: np.ndarray | None = None) -> np.ndarray:
    """:math:`\\sum_J value_J W(|x - r_J|; s)` on the periodic mesh of a square box, ``spacing``
    rounded so that an integer number of points tiles it, inactive particles (``active == 0``)
    left out. The box must be at least twice the support wide (else the minimum image is
    ambiguous, as in the neighbour search)."""
    xw, yw, value, order, n_mesh, spacing = _prepare(x, y, value, box_length, support, spacing,
                                                     active)
    field = np.empty((n_mesh, n_mesh))
    whole = np.ones((1, 1), np.bool_)
    _mesh_sum_rows(xw, yw, value, order, yw[order], float(box_length), float(support),
                   kernel_kind(kernel), n_mesh, spacing, whole, n_mesh, ~whole, 0.0, field,
                   np.empty((0, 0), np.bool_))
    return field


def mesh_image(x: np.ndarray, y: np.ndarray, value: np.ndarray, box_length: float,
               support: float, spacing: float, kernel: str, level: float,
               active: np.ndarray | None = None) -> np.ndarray:
    """``mesh_field(...) >= level``, the same image bit for bit, with the field summed only in
    the blocks of mesh points where it can reach ``level`` (module docstring)."""
    xw, yw, value, order, n_mesh, spacing = _prepare(x, y, value, box_length, support, spacing,
                                                     active)
    length, s, kind = float(box_length), float(support), kernel_kind(kernel)
    block = min(1 + round(BLOCK_SIDE * s / spacing), n_mesh)
    if block < 3:  # blocks of a point or two: bounding them costs as much as the sum
        above, need, block = np.zeros((1, 1), np.bool_), np.ones((1, 1), np.bool_), n_mesh
    else:
        lower, upper = _block_bounds(xw, yw, value, order, yw[order], length, s, kind, n_mesh,
                                     spacing, block)
        above = lower >= level + ROUNDING
        need = ~above & (upper >= level - ROUNDING)
    image = np.empty((n_mesh, n_mesh), np.bool_)
    _mesh_sum_rows(xw, yw, value, order, yw[order], length, s, kind, n_mesh, spacing, need, block,
                   above, level, np.empty((0, 0)), image)
    return image


def mesh_spacing(box_length: float, spacing: float) -> float:
    """The spacing :func:`mesh_field` actually uses (an integer number of points per side)."""
    return box_length / max(1, int(round(box_length / spacing)))
