r"""Buoyancy below the water line (lattice spec section 10, HiDEM [C]).

A particle whose centre is below :math:`y_w` gets :math:`F_y = \rho_w g V_p` with
:math:`V_p = m/\rho_i` (net :math:`-g m (1 - \rho_w/\rho_i)` with gravity); energy
:math:`f(y) - f(y_{ref})`, :math:`f(y) = -\rho_w g V_p \min(y - y_w, 0)`. Decision [D]: the
centre decides (no partial immersion), so the force jumps at the water line.
"""

import math

from numba import njit

from craquelure.registry import Effect, Param

EFFECT = Effect("lattice", "buoyancy", "BUOYANCY",
                "buoyancy rho_w g m/rho_i on particles below the water line",
                requires=("domain.water_level",),
                params=(Param("g", "material.g", "length/time^2"),
                        Param("slope_angle", "material.slope_angle", "rad", convert=math.radians),
                        Param("water_level", "domain.water_level", "length", neutral=-math.inf,
                              optional=True),
                        Param("rho_w", "material.rho_w", "mass/area"),
                        Param("rho", "material.rho", "mass/area", neutral=1.0)))


@njit(inline="always", cache=True)
def buoyancy(m, rho, rho_w, g, y, y_ref, y_w):
    """(force y, energy relative to y_ref)."""
    w = rho_w * g * m / rho
    f = w if y < y_w else 0.0
    return f, -w * (min(y - y_w, 0.0) - min(y_ref - y_w, 0.0))
