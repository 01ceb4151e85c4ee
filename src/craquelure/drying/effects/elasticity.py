r"""Hypo-elastic stress with the Jaumann rate (drying spec section 2).

.. math::
    \dot\sigma_e = \lambda\,\mathrm{tr}(D)\,\mathbf 1 + 2\mu D + \Omega\sigma_e - \sigma_e\Omega,

with :math:`L_{ab} = \partial v_a/\partial x_b`, :math:`D = (L + L^T)/2`,
:math:`\Omega = (L - L^T)/2`. In 2D (components xx, yy, xy), with :math:`w = \Omega_{xy}`:
:math:`(\Omega\sigma - \sigma\Omega)_{xx} = 2 w \sigma_{xy}`,
:math:`(\ldots)_{yy} = -2 w \sigma_{xy}`, :math:`(\ldots)_{xy} = w(\sigma_{yy} - \sigma_{xx})`."""

from numba import njit

from craquelure.registry import Effect, Param

EFFECT = Effect("drying", "elasticity", "ELASTICITY",
                "hypo-elastic stress, Jaumann rate (lambda, mu)",
                params=(Param("lame_lambda", "material.lame_lambda", "stress"),
                        Param("lame_mu", "material.lame_mu", "stress")),
                diagnostics=("elastic_energy",))


@njit(inline="always", cache=True)
def jaumann_rate(lxx, lxy, lyx, lyy, sxx, syy, sxy, lam, mu):
    """Rates (dsxx, dsyy, dsxy) of the elastic stress for velocity gradient L."""
    dxx, dyy = lxx, lyy
    dxy = 0.5 * (lxy + lyx)
    w = 0.5 * (lxy - lyx)
    tr = dxx + dyy
    return (lam * tr + 2.0 * mu * dxx + 2.0 * w * sxy,
            lam * tr + 2.0 * mu * dyy - 2.0 * w * sxy,
            2.0 * mu * dxy + w * (syy - sxx))
