r"""Monaghan velocity averaging, XSPH (drying spec section 6, Eqs. 22-23):

.. math:: \dot{\mathbf r}^I = \hat{\mathbf v}^I = \mathbf v^I
   + \epsilon \sum_J \frac{m_J}{\bar\rho_{IJ}} (\mathbf v^J - \mathbf v^I) W_{IJ},
   \qquad \bar\rho_{IJ} = (\rho^I + \rho^J)/2.

:math:`\hat{\mathbf v}` only moves particles; the velocity gradient, viscous stress and momentum
use :math:`\mathbf v` (decision of the spec). Without this effect :math:`\dot{\mathbf r} =
\mathbf v`."""

from numba import njit

from craquelure.registry import Effect, Param

EFFECT = Effect("drying", "xsph", "XSPH",
                "XSPH velocity averaging of particle transport (epsilon)",
                params=(Param("xsph_epsilon", "numerics.xsph_epsilon"),))


@njit(inline="always", cache=True)
def xsph_pair(mj, inv_rho_sum, dvx, dvy, w):
    """Contribution of J to the XSPH correction of I (before the factor epsilon), given
    ``inv_rho_sum`` = 1/(rho_I + rho_J): m_J/rho_bar_IJ = 2 m_J/(rho_I + rho_J)."""
    f = 2.0 * mj * inv_rho_sum * w
    return f * dvx, f * dvy
