r"""CSCM's rate effects (Murray, FHWA-HRT-05-062, 2007, chapter 2 "Rate effects"): a
viscoplastic (Duvaut-Lions) update of the stress, an opt-in effect (LS-DYNA's default is
IRATE = 0; the source does not say whether it ran with it).

Each step the trial stress :math:`\sigma^T` (the step's elastic increment added to the
viscoplastic stress of the step's start) and the inviscid stress :math:`\sigma^P` (the
rate-independent model of the same strain history: cap return, compressive and tensile damage)
are blended,

.. math::
    \sigma^{vp} = (1-\gamma)\,\sigma^T + \gamma\,\sigma^P,\qquad
    \gamma = \frac{\Delta t/\eta}{1 + \Delta t/\eta},\qquad
    \eta_t = \frac{\eta_{0t}}{\dot\varepsilon^{\,n_t}},\quad
    \eta_c = \frac{\eta_{0c}}{\dot\varepsilon^{\,n_c}},\quad \eta_s = \mathrm{SRATE}\,\eta_t,

interpolated by the stress state as CSCM does, linearly in the ratio
:math:`r = J_1'/(\sqrt3\sqrt{J_2})` of the trial (:math:`J_1' = -I_1`, compression positive):
:math:`r = -1` uniaxial tension, 0 pure shear, 1 uniaxial compression,

.. math::
    \eta = \eta_s + r(\eta_c - \eta_s)\ (r \ge 0),\qquad
    \eta = \eta_s - r(\eta_t - \eta_s)\ (r < 0),

with r clipped to [-1, 1] (decision [D]; beyond, e.g. near the hydrostatic axis, the
uniaxial values). The overstress :math:`\sigma^{vp} - \sigma^P` is limited in norm
(:math:`\|\cdot\|` Frobenius, the uniaxial stress difference in a uniaxial state) by OVERT in
tension and shear and by OVERC in compression (interpolated like η). At a steady uniaxial rate
the overstress settles at :math:`E\dot\varepsilon\eta` (1D Duvaut-Lions), hence the manual's
dynamic increase factors

.. math::
    \mathrm{DIF} = 1 + \frac{\min(E\,\eta_0\,\dot\varepsilon^{1-n},\ \mathrm{OVER})}{f'},

f' = f_t (tension) or f_c (compression). The fracture energy grows with the rate as REPOW
sets, :math:`G_F^{dyn} = G_F\,\mathrm{DIF}_t^{\mathrm{REPOW}}`: the overstress, carried to
full softening (below), already dissipates the factor DIF_t, so the softening strain of
:mod:`.damage` scales by :math:`\mathrm{DIF}_t^{\mathrm{REPOW}-1}` (1 for CSCM's default
REPOW = 1; the damage never decreases when the rate drops).

Strain rate [D]: :math:`\dot\varepsilon = \max(\dot\varepsilon_1, -\dot\varepsilon_3)`, the
largest principal strain-rate magnitude (the axial rate of a uniaxial test). Cracked material,
decision [D]: CSCM applies its damage d to the viscoplastic stress,
:math:`(1-d)\sigma^{vp}`, so a failed point carries no overstress. Here the Rankine damage
acts on the inviscid stress, and the overstress is limited to
:math:`(1 - w)\min(\mathrm{OVER}, E\dot\varepsilon\eta)`, with
:math:`w = (\kappa - \mathrm{DIF}_t\varepsilon_0)/(\varepsilon_f - \mathrm{DIF}_t\varepsilon_0)`
clipped to [0, 1] (:func:`softening_left`): the share of the strength lost on the softening
branch past the dynamic strength, CSCM's d; without it an open crack would stay loaded by
:math:`E\dot\varepsilon\eta`.

Default fits (Murray's, :func:`rate_constants`), with f'_c in MPa, η_0 in s^(1-n) (η in s at
strain rates in 1/s) and OVERT/OVERC in MPa; SRATE = REPOW = 1:

.. math::
    \eta_{0t} = 8.0614774\times10^{-13} f_c'^2 - 9.77736719\times10^{-10} f_c'
    + 5.0752351\times10^{-5},\quad n_t = 0.48,\\
    \eta_{0c} = 1.2772337\times10^{-11} f_c'^2 - 1.0613722\times10^{-7} f_c'
    + 3.203497\times10^{-4},\quad n_c = 0.78,\\
    \mathrm{OVERT} = \mathrm{OVERC} = 1.309663\times10^{-2} f_c'^2 - 0.3927659 f_c' + 21.45.

At f'_c = 43.1 MPa: η_0t = 5.0711e-5 s^0.52, η_0c = 3.1580e-4 s^0.22, OVERT = OVERC =
28.85 MPa. The fits depend on f'_c only; the aggregate size (8 mm here) enters CSCM's fracture
energies, not its rate effects. With E = 29.72 GPa, f_t = 3.22 MPa, f_c = 43.1 MPa the
manual's factors are DIF_t = 1.47 / 2.55 / 6.14 and DIF_c = 1.22 / 1.36 / 1.60 at
1 / 10 / 100 1/s; OVERT caps DIF_t above about 290 1/s, OVERC caps DIF_c above about
165 1/s.

Sources. The manual's chapter 2 ("Plastic update") defines the trial elastic stress and the
inviscid stress (its return to the yield surface); its chapter 3 gives the default parameters
for unconfined strengths of about 20-58 MPa. The units of the fits and of the factor (E, f' and
OVER in MPa, ε̇ in 1/s) are those of the public re-implementation ``MatCSCM.py`` (repository
yurynovozhilov/MAT_CSCM_CONCRETE_NOVOZHILOV, class ``StrainRate``), which agrees with every
number above (read in psi, OVERT's fit would give 5.1e5).

Three dimensions, decision [D]. The factors are the steady overstress of a 1D element (spring
E, slider f', dashpot η), which the blend reaches exactly; a material point in uniaxial tension
follows DIF_t. In unconfined compression the inviscid return flows at constant volume, so the
steady overstress η C:ε̇^p is 2G ε̇ η axially and G ε̇ η of lateral tension, which the inviscid
stress balances by a lateral compression that raises its pressure-dependent strength: the point
exceeds DIF_c. The manual's algorithm and fits are kept rather than forcing the 1D factor. The
manual's σ^P is the return of σ^T itself; here [D] it is the rate-independent history, which
keeps the damage and hardening of the inviscid model (without damage both peak alike).
"""

