r"""Elastic gravity check (lattice spec section 10, check 10).

A block with its bottom row clamped settles under gravity by :math:`\rho_2 g H^2/(2M)` at
the top, for a laterally constrained column (uniaxial strain, M = lambda + 2 mu; exact for a
block periodic in x, approximate in the middle of a wide block). Discrete lattice [D]: with
n rows above the clamped row (row spacing h), the rows carry n, n-1, ..., 1 particle
weights, so the settlement is :math:`\rho_2 g h^2 n(n+1)/(2M)`, i.e. the continuum formula
with :math:`H = (n + 1/2)h` to O(1/n^2): every particle stands for a cell of height h.
"""

import numpy as np

from craquelure.lattice import beam
from craquelure.lattice.geometry import ROW


def effective_height(ny: int, L: float = 1.0) -> float:  # noqa: N803
    return (ny - 1 + 0.5) * ROW * L


def predicted_settlement(kn: float, ks: float, mass: float, g: float, ny: int,
                         L: float = 1.0) -> float:  # noqa: N803
    m = beam.lattice_moduli(kn, ks)["M"]
    rho2 = mass / beam.cell_area(L)
    return rho2 * g * effective_height(ny, L) ** 2 / (2.0 * m)


def measured_settlement(y0: np.ndarray, y: np.ndarray, row: np.ndarray, x0: np.ndarray,
                        central_fraction: float = 0.2) -> float:
    """Mean downward displacement of the top row within the central fraction of the width."""
    top = row == row.max()
    xc = 0.5 * (x0[top].min() + x0[top].max())
    half = 0.5 * central_fraction * (x0[top].max() - x0[top].min())
    sel = top & (np.abs(x0 - xc) <= max(half, 0.5))
    return float(np.mean(y0[sel] - y[sel]))
