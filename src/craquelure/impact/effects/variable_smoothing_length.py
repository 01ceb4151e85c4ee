r"""Benz variable smoothing length (spec section 3, source eq. 7).

.. math::
    \frac{dh_i}{dt} = -\frac{h_i}{d\,\rho_i}\frac{d\rho_i}{dt} = \frac{h_i}{d}\,\mathrm{tr}L_i,
    \qquad h_i \in [h_{min}, h_{max}]\, h_i(0) \;(0.2, 2.0).

Decision [D]: with the discrete continuity equation :math:`d\rho_i/dt = -\rho_i\,\mathrm{tr}L_i`
holds exactly, and both are integrated exactly over a step with the mid-step
:math:`\mathrm{tr}L_i` (:math:`\rho \leftarrow \rho e^{-\mathrm{tr}L\,\Delta t}`,
:math:`h \leftarrow h e^{\mathrm{tr}L\,\Delta t/d}`), so :math:`h\rho^{1/d}` is invariant to
round-off until the clamp acts (check 5). Without this effect h stays h(0) = κ·1.2Δ.
"""

import math

from numba import njit

from craquelure.registry import Effect, Param

EFFECT = Effect("impact", "variable_smoothing_length", "VARIABLE_SMOOTHING_LENGTH",
                "Benz smoothing-length evolution dh/dt = (h/d) tr L, clamped",
                params=(Param("h_min", "numerics.h_min", "m"),
                        Param("h_max", "numerics.h_max", "m")))


@njit(inline="always", cache=True)
def benz_update(h, h0, tr_l, dt, dim, h_min, h_max):
    new = h * math.exp(tr_l * dt / dim)
    return min(max(new, h_min * h0), h_max * h0)
