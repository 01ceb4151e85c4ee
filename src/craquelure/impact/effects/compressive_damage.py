r"""Compressive (ductile) damage: softening of the shear surface after crushing (impact spec
section 2 item 5; CSCM's ductile damage with G_fc ≈ 100 G_ft, Murray 2007).

.. math::
    D_c = \min\!\left(D_{c,max},\; \frac{\bar\varepsilon_p}{\varepsilon_{fc}}\right), \qquad
    \varepsilon_{fc} = \frac{G_{fc}/\ell_c}{\int_0^{D_{c,max}} \sigma_u(D)\,dD},
    \qquad G_{fc} = 100\,G_F,

and the shear surface of :mod:`.cap_plasticity` is scaled by :math:`1 - D_c` (the pressure is
not damaged: crushed concrete under confinement still carries pressure, and a fully damaged
point keeps a hydrostatic stress only). :math:`\sigma_u(D)` is the uniaxial compressive
strength of the damaged surface, the root of :math:`\sigma/\sqrt3 = (1-D)F_f(\sigma)`
(:math:`\sigma_u(0) = f_c`); since :math:`d\bar\varepsilon_p = \varepsilon_{fc}\,dD` in uniaxial
compression, the plastic work after the peak is :math:`\varepsilon_{fc}\int\sigma_u dD =
G_{fc}/\ell_c`: the crushing band ℓ_c (the tensile crack band, :func:`.damage.crack_band_width`)
dissipates G_fc per unit area. The curved meridian and CSCM's cap make σ_u fall faster than
1 − D (the strength drops with the pressure), ∫σ_u dD = 0.30 f_c instead of 0.5 f_c, so
ε_fc = 0.081 at ℓ_c = 8 mm (0.048 for a linear drop).
:math:`D_{c,max}` = 0.99 keeps a residual shear strength
of 1 % (a fluid-like crushed zone would let the contact particles interpenetrate).

Differences from CSCM [D]: CSCM's ductile damage is an exponential function of an energy norm
of the total strain with a threshold on the initial surface and scales the whole stress; here it
is linear in ε̄_p and acts on the deviatoric strength only.
"""

import math

import numpy as np
from numba import njit

from craquelure.impact.effects import F_C, G_F
from craquelure.registry import Effect

EFFECT = Effect("impact", "compressive_damage", "COMPRESSIVE_DAMAGE", "ductile damage: shear "
                "surface x (1 - D_c), D_c linear in plastic strain, G_fc = 100 G_F (needs "
                "cap_plasticity)", params=(F_C, G_F))

DC_MAX = 0.99


def uniaxial_strength(damage: float, surface) -> float:
    """σ_u(D): root of σ/√3 = (1 − D) F_f(σ) √F_c(σ) (compression positive, Pa; the initial
    cap's F_c, :mod:`.cap_plasticity`)."""
    from scipy.optimize import brentq

    def g(sig):
        return sig / math.sqrt(3.0) - (1.0 - damage) * float(surface.shear_limit(sig))

    hi = 1.0
    while g(hi) < 0.0:
        hi *= 2.0
    return brentq(g, 0.0, hi, xtol=1e-6)


def softening_strain(f_c: float, G_F: float, band: float, surface,
                     ratio: float = 100.0) -> float:
    """ε_fc = (G_fc/ℓ_c) / ∫_0^{D_c,max} σ_u(D) dD with G_fc = ratio G_F."""
    del f_c  # σ_u(0) = f_c through the surface's fit
    d = np.linspace(0.0, DC_MAX, 199)
    sig = np.array([uniaxial_strength(x, surface) for x in d])
    return ratio * G_F / band / float(np.trapezoid(sig, d))


@njit(inline="always", cache=True)
def ductile_damage(epsp, eps_fc):
    return min(DC_MAX, epsp / eps_fc)
