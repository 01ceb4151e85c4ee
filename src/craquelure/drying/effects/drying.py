r"""Drying stress (drying spec section 2): :math:`\sigma_{dry} = v_r\, t\, \mathbf 1`, isotropic
and linear in time; in 2D it adds :math:`v_r t` to :math:`\sigma_{xx}` and :math:`\sigma_{yy}`.
Tension is positive. An optional cap holds the stress at F = ``material.drying_stress_cap`` once
:math:`v_r t` reaches it (used for the quasi-static strip check, spec 13.10)."""

import math

from numba import njit

from craquelure.registry import Effect, Param

EFFECT = Effect("drying", "drying", "DRYING", "isotropic drying stress sigma_dry = v_r t 1",
                params=(Param("drying_rate", "material.drying_rate", "stress/time"),
                        # absent: sigma_dry grows without bound
                        Param("drying_stress_cap", "material.drying_stress_cap", "stress",
                              neutral=math.inf, optional=True)),
                diagnostics=("kappa_max", "kappa_criterion_max"))


@njit(inline="always", cache=True)
def drying_stress(t, v_r, cap):
    return min(v_r * t, cap)
