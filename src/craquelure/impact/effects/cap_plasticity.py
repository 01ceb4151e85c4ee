r"""CSCM-like shear surface with a curved compression meridian, Lode-angle dependence and a
compaction cap (impact spec section 2 item 5; CSCM = LS-DYNA MAT_159, Murray, FHWA-HRT-05-062,
2007). Replaces the straight Drucker-Prager cone of :mod:`.plasticity` (the two conflict).

Pressure-type invariant, compression positive: :math:`I_1' = -\mathrm{tr}\tilde\sigma`.
Compression meridian (triaxial compression, TXC) in units of :math:`\sqrt{J_2}`:

.. math::
    F_f(I_1') = \alpha - \lambda e^{-\beta I_1'} + \theta I_1' .

Lode-angle dependence (Willam-Warnke ellipse, in the role of CSCM's Rubin factor):
:math:`\sqrt{J_2} \le \Re(\psi)\,F_f(I_1')`, :math:`\Re = 1` on TXC, :math:`\Re = e` on the
extension meridian (TXE: uniaxial tension, equibiaxial compression), with
:math:`\cos 3\psi = \tfrac{3\sqrt3}{2} J_3/J_2^{3/2}` (:math:`\psi = 0` on TXE) and

.. math::
    \Re = \frac{2(1-e^2)\cos\psi + (2e-1)\sqrt{4(1-e^2)\cos^2\psi + 5e^2 - 4e}}
               {4(1-e^2)\cos^2\psi + (2e-1)^2}.

Cap (compaction, CSCM's hardening law): the hydrostatic limit :math:`I_1' \le X`, with

.. math::
    \varepsilon_v^p = W\bigl(1 - e^{-D_1 (X - X_0) - D_2 (X - X_0)^2}\bigr), \quad
    X_0 = \kappa_0 + R\,F_f(\kappa_0),

so :math:`X(\varepsilon_v^p) = X_0 + \Delta`, :math:`D_1\Delta + D_2\Delta^2 = -\ln(1 -
\varepsilon_v^p/W)`. Return (operator split, per step): (1) if :math:`I_1'^{tr} > X`, the
pressure returns to the cap with the compaction :math:`\Delta\varepsilon_v^p = (I_1'^{tr} -
I_1')/(3K)` that makes :math:`I_1' = X(\varepsilon_v^p + \Delta\varepsilon_v^p)` (Newton on a
monotone scalar equation); (2) radial return of the deviator at fixed :math:`I_1'` and Lode
angle, :math:`s \leftarrow r s`, :math:`r = \phi\,\Re F_f/\sqrt{J_2}` if :math:`r < 1`, zero
dilatancy as in :mod:`.plasticity`, :math:`\Delta\bar\varepsilon_p = (1-r)\sqrt{J_2^{tr}}/(\sqrt3
G)`. :math:`\phi = 1 - D_c` carries the compressive damage (:mod:`.compressive_damage`); with
:mod:`.rate_effects` the surface is enlarged homothetically by DIF_c.
Plastic work density: :math:`r(1-r)J_2^{tr}/G + p\,\Delta\varepsilon_v^p` (:math:`p = I_1'/3`).
As with the cone, the shear return acts only for :math:`I_1' > 0`: tension is the Rankine damage
model's domain (otherwise the extension meridian would cap uniaxial tension at 2.7 MPa < f_t).

Differences from CSCM [D]: CSCM's cap multiplies the shear surface by :math:`\sqrt{F_c}` (an
elliptical cap coupling shear and compaction); here the cap is a plane :math:`I_1' = X` in the
meridian plane (same hydrostatic limit and hardening, no shear-compaction coupling), which keeps
the return to two scalar steps; no pre-peak hardening (CSCM's N_H, C_H); Willam-Warnke with a
constant ratio e instead of Rubin's pressure-dependent Q_1, Q_2.

Constants for :math:`f_c` = 43.1 MPa (MPa, 1/MPa), from the default-parameter fits by strength of
Murray (2007), its "revision 1" polynomials in :math:`f'_c` [MPa]
(:func:`murray_fits`): :math:`\alpha = -0.003 f'^2_c + 0.3169747 f'_c + 7.7047` = 15.79,
:math:`\lambda` = 10.5, :math:`\beta` = 0.01929, :math:`\theta = 1.3216\times10^{-5} f'^2_c +
2.3548\times10^{-3} f'_c + 0.2140058` = 0.3401, :math:`\kappa_0 = 8.769178\times10^{-3} f'^2_c -
0.073302306 f'_c + 84.85` = 97.98, R = 5, W = 0.05, D_1 = 2.5e-4, D_2 = 3.49e-7.
Two fitted to this project's strengths [D] (:func:`surface_constants`): Murray's
:math:`F_f(f_c)` = 25.87 MPa lies 4 % above the uniaxial point :math:`f_c/\sqrt3` = 24.88 MPa
(uniaxial strength 49.5 MPa instead of 43.1), so :math:`\alpha` is shifted by −0.99 MPa to
14.80 MPa, which puts the uniaxial compressive strength at f_c (spec check 6) and keeps
:math:`\lambda, \beta, \theta`; e = 0.611 puts the equibiaxial strength at
:math:`f_{bc}` = 1.16 f_c (Kupfer, as the cone's fit). Then X_0 = 97.98 + 5 F_f(97.98) = 330.6 MPa
(hydrostatic yield at p = 110 MPa).
"""

