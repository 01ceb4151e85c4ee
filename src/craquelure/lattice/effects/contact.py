r"""Contact between unbonded particles (lattice spec section 6, HiDEM ``glas.f90``).

Repulsion along the centre line for :math:`r < d = (d_i + d_j)/2`:
:math:`F = k_c (d - r)^{3/2}`, energy :math:`0.4\,k_c (d - r)^{5/2}`. Optional friction [D]:
a regularised Coulomb force against the relative tangential velocity of the centres,
:math:`F_t = -\min(\mu F, c_t |v_t|)\,\mathrm{sign}(v_t)` (no rotation coupling, so it
exerts no torque); its work is booked as dissipation. Pairs come from a Verlet list (radius
d + skin) rebuilt when a particle has moved more than skin/2 or a beam has broken.
"""

import math

from numba import njit

from craquelure.registry import Effect, Param

EFFECT = Effect("lattice", "contact", "CONTACT",
                "Hertz-like repulsion k_c (d - r)^1.5 between unbonded particles, with friction",
                params=(Param("contact_stiffness", "contact.stiffness", "force/length^1.5"),
                        Param("friction", "contact.friction"),
                        # NaN when off: the engine refuses a contact run without them
                        Param("skin", "contact.skin", "length", neutral=math.nan),
                        Param("friction_viscosity", "contact.friction_viscosity", "time",
                              neutral=math.nan)))


@njit(inline="always", cache=True)
def repulsion(r, d, kc):
    """(force magnitude, energy) of an overlapping pair (zero when r >= d)."""
    if r >= d:
        return 0.0, 0.0
    h = d - r
    s = math.sqrt(h)
    return kc * h * s, 0.4 * kc * h * h * s


@njit(inline="always", cache=True)
def friction(fn, vt, mu, ct):
    """Regularised Coulomb friction force along t for a tangential relative speed vt."""
    f = min(mu * fn, ct * abs(vt))
    return -f if vt > 0 else f
