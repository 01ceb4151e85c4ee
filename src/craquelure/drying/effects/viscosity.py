r"""Voigt viscous stress (drying spec section 2): :math:`\sigma_{vis} = \eta D`
(no factor 2), :math:`D = (L + L^T)/2`, added to the total stress at every rate evaluation."""

from numba import njit

from craquelure.registry import Effect, Param

EFFECT = Effect("drying", "viscosity", "VISCOSITY", "Voigt viscous stress sigma_vis = eta D",
                params=(Param("eta", "material.eta", "stress time"),))


@njit(inline="always", cache=True)
def viscous_stress(lxx, lxy, lyx, lyy, eta):
    """(sxx, syy, sxy) of eta D."""
    return eta * lxx, eta * lyy, 0.5 * eta * (lxy + lyx)