import math
from dataclasses import dataclass

from numba import njit

from craquelure.registry import Effect

EFFECT = Effect("impact", "cap_plasticity", "CAP_PLASTICITY", "CSCM-like curved compression "
                "meridian (Murray 2007 fits), Willam-Warnke Lode dependence, compaction cap",
                requires=("material.f_c",), conflicts=("plasticity",))

MPA = 1e6


def murray_fits(f_c: float) -> dict[str, float]:
    """Murray (2007) default-parameter fits (revision 1) at f'_c = ``f_c`` [Pa]; SI units out."""
    f = f_c / MPA
    return {
        "alpha": (-0.003 * f * f + 0.3169747 * f + 7.7047) * MPA,
        "lambda": 10.5 * MPA,
        "beta": 0.01929 / MPA,
        "theta": 1.3216e-5 * f * f + 2.3548e-3 * f + 0.2140058,
        "kappa0": (8.769178e-3 * f * f - 0.073302306 * f + 84.85) * MPA,
        "R": 5.0,
        "W": 0.05,
        "D1": 2.5e-4 / MPA,
        "D2": 3.49e-7 / MPA**2,
    }


def meridian(i1, alpha, lam, beta, theta):
    """F_f(I1') (compression positive), works on floats and arrays."""
    import numpy as np

    return alpha - lam * np.exp(-beta * i1) + theta * i1


@dataclass(frozen=True)
class CapSurface:
    """Constants of the surface (SI). ``alpha_murray`` is Murray's fit before the shift."""

    alpha: float
    lam: float
    beta: float
    theta: float
    e: float
    kappa0: float
    R: float
    W: float
    D1: float
    D2: float
    alpha_murray: float

    def F_f(self, i1):
        return meridian(i1, self.alpha, self.lam, self.beta, self.theta)

    @property
    def X0(self) -> float:
        return self.kappa0 + self.R * float(self.F_f(self.kappa0))


def surface_constants(f_c: float, f_bc_ratio: float = 1.16) -> CapSurface:
    """Murray's fits at f_c with alpha shifted through the uniaxial point (f_c/sqrt3 at I1' = f_c)
    and the Willam-Warnke ratio e through the equibiaxial point (f_bc/sqrt3 at I1' = 2 f_bc)."""
    from craquelure.errors import SceneError

    m = murray_fits(f_c)
    alpha = f_c / math.sqrt(3.0) + m["lambda"] * math.exp(-m["beta"] * f_c) - m["theta"] * f_c
    f_bc = f_bc_ratio * f_c
    e = (f_bc / math.sqrt(3.0)) / float(meridian(2 * f_bc, alpha, m["lambda"], m["beta"],
                                                 m["theta"]))
    if not 0.5 <= e <= 1.0:
        raise SceneError(f"material.f_bc_ratio: {f_bc_ratio:g} gives a Willam-Warnke ratio "
                         f"e = {e:.3g} outside [0.5, 1]; allowed f_bc_ratio values give 0.5 <= e "
                         f"<= 1 (1.16 gives 0.61)")
    return CapSurface(alpha=alpha, lam=m["lambda"], beta=m["beta"], theta=m["theta"], e=e,
                      kappa0=m["kappa0"], R=m["R"], W=m["W"], D1=m["D1"], D2=m["D2"],
                      alpha_murray=m["alpha"])


