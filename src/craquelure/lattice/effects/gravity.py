r"""Gravity, optionally along a slope (lattice spec sections 5 and 10).

:math:`F = m g (\sin\beta, -\cos\beta)` on every particle (:math:`\beta` =
``material.slope_angle`` in degrees, 0: vertical gravity; a slab on an inclined bed is
simulated in the frame of the bed, x along the slope), energy
:math:`-F\cdot(r - r_{ref})` with the initial positions as reference.
"""

import math

from numba import njit

from craquelure.registry import Effect, Param

EFFECT = Effect("lattice", "gravity", "GRAVITY",
                "uniform gravity m g, vertical or along a slope (material.slope_angle)",
                params=(Param("g", "material.g", "length/time^2"),
                        Param("slope_angle", "material.slope_angle", "rad", convert=math.radians)))


@njit(inline="always", cache=True)
def gravity(m, gx, gy, x, y, x_ref, y_ref):
    """(force x, force y, energy relative to the reference position); (gx, gy) = g (sin b,
    -cos b)."""
    fx, fy = m * gx, m * gy
    return fx, fy, -(fx * (x - x_ref) + fy * (y - y_ref))