import math

from numba import njit

from craquelure.impact.effects import F_C, F_T
from craquelure.impact.effects.damage import principal
from craquelure.registry import Effect

EFFECT = Effect("impact", "rate_effects", "RATE_EFFECTS", "CSCM's viscoplastic (Duvaut-Lions) "
                "rate effects (opt-in; needs cap_plasticity and damage)",
                params=(F_C, F_T))

# the rate constants in the kernels' parameter vector, in this order (keep together)
RATE_PARAMS = ("eta0_t", "n_t", "eta0_c", "n_c", "overt", "overc", "srate", "repow")


def rate_constants(f_c: float) -> dict[str, float]:
    """Murray's default fits at f'_c = ``f_c`` [Pa] (f'_c in MPa in the polynomials); SI out,
    η_0 in s^(1-n)."""
    f = f_c / 1e6
    over = (1.309663e-2 * f * f - 0.3927659 * f + 21.45) * 1e6
    return {"eta0_t": 8.0614774e-13 * f * f - 9.77736719e-10 * f + 5.0752351e-5, "n_t": 0.48,
            "eta0_c": 1.2772337e-11 * f * f - 1.0613722e-7 * f + 3.203497e-4, "n_c": 0.78,
            "overt": over, "overc": over, "srate": 1.0, "repow": 1.0}


@njit(inline="always", cache=True)
def strain_rate(d):
    """max(D_1, -D_3) of d = (xx, yy, xy, zz, xz, yz): the largest principal rate magnitude."""
    dxx, dyy, dxy, dzz, dxz, dyz = d
    if dxz == 0.0 and dyz == 0.0:
        c = 0.5 * (dxx + dyy)
        rad = math.sqrt(0.25 * (dxx - dyy) ** 2 + dxy * dxy)
        return max(max(c + rad, dzz), -min(c - rad, dzz))
    lam = principal(d)[0]
    return max(lam.max(), -lam.min())


@njit(inline="always", cache=True)
def increase_factor(rate, young, eta0, n, over, strength):
    """The manual's dynamic increase factor 1 + min(E η_0 rate^(1-n), OVER)/f' (1 at rate 0)."""
    if rate <= 0.0:
        return 1.0
    return 1.0 + min(young * eta0 * rate ** (1.0 - n), over) / strength


@njit(inline="always", cache=True)
def softening_left(kappa, eps_0, eps_f, dif_t):
    """1 - w, w = (κ - DIF_t ε_0)/(ε_f - DIF_t ε_0) in [0, 1]: the share of the overstress left
    on the softening branch past the dynamic strength (CSCM's 1 - d)."""
    start = dif_t * eps_0
    return 1.0 - min(1.0, max(0.0, (kappa - start) / max(eps_f - start, 1e-300)))


@njit(inline="always", cache=True)
def viscoplastic(trial, inviscid, rate, dt, eta0_t, n_t, eta0_c, n_c, overt, overc, srate,
                 young, intact):
    """σ^vp = (1 - γ) σ^T + γ σ^P with the overstress limit, all (xx, yy, xy, zz, xz, yz)."""
    sxx, syy, sxy, szz, sxz, syz = trial
    i1 = sxx + syy + szz
    m = i1 / 3.0
    j2 = (0.5 * ((sxx - m) ** 2 + (syy - m) ** 2 + (szz - m) ** 2)
          + sxy * sxy + sxz * sxz + syz * syz)
    r = 0.0
    if j2 > 0.0:
        r = min(1.0, max(-1.0, -i1 / math.sqrt(3.0 * j2)))
    elif i1 != 0.0:
        r = -1.0 if i1 > 0.0 else 1.0
    keep = 1.0  # 1 - γ; η infinite at rate 0: no relaxation within the step
    over = overt + max(r, 0.0) * (overc - overt)
    if rate > 0.0:
        eta_t = eta0_t / rate ** n_t
        eta_s = srate * eta_t
        if r >= 0.0:
            eta = eta_s + r * (eta0_c / rate ** n_c - eta_s)
        else:
            eta = eta_s - r * (eta_t - eta_s)
        keep = eta / (eta + dt)
        over = min(over, young * rate * eta)
    over *= intact
    qxx, qyy, qxy = trial[0] - inviscid[0], trial[1] - inviscid[1], trial[2] - inviscid[2]
    qzz, qxz, qyz = trial[3] - inviscid[3], trial[4] - inviscid[4], trial[5] - inviscid[5]
    norm = keep * math.sqrt(qxx * qxx + qyy * qyy + qzz * qzz
                            + 2.0 * (qxy * qxy + qxz * qxz + qyz * qyz))
    if norm > over:
        keep *= over / norm
    return (inviscid[0] + keep * qxx, inviscid[1] + keep * qyy, inviscid[2] + keep * qxy,
            inviscid[3] + keep * qzz, inviscid[4] + keep * qxz, inviscid[5] + keep * qyz)
