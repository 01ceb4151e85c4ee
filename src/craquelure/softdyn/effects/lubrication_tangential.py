r"""Tangential lubrication (Couette shear of the film over the area pi a^2), spec section 3.

.. math::
    f^{visc}_t = -\zeta_t\, Q u_{ij}, \qquad \zeta_t = c_t\, \eta\, a^2 / h \quad (c_t = \pi),
    \qquad \zeta_t/\zeta_n = (c_t/c_n)\, h^2/a^2

The exact sphere-sphere sliding resistance carries a weak ln(R/h); the model keeps the plain
Couette form (as the paper does). Without this effect the pair is frictionless in sliding: the
tangential force and the tangential deflection q vanish identically, q is not part of the state,
and the tangential velocity may be undetermined (a pair with no force can slide freely), so the
velocity system is then solved in the minimum-norm least-squares sense [D].
"""

import math

from numba import njit

from craquelure.registry import Effect, Param

EFFECT = Effect("softdyn", "lubrication_tangential", "LUBRICATION_TANGENTIAL",
                "Couette sliding film, zeta_t = c_t eta a^2 / h",
                params=(Param("eta", "material.viscosity", "viscosity"),
                        # no sliding film when off: the Couette prefactor pi (compiled out)
                        Param("c_t", "material.c_t", neutral=math.pi)))


@njit(inline="always", cache=True)
def zeta_tangential(eta, c_t, a2, h):
    """Tangential friction coefficient zeta_t = c_t eta a^2 / h (``a2`` = a^2)."""
    return c_t * eta * a2 / h