@njit(inline="always", cache=True)
def willam_warnke(cos_psi, e):
    """Ratio of the meridian at Lode angle psi (cos psi in [0.5, 1]) to the TXC meridian."""
    a = 1.0 - e * e
    c2 = cos_psi * cos_psi
    root = math.sqrt(max(4.0 * a * c2 + 5.0 * e * e - 4.0 * e, 0.0))
    return (2.0 * a * cos_psi + (2.0 * e - 1.0) * root) / (4.0 * a * c2 + (2.0 * e - 1.0) ** 2)


@njit(inline="always", cache=True)
def cap_position(epsv, x0, w, d1, d2):
    """X(eps_v^p) = X0 + Delta with D1 Delta + D2 Delta^2 = -ln(1 - eps_v^p / W)."""
    frac = min(epsv / w, 1.0 - 1e-12)
    c = -math.log(1.0 - frac)
    return x0 + 2.0 * c / (d1 + math.sqrt(d1 * d1 + 4.0 * d2 * c))


@njit(inline="always", cache=True)
def cap_return(s, epsv, alpha, lam, beta, theta, e, x0, w, d1, d2, bulk,
               shear, strength, dif):
    """Returns (stress, d_eps_v^p, d_eps_p, plastic work density) for the trial stress ``s``,
    both (xx, yy, xy, zz, xz, yz) (xz = yz = 0 in 2D).
    ``strength`` = 1 - D_c scales the shear surface, ``dif`` = DIF_c enlarges it
    homothetically (:mod:`.rate_effects`)."""
    sxx, syy, sxy, szz, sxz, syz = s
    i1 = -(sxx + syy + szz)
    d_epsv = 0.0
    work = 0.0
    x = cap_position(epsv, x0, w, d1, d2)
    if i1 > x:
        # pressure return: g(dv) = i1 - 3K dv - X(epsv + dv) = 0, g decreasing in dv
        dv = 0.0
        for _ in range(60):
            xn = cap_position(epsv + dv, x0, w, d1, d2)
            g = i1 - 3.0 * bulk * dv - xn
            if abs(g) <= 1e-12 * (abs(i1) + x0):
                break
            # dX/deps_v = W e^{-c} ... / (D1 + 2 D2 Delta) / (W - eps_v)
            delta = xn - x0
            dxde = 1.0 / ((d1 + 2.0 * d2 * delta) * max(w - epsv - dv, 1e-12 * w))
            dv += g / (3.0 * bulk + dxde)
            if dv < 0.0:
                dv = 0.0
        # each normal stress loses K dv of compression
        sxx += bulk * dv
        syy += bulk * dv
        szz += bulk * dv
        i1 = -(sxx + syy + szz)
        d_epsv = dv
        work = i1 / 3.0 * dv
    if i1 <= 0.0:
        return (sxx, syy, sxy, szz, sxz, syz), d_epsv, 0.0, work
    m = -i1 / 3.0
    dxx, dyy, dzz = sxx - m, syy - m, szz - m
    j2 = 0.5 * (dxx * dxx + dyy * dyy + dzz * dzz) + sxy * sxy + sxz * sxz + syz * syz
    if j2 <= 0.0:
        return (sxx, syy, sxy, szz, sxz, syz), d_epsv, 0.0, work
    sq = math.sqrt(j2)
    # J3 = det(s); the xz, yz terms vanish in 2D
    j3 = (dzz * (dxx * dyy - sxy * sxy) - dxx * syz * syz - dyy * sxz * sxz
          + 2.0 * sxy * sxz * syz)
    c3 = 1.5 * math.sqrt(3.0) * j3 / (j2 * sq)
    c3 = min(1.0, max(-1.0, c3))
    cos_psi = math.cos(math.acos(c3) / 3.0)
    i1s = i1 / dif
    limit = strength * dif * willam_warnke(cos_psi, e) * (alpha - lam * math.exp(-beta * i1s)
                                                          + theta * i1s)
    if sq <= limit:
        return (sxx, syy, sxy, szz, sxz, syz), d_epsv, 0.0, work
    r = max(limit, 0.0) / sq
    deps = (1.0 - r) * sq / (math.sqrt(3.0) * shear)
    work += r * (1.0 - r) * j2 / shear if r > 0.0 else j2 / shear
    return ((m + r * dxx, m + r * dyy, r * sxy, m + r * dzz, r * sxz, r * syz), d_epsv, deps,
            work)
