r"""Linear water drag (lattice spec section 10): :math:`F = -c_d\, m\, v` on particles below
the water line (``drag.everywhere`` applies it to all particles). It enters the
central-difference update implicitly as an extra per-particle damping rate :math:`c_d`
(like the mass damping C = c M of section 5); its work is booked as dissipation."""

import math

from numba import njit

from craquelure.registry import Effect, Param

EFFECT = Effect("lattice", "drag", "DRAG", "linear drag -c_d m v below the water line",
                params=(Param("drag_rate", "drag.rate", "1/time"),
                        Param("drag_everywhere", "drag.everywhere"),
                        Param("water_level", "domain.water_level", "length", neutral=-math.inf,
                              optional=True)))


@njit(inline="always", cache=True)
def drag_rate(y, y_w, rate, everywhere):
    if everywhere or y < y_w:
        return rate
    return 0.0
