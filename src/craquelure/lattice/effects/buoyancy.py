r"""Buoyancy below the water line (lattice spec section 10, HiDEM [C]).

A particle whose centre is below :math:`y_w` gets :math:`F_y = \rho_w g V_p` with
:math:`V_p = m/\rho_i` (net :math:`-g m (1 - \rho_w/\rho_i)` with gravity); energy
:math:`f(y) - f(y_{ref})`, :math:`f(y) = -\rho_w g V_p \min(y - y_w, 0)`. Decision [D]: the
centre decides (no partial immersion), so the force jumps at the water line.
"""

from numba import njit

from craquelure.registry import Effect

EFFECT = Effect("lattice", "buoyancy", "BUOYANCY",
                "buoyancy rho_w g m/rho_i on particles below the water line",
                requires=("material.g", "material.rho_w", "material.rho", "domain.water_level"))


@njit(inline="always", cache=True)
def buoyancy(m, rho, rho_w, g, y, y_ref, y_w):
    """(force y, energy relative to y_ref)."""
    w = rho_w * g * m / rho
    f = w if y < y_w else 0.0
    return f, -w * (min(y - y_w, 0.0) - min(y_ref - y_w, 0.0))
