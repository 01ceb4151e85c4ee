r"""SPH fields sampled on a periodic square mesh, computed with a cell list (O(mesh x
neighbours), never O(mesh x N)).

:math:`\phi(\mathbf x) = \sum_J V_J\, W(|\mathbf x - \mathbf r_J|; s)` with :math:`V_J = m_J/\rho_J`
is the Shepard (partition-of-unity) field: 1 inside intact material, about 0.5 on a free edge,
0 in a crack. The drying model binarises it (:math:`\phi \ge \phi_0`) to find fragments.
Mesh point (i, j) sits at ``(i * spacing, j * spacing)``; the array is indexed ``[j, i]``
(row = y).
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange

from craquelure.sph.kernels import kernel_kind, kernel_w
from craquelure.sph.neighbours import Box, bin_particles, cells_per_side


@njit(parallel=True, cache=True)
def _mesh_sum(x, y, value, cell, start, order, ncx, ncy, length, s, kind, n_mesh, spacing):
    out = np.zeros((n_mesh, n_mesh))
    csize = length / ncx
    reach = int(np.ceil(s / csize))
    for j in prange(n_mesh):
        py = j * spacing
        cy = int(np.floor(py / csize)) % ncy
        for i in range(n_mesh):
            px = i * spacing
            cx = int(np.floor(px / csize)) % ncx
            acc = 0.0
            for oy in range(-reach, reach + 1):
                yy = (cy + oy) % ncy
                for ox in range(-reach, reach + 1):
                    xx = (cx + ox) % ncx
                    c = yy * ncx + xx
                    for p in range(start[c], start[c + 1]):
                        q = order[p]
                        dx = px - x[q]
                        dx -= length * np.rint(dx / length)
                        dy = py - y[q]
                        dy -= length * np.rint(dy / length)
                        r2 = dx * dx + dy * dy
                        if r2 < s * s:
                            acc += value[q] * kernel_w(kind, np.sqrt(r2), s, 2)
            out[j, i] = acc
    return out


def mesh_field(x: np.ndarray, y: np.ndarray, value: np.ndarray, box_length: float,
               support: float, spacing: float, kernel: str = "quintic",
               active: np.ndarray | None = None) -> np.ndarray:
    """:math:`\\sum_J value_J W(|x - r_J|; s)` on the periodic mesh of a square box.

    ``spacing`` is rounded so that an integer number of mesh points tiles the box.
    """
    n_mesh = max(1, int(round(box_length / spacing)))
    spacing = box_length / n_mesh
    if active is None:
        active = np.ones(x.size, np.bool_)
    box = Box.square(box_length, periodic=True)
    # Cells no smaller than s/2 keep the number of cells visited per mesh point small.
    ncx, ncy = cells_per_side(box, support / 2 if box_length >= support else support)
    cell, start, order = bin_particles(np.asarray(x, np.float64), np.asarray(y, np.float64),
                                       active, 0.0, 0.0, box_length, box_length, ncx, ncy, True)
    return _mesh_sum(np.asarray(x, np.float64), np.asarray(y, np.float64),
                     np.asarray(value, np.float64), cell, start, order, ncx, ncy,
                     float(box_length), float(support), kernel_kind(kernel), n_mesh, spacing)


def mesh_spacing(box_length: float, spacing: float) -> float:
    """The spacing :func:`mesh_field` actually uses (an integer number of points per side)."""
    return box_length / max(1, int(round(box_length / spacing)))
