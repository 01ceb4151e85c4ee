"""The Shepard field on the mesh as `craquelure fragments` summed it up to commit 4db0bf1 (every
mesh point, the row-strip neighbour search of craquelure.drying.field then): the reference the
block-classified image of :func:`craquelure.drying.field.mesh_image` must equal bit for bit
(tests/drying/test_field.py, benchmarks/drying_labelling.py)."""

from __future__ import annotations

import numpy as np
from numba import njit, prange

from craquelure.periodic import minimum_image
from craquelure.sph.kernels import kernel_kind, kernel_w


@njit(inline="always", cache=True)
def _add_row_range(acc, x, y, value, order, lo, hi, py, length, s, kind, n_mesh, spacing):
    """Scatter the particles order[lo:hi] into the mesh row at height py."""
    for p in range(lo, hi):
        q = order[p]
        dy = py - y[q]
        dy = minimum_image(dy, length)
        rem = s * s - dy * dy
        if rem <= 0.0:
            continue
        half = np.sqrt(rem)
        i_lo = int(np.ceil((x[q] - half) / spacing))
        i_hi = int(np.floor((x[q] + half) / spacing))
        if i_hi - i_lo + 1 > n_mesh:  # support wider than the box: visit each point once
            i_hi = i_lo + n_mesh - 1
        for i in range(i_lo, i_hi + 1):
            dx = i * spacing - x[q]
            r2 = dx * dx + dy * dy
            if r2 < s * s:
                acc[i % n_mesh] += value[q] * kernel_w(kind, np.sqrt(r2), s, 2)


@njit(parallel=True, cache=True)
def _mesh_sum_rows(x, y, value, order, y_sorted, length, s, kind, n_mesh, spacing):
    out = np.zeros((n_mesh, n_mesh))
    n = order.size
    for j in prange(n_mesh):
        py = j * spacing
        acc = out[j]
        lo_y, hi_y = py - s, py + s
        # The strip [py - s, py + s) wrapped into [0, L): one or two index ranges.
        if lo_y < 0.0:
            a = np.searchsorted(y_sorted, lo_y + length)
            _add_row_range(acc, x, y, value, order, a, n, py, length, s, kind, n_mesh, spacing)
            lo_y = 0.0
        if hi_y > length:
            b = np.searchsorted(y_sorted, hi_y - length, side="right")
            _add_row_range(acc, x, y, value, order, 0, b, py, length, s, kind, n_mesh, spacing)
            hi_y = length
        a = np.searchsorted(y_sorted, lo_y)
        b = np.searchsorted(y_sorted, hi_y, side="right")
        _add_row_range(acc, x, y, value, order, a, b, py, length, s, kind, n_mesh, spacing)
    return out


def mesh_field(x: np.ndarray, y: np.ndarray, value: np.ndarray, box_length: float,
               support: float, spacing: float, kernel: str = "quintic",
               active: np.ndarray | None = None) -> np.ndarray:
    """:math:`\\sum_J value_J W(|x - r_J|; s)` on the periodic mesh of a square box.

    ``spacing`` is rounded so that an integer number of mesh points tiles the box.
    Inactive particles (``active == 0``) do not contribute. The box must be at least twice the
    support wide (otherwise the minimum image is ambiguous, as in the neighbour search).
    """
    if box_length < 2 * support:
        raise ValueError(f"periodic box {box_length} is smaller than twice the kernel support "
                         f"{support}: the minimum image is ambiguous")
    n_mesh = max(1, int(round(box_length / spacing)))
    spacing = box_length / n_mesh
    length = float(box_length)
    x = np.asarray(x, np.float64)
    y = np.asarray(y, np.float64)
    value = np.asarray(value, np.float64)
    keep = np.ones(x.size, np.bool_) if active is None else np.asarray(active).astype(np.bool_)
    # Wrap into [0, L) so the sorted strips and the minimum image agree.
    xw = np.mod(x, length)
    yw = np.mod(y, length)
    order = np.flatnonzero(keep)
    order = order[np.argsort(yw[order], kind="stable")].astype(np.int64)
    return _mesh_sum_rows(xw, yw, value, order, yw[order], length, float(support),
                          kernel_kind(kernel), n_mesh, spacing)
