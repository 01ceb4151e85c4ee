r"""Strain-rate enhancement of strength in CSCM's form (impact spec section 2 item 5; Murray,
FHWA-HRT-05-062, 2007): an opt-in effect, off in the source-faithful scenes (LS-DYNA's
default IRATE = 0, and the source does not mention rate effects).

CSCM's viscoplastic overstress (Duvaut-Lions) with fluidity :math:`\eta = \eta_0/\dot\varepsilon^n`
gives, at a steady strain rate, a strength raised by the overstress :math:`E\dot\varepsilon\eta`,
capped by OVERT/OVERC; the dynamic increase factors are

.. math::
    \mathrm{DIF}_t = 1 + \frac{\min(E\,\eta_{0t}\,\dot\varepsilon_t^{1-n_t},\ \mathrm{OVERT})}{f_t},
    \qquad
    \mathrm{DIF}_c = 1 + \frac{\min(E\,\eta_{0c}\,\dot\varepsilon_c^{1-n_c},\ \mathrm{OVERC})}{f_c},

with :math:`\dot\varepsilon_t = \langle D_1\rangle_+` (largest principal strain rate) and
:math:`\dot\varepsilon_c = \langle -D_3\rangle_+` (most compressive). Murray's fits at
f'_c = 43.1 MPa (:func:`rate_constants`): η_0t = 5.07e-5 s^(1-n), n_t = 0.48, η_0c = 3.16e-4,
n_c = 0.78, OVERT = OVERC = 28.85 MPa: DIF_t = 1.47 / 2.55 / 6.14 at 1 / 10 / 100 1/s,
DIF_c = 1.22 / 1.36 / 1.60.

Units of the fits [not verified against the manual's text]: OVERT/OVERC's
polynomial only makes sense with f'_c in MPa (28.85 MPa; in psi it would give 5.1e5). The η_0
polynomials read differently: with f'_c in MPa their quadratic and linear terms are 0.003 % and
2 % of the constant (η_0t) and 0.01 % and 1.4 % (η_0c), implausible for fitted terms; with f'_c
in psi (6251 psi) the three terms are of one size, which suggests the fits were made in psi
(η_0t = 7.61e-5, η_0c = 1.57e-4 s^(1-n) instead of 5.07e-5 and 3.16e-4; one public
implementation, MatCSCM.py of yurynovozhilov/MAT_CSCM_CONCRETE_NOVOZHILOV, computes f'_c in psi
beside these fits but evaluates them in MPa). This module keeps MPa; the effect is opt-in and
off in every judged scene.

Applied as rate-dependent strengths, the steady-state limit of the overstress (without its
relaxation time). Compression: the shear surface of :mod:`.cap_plasticity` is enlarged
homothetically in the meridian plane, :math:`\sqrt{J_2} \le \mathrm{DIF}_c\,\Re\,F_f(I_1'/
\mathrm{DIF}_c)`, which puts the uniaxial strength at DIF_c f_c exactly. (Blending the trial and
the inviscid return as CSCM's Duvaut-Lions update does was tried: with the pressure-dependent
meridian and a return at fixed pressure the overstress raises the pressure and with it the
strength, and the uniaxial increase came out 1.93 at 1 1/s instead of 1.22.) Tension: the driver
of :mod:`.damage` becomes
:math:`\langle\tilde\sigma_1\rangle_+/(E\,\mathrm{DIF}_t)`, so the tensile strength and the
softening strains scale by DIF_t (G_F by DIF_t²; CSCM's REPOW = 1 scales it by DIF_t). The history
variable κ keeps the damage irreversible when the rate drops.
"""

import math

from numba import njit

from craquelure.impact.effects import F_C, F_T
from craquelure.impact.effects.damage import principal
from craquelure.registry import Effect

EFFECT = Effect("impact", "rate_effects", "RATE_EFFECTS", "CSCM-form dynamic increase of "
                "tensile and compressive strength (opt-in; needs cap_plasticity and damage)",
                params=(F_C, F_T))


def rate_constants(f_c: float) -> dict[str, float]:
    """Murray (2007) fits at f'_c = ``f_c`` [Pa] (f'_c in MPa in the polynomials); SI out."""
    f = f_c / 1e6
    over = (1.309663e-2 * f * f - 0.3927659 * f + 21.45) * 1e6
    return {"eta0_t": 8.0614774e-13 * f * f - 9.77736719e-10 * f + 5.0752351e-5, "n_t": 0.48,
            "eta0_c": 1.2772337e-11 * f * f - 1.0613722e-7 * f + 3.203497e-4, "n_c": 0.78,
            "overt": over, "overc": over}


@njit(inline="always", cache=True)
def increase_factor(rate, young, eta0, n, over, strength):
    """1 + min(E eta0 rate^(1-n), over)/strength; 1 at rate <= 0."""
    if rate <= 0.0:
        return 1.0
    return 1.0 + min(young * eta0 * rate ** (1.0 - n), over) / strength


@njit(inline="always", cache=True)
def principal_rates(d):
    """(largest, smallest) principal strain rate of d = (xx, yy, xy, zz, xz, yz)."""
    dxx, dyy, dxy, dzz, dxz, dyz = d
    if dxz == 0.0 and dyz == 0.0:
        c = 0.5 * (dxx + dyy)
        rad = math.sqrt(0.25 * (dxx - dyy) ** 2 + dxy * dxy)
        return max(c + rad, dzz), min(c - rad, dzz)
    lam = principal(d)[0]
    return lam.max(), lam.min()
