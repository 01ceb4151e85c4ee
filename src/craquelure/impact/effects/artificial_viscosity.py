r"""Monaghan artificial viscosity (spec section 3).

.. math::
    \Pi_{ij} = \frac{-\alpha_{AV} c_p \mu_{ij} + \beta_{AV}\mu_{ij}^2}{\bar\rho_{ij}}
    \;\text{ if } v_{ij}\cdot r_{ij} < 0, \text{ else } 0, \qquad
    \mu_{ij} = \frac{h_{ij}\, v_{ij}\cdot r_{ij}}{r_{ij}^2 + 0.01 h_{ij}^2},

entering the momentum equation as :math:`-\Pi_{ij}\mathbf 1` inside the pair bracket; its
dissipation rate :math:`\tfrac12\sum_{ij} m_i m_j \Pi_{ij} v_{ij}\cdot\nabla_i W_{ij} \ge 0` is
accumulated for the energy balance. :math:`\bar\rho_{ij} = (\rho_i+\rho_j)/2`,
:math:`c_p = \sqrt{(K + 4G/3)/\rho_0}`; :math:`|\mu_{ij}|` also enters the time step.
"""

from numba import njit

from craquelure.registry import Effect, Param

EFFECT = Effect("impact", "artificial_viscosity", "ARTIFICIAL_VISCOSITY",
                "Monaghan artificial viscosity (alpha_AV, beta_AV)",
                params=(Param("av_alpha", "numerics.av_alpha"),
                        Param("av_beta", "numerics.av_beta")))


@njit(inline="always", cache=True)
def monaghan_pi(vdotr, r2, hij, rho_bar, c, alpha, beta):
    """Returns (Pi_ij, mu_ij); zero for receding pairs."""
    if vdotr >= 0.0:
        return 0.0, 0.0
    mu = hij * vdotr / (r2 + 0.01 * hij * hij)
    return (-alpha * c * mu + beta * mu * mu) / rho_bar, mu
