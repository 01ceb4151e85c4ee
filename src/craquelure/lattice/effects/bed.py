r"""Bed contact (lattice spec section 10, HiDEM defaults [C]).

A particle whose bottom :math:`y - d/2` is below the bed level :math:`y_b` is pushed up by a
spring :math:`F_y = k_b (y_b - y + d/2)` (energy :math:`\frac12 k_b \delta^2`) with damping
rate :math:`c_b` (critical: :math:`2\sqrt{k_b/m}`) on the vertical velocity and a drag-type
friction rate :math:`c_f` on the horizontal velocity; both damping terms are implicit in
the update and their work is booked as dissipation.
"""

import math

from numba import njit

from craquelure.registry import Effect, Param

EFFECT = Effect("lattice", "bed", "BED",
                "elastic bed below the body: spring + damping vertically, drag friction",
                params=(Param("bed_level", "domain.bed_level", "length", neutral=-math.inf),
                        Param("bed_stiffness", "bed.stiffness", "force/length"),
                        Param("bed_damping", None, "1/time"),  # from bed.damping_ratio and m
                        Param("bed_friction", "bed.friction_rate", "1/time")))


@njit(inline="always", cache=True)
def bed(y, d, y_bed, k_bed):
    """(overlap, force y, energy)."""
    h = y_bed - (y - 0.5 * d)
    if h <= 0.0:
        return 0.0, 0.0, 0.0
    return h, k_bed * h, 0.5 * k_bed * h * h
