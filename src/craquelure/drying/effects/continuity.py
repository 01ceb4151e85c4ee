r"""Continuity equation for the density (drying spec section 6, Eq. 21):
:math:`\dot\rho^I = -\rho^I\,\mathrm{tr}\,L^I`, with the SPH velocity gradient
:math:`L^I_{ab} = \sum_J V_J (v^J_a - v^I_a)\,\partial_b W_{IJ}`. Without this effect the
density stays at its initial value."""

from numba import njit

from craquelure.registry import Effect

EFFECT = Effect("drying", "continuity", "CONTINUITY",
                "density from the continuity equation d rho/dt = -rho tr L")


@njit(inline="always", cache=True)
def density_rate(rho, lxx, lyy):
    return -rho * (lxx + lyy)
