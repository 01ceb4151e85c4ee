r"""Hertz-like elastic response of the two facing surfaces, spec section 4.

.. math::
    f^{el}_{ij} = K\,\delta_{ij},\quad K = E a (k_n P + k_t Q),\quad
    \delta_{ij} = s\,n + q,\quad a^2 = R\,(h + |s|),\quad h = r - 2R + s

``s > 0`` is compression (facing surfaces flattened), ``s < 0`` suction. In the Hertz limit
:math:`f_n = k_n E R^{1/2} |s|^{3/2}`. The interpolation :math:`a^2 = R(h+|s|)` is ours [R]: the
paper only fixes its two limits (Poiseuille a^2 ~ R h, Hertz a^2 ~ R|s|).
The elastic element is in series with the film (pair balance f^visc = f^el), so the deflection
relaxes at the material rate :math:`w = -(v_i - v_j) - Z^{-1} f` (a Maxwell element).

Deflection rule (scene option ``numerics.deflection_rule``):

* ``corotating`` (default [D]): :math:`\dot s = n\cdot w`, :math:`\dot q = Q w - n(\dot n\cdot q)`
  (q is parallel-transported with the pair frame). The gap law :math:`\dot h = -f_n/\zeta_n` holds
  exactly.
* ``literal`` (opt-in, flagged in spec 9.3): δ is a lab-frame vector with :math:`\dot\delta = w`, so
  :math:`\dot s = n\cdot w + \dot n\cdot q` and :math:`\dot q = Q w - n(\dot n\cdot q) - s\dot n`;
  tangential deflection leaks into normal deflection as the pair rotates, the gap law gains
  :math:`+\dot n\cdot q`, and in the Hertz regime the T1 jams.

Without this effect the spheres are rigid (δ = 0, :math:`a^2 = R h`) and the pair force is the
lubrication force itself, :math:`f_{ij} = -Z(v_i - v_j)`.
"""

from numba import njit

from craquelure.registry import Effect, Param

EFFECT = Effect("softdyn", "hertz", "HERTZ",
                "elastic surfaces f = E a (k_n s n + k_t q), a^2 = R (h + |s|)",
                requires=("material.young",),
                # rigid spheres when off: unit stiffnesses (compiled out; the Hertz theory's h*
                # of a rigid scene is quoted at k_n = 1)
                params=(Param("k_n", "material.k_n", neutral=1.0),
                        Param("k_t", "material.k_t", neutral=1.0)))


@njit(inline="always", cache=True)
def interaction_radius2(radius, h, s):
    """a^2 = R (h + |s|), the interpolated interaction radius squared."""
    return radius * (h + abs(s))


@njit(inline="always", cache=True)
def sign(s):
    """sgn(s) with sgn(0) = 0 (derivative of |s|; all pairs start at s = 0)."""
    if s > 0.0:
        return 1.0
    if s < 0.0:
        return -1.0
    return 0.0
