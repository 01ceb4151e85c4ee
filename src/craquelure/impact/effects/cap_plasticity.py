r"""CSCM-like shear surface with a curved compression meridian, Lode-angle dependence and
CSCM's compaction cap, coupled to the shear surface as CSCM couples them (impact spec section 2
item 5; CSCM = LS-DYNA MAT_159 / MAT_CSCM_CONCRETE, Murray, *Users Manual for LS-DYNA Concrete
Material Model 159*, FHWA-HRT-05-062, 2007, chapter 2 "Theoretical manual" and the default
parameters of its chapter on fits; evaluated in FHWA-HRT-05-063, 2007). Replaces the straight
Drucker-Prager cone of :mod:`.plasticity` (the two conflict).

Pressure-type invariant, compression positive (CSCM's sign convention): :math:`I_1' =
-\mathrm{tr}\tilde\sigma`. Shear failure surface on the compression meridian (TXC) in units of
:math:`\sqrt{J_2}`:

.. math::
    F_f(I_1') = \alpha - \lambda e^{-\beta I_1'} + \theta I_1' .

CSCM's yield function couples it with the cap multiplicatively,

.. math::
    f = J_2 - \Re^2 F_f^2 F_c, \qquad
    F_c = 1 - \frac{[I_1' - L(\kappa)]\,\bigl(|I_1' - L(\kappa)| + I_1' - L(\kappa)\bigr)}
                   {2\,[X(\kappa) - L(\kappa)]^2},

so :math:`F_c = 1` for :math:`I_1' \le L` and :math:`F_c = 1 - ((I_1' - L)/(X - L))^2` on the
elliptical cap between L and X; :math:`L(\kappa) = \max(\kappa, \kappa_0)` and
:math:`X(\kappa) = L(\kappa) + R\,F_f(L(\kappa))`. The cap's initial position is its intercept
:math:`X_0` on the I1 axis: the hardening law is written in :math:`X - X_0`,

.. math::
    \varepsilon_v^p = W\bigl(1 - e^{-D_1 (X - X_0) - D_2 (X - X_0)^2}\bigr),

and :math:`\kappa_0` (where cap and shear surface meet before hardening) follows from
:math:`X_0 = \kappa_0 + R\,F_f(\kappa_0)`; as the cap hardens, L solves
:math:`L + R F_f(L) = X` (monotone: :math:`1 + R F_f' > 0`). The fit is LS-DYNA's input ``X0``
of the cap card (as the public keyword generator MatCSCM.py of
yurynovozhilov/MAT_CSCM_CONCRETE_NOVOZHILOV writes it), not κ0 (which would put X0 at 330.6 MPa).

Lode-angle dependence (Willam-Warnke ellipse, in the role of CSCM's Rubin factor):
:math:`\Re = 1` on TXC, :math:`\Re = e` on the extension meridian (TXE: uniaxial tension,
equibiaxial compression), :math:`\cos 3\psi = \tfrac{3\sqrt3}{2} J_3/J_2^{3/2}` (:math:`\psi = 0`
on TXE) and

.. math::
    \Re = \frac{2(1-e^2)\cos\psi + (2e-1)\sqrt{4(1-e^2)\cos^2\psi + 5e^2 - 4e}}
               {4(1-e^2)\cos^2\psi + (2e-1)^2}.

Return (per step): left of L (:math:`I_1' \le L`) the deviator returns radially at fixed
:math:`I_1'` and Lode angle, :math:`s \leftarrow r s`, :math:`r = \phi\,\Re F_f/\sqrt{J_2}`, zero
dilatancy as in :mod:`.plasticity`. On the cap (:math:`I_1' > L`, outside) the stress returns to
the closest point of the coupled surface in the elastic metric :math:`(\Delta I_1')^2/(9K) +
(\Delta\sqrt{J_2})^2/G` (where associated flow is the closest-point projection) over
:math:`I_1' \in [L, \min(I_1'^{tr}, X)]` (the return compacts, never dilates), the pressure drop
being the compaction :math:`\Delta\varepsilon_v^p = (I_1'^{tr} - I_1')/(3K)` and the cap hardened
by it within the same step (implicit, :func:`_compaction`); on the hydrostatic axis this is the
cap's hardening law exactly. :math:`\Delta\bar\varepsilon_p = (1-r)\sqrt{J_2^{tr}}/(\sqrt3 G)`;
:math:`\phi = 1 - D_c` carries the compressive damage (:mod:`.compressive_damage`). Plastic work
density: :math:`r(1-r)J_2^{tr}/G + p\,\Delta\varepsilon_v^p` (:math:`p = I_1'/3`). As with the
cone, the return acts only for :math:`I_1' > 0`: tension is the Rankine damage model's domain.

Differences from CSCM [D]: the return is not CSCM's associated return with subincrementation:
left of the cap's top the closest point never lies below the trial's I1' (no plastic dilatancy;
CSCM's associated flow dilates there), and the Lode factor is held at the trial's; no pre-peak
hardening (CSCM's N_H, C_H); Willam-Warnke with a constant ratio e instead of Rubin's
pressure-dependent Q_1, Q_2. Consequence measured at a material point
(tests/impact/effects/test_cap_plasticity.py): in triaxial compression the stress
settles on the coupled surface with F_c < 1 (at 25 MPa confinement q = 112.6 MPa against the
uncoupled meridian's √3 F_f = 137.4 MPa, −18 %), not on the meridian.

Constants for :math:`f'_c` = 43.1 MPa, every one from Murray (2007)'s default-parameter fits
("revision 1" polynomials in :math:`f'_c` [MPa], written out in :func:`murray_fits`; the same
as the REV_1 branch of the public MatCSCM.py above): :math:`\alpha` = 15.79 MPa,
:math:`\lambda` = 10.5 MPa, :math:`\beta` = 0.01929 1/MPa, :math:`\theta` = 0.3401,
:math:`X_0` = 97.98 MPa, R = 5, W = 0.05, D_1 = 2.5e-4 1/MPa, D_2 = 3.49e-7 1/MPa². Derived:
κ0 = 20.21 MPa (F_f(κ0) = 15.55 MPa).
With the coupling, Murray's α gives the unconfined strength 42.53 MPa (1.3 % below f_c; the
uncoupled meridian alone would give 49.5 MPa). One constant is this project's [D]
(:func:`surface_constants`): e = 0.596 puts the equibiaxial point (f_bc/√3 at I1' = 2 f_bc,
f_bc = 1.16 f_c, Kupfer) on the uncoupled shear surface, where CSCM uses its own Rubin fits;
that point lies at I1' = 100 MPa, beyond X0, so the equibiaxial strength is reached only as the
cap hardens (tests/impact/effects/test_cap_plasticity.py measures it).
"""

import math
from dataclasses import dataclass

import numpy as np
from numba import njit

from craquelure.errors import SceneError
from craquelure.impact.effects import F_C
from craquelure.registry import Effect, Param

EFFECT = Effect("impact", "cap_plasticity", "CAP_PLASTICITY", "CSCM-like curved compression "
                "meridian (Murray 2007 fits), Willam-Warnke Lode dependence, CSCM's elliptical "
                "compaction cap from X0", conflicts=("plasticity",),
                # Concrete.cap_vector(): the surface, cap and rate constants
                params=(F_C, Param("cap", None, size=22)))

MPA = 1e6
R_CAP = 5.0  # CSCM's cap ellipticity R (revision 1 default, Murray 2007)


def murray_fits(f_c: float) -> dict[str, float]:
    """Murray (2007) default-parameter fits (revision 1) at f'_c = ``f_c`` [Pa]; SI units out.
    ``X0`` is the cap's initial I1 intercept (MAT_CSCM's input X0)."""
    f = f_c / MPA
    return {
        "alpha": (-0.003 * f * f + 0.3169747 * f + 7.7047) * MPA,
        "lambda": 10.5 * MPA,
        "beta": 0.01929 / MPA,
        "theta": 1.3216e-5 * f * f + 2.3548e-3 * f + 0.2140058,
        "X0": (8.769178e-3 * f * f - 0.073302306 * f + 84.85) * MPA,
        "R": R_CAP,
        "W": 0.05,
        "D1": 2.5e-4 / MPA,
        "D2": 3.49e-7 / MPA**2,
    }


def meridian(i1, alpha, lam, beta, theta):
    """F_f(I1') (compression positive), works on floats and arrays."""
    return alpha - lam * np.exp(-beta * i1) + theta * i1


@dataclass(frozen=True)
class CapSurface:
    """Constants of the surface (SI): Murray's fits, e fitted, κ0 derived from X0."""

    alpha: float
    lam: float
    beta: float
    theta: float
    e: float
    X0: float
    R: float
    W: float
    D1: float
    D2: float

    def F_f(self, i1):
        return meridian(i1, self.alpha, self.lam, self.beta, self.theta)

    @property
    def kappa0(self) -> float:
        """κ0 from X0 = κ0 + R F_f(κ0)."""
        return cap_left(self.X0, self.R, self.alpha, self.lam, self.beta, self.theta)

    def F_c(self, i1, x=None):
        """CSCM's cap function at I1' for the cap at X (default: the initial cap X0)."""
        x = self.X0 if x is None else x
        left = cap_left(x, self.R, self.alpha, self.lam, self.beta, self.theta)
        d = np.maximum(np.asarray(i1, float) - left, 0.0)
        return np.clip(1.0 - (d / (x - left)) ** 2, 0.0, 1.0)

    def shear_limit(self, i1, x=None):
        """√J2 limit on TXC with the cap: F_f √F_c (compression positive, Pa)."""
        return self.F_f(i1) * np.sqrt(self.F_c(i1, x))


def surface_constants(f_c: float, f_bc_ratio: float = 1.16) -> CapSurface:
    """Murray's fits at f_c, X0 as fitted, and the Willam-Warnke ratio e through the
    equibiaxial point (f_bc/sqrt3 at I1' = 2 f_bc) on the uncoupled shear surface."""
    m = murray_fits(f_c)
    f_bc = f_bc_ratio * f_c
    e = (f_bc / math.sqrt(3.0)) / float(meridian(2 * f_bc, m["alpha"], m["lambda"], m["beta"],
                                                 m["theta"]))
    if not 0.5 <= e <= 1.0:
        raise SceneError(f"material.f_bc_ratio: {f_bc_ratio:g} gives a Willam-Warnke ratio "
                         f"e = {e:.3g} outside [0.5, 1]; allowed f_bc_ratio values give 0.5 <= e "
                         f"<= 1 (1.16 gives 0.60)")
    return CapSurface(alpha=m["alpha"], lam=m["lambda"], beta=m["beta"], theta=m["theta"], e=e,
                      X0=m["X0"], R=m["R"], W=m["W"], D1=m["D1"], D2=m["D2"])


@njit(cache=True)
def cap_left(x, r, alpha, lam, beta, theta):
    """L with L + R F_f(L) = X (Newton: the left side is concave and increasing, so after the
    first step the iterates stay below the root and increase to it)."""
    k = x / (1.0 + r * theta)
    for _ in range(100):
        ex = math.exp(-beta * k)
        g = k + r * (alpha - lam * ex + theta * k) - x
        dg = 1.0 + r * (lam * beta * ex + theta)
        step = g / dg
        k -= step
        if abs(step) <= 1e-13 * (abs(x) + 1.0):
            break
    return k


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
def _limit(y, left, x, alpha, lam, beta, theta, scale):
    """√J2 limit at I1' = y: scale F_f(y) √F_c (scale = (1 - D_c) ℜ), cap from L = ``left``
    to X = ``x``."""
    cap = 1.0
    if y > left:
        ratio = (y - left) / (x - left)
        cap = max(1.0 - ratio * ratio, 0.0)
    return scale * (alpha - lam * math.exp(-beta * y) + theta * y) * math.sqrt(cap)


@njit(inline="always", cache=True)
def _distance_slope(y, i1, sq, left, x, alpha, lam, beta, theta, scale, bulk, shear):
    """d/dy of (y - I1')²/(9K) + (g(y) - √J2)²/G, g the coupled limit of :func:`_limit`."""
    ff = alpha - lam * math.exp(-beta * y) + theta * y
    dff = lam * beta * math.exp(-beta * y) + theta  # d F_f / d y
    cap, dcap = 1.0, 0.0
    if y > left:
        span = x - left
        ratio = (y - left) / span
        cap = max(1.0 - ratio * ratio, 1e-300)
        dcap = -2.0 * ratio / span
    root = math.sqrt(cap)
    g = scale * ff * root
    dg = scale * (dff * root + ff * dcap / (2.0 * root))
    return 2.0 * (y - i1) / (9.0 * bulk) + 2.0 * (g - sq) * dg / shear


@njit(cache=True)
def _closest(i1, sq, left, x, alpha, lam, beta, theta, scale, bulk, shear):
    """I1' of the closest point of the coupled surface (cap at X, left end L) to the trial (I1',
    √J2) in the elastic metric over [L, min(I1'_trial, X)]: the zero of the distance's slope by
    bisection (exact to round-off, unlike minimising the distance)."""
    hi = min(i1, x)
    if hi <= left or sq == 0.0:
        return hi
    lo = left
    if _distance_slope(lo, i1, sq, left, x, alpha, lam, beta, theta, scale, bulk,
                       shear) >= 0.0:
        return lo
    if _distance_slope(hi, i1, sq, left, x, alpha, lam, beta, theta, scale, bulk,
                       shear) <= 0.0:
        return hi
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if mid <= lo or mid >= hi:
            break
        if _distance_slope(mid, i1, sq, left, x, alpha, lam, beta, theta, scale, bulk,
                           shear) > 0.0:
            hi = mid
        else:
            lo = mid
    return 0.5 * (lo + hi)


@njit(cache=True)
def _compaction(i1, sq, epsv, alpha, lam, beta, theta, x0, w, d1, d2, kappa0, r_cap,
                scale, bulk, shear):
    """(Δε_v^p, I1', X, L) of the cap return with implicit hardening: the root of
    h(Δ) = Δ − (I1'_trial − y(X(ε_v^p + Δ)))/(3K), y the closest point with the cap hardened by
    Δ (h increases; Illinois regula falsi on [0, (I1'_trial − κ0)/(3K)])."""
    def position(dv):
        x = cap_position(epsv + dv, x0, w, d1, d2) if epsv + dv > 0.0 else x0
        left = kappa0 if x <= x0 else cap_left(x, r_cap, alpha, lam, beta, theta)
        return x, left

    x, left = position(0.0)
    y = _closest(i1, sq, left, x, alpha, lam, beta, theta, scale, bulk, shear)
    h_lo = -(i1 - y) / (3.0 * bulk)
    if h_lo >= 0.0:
        return 0.0, y, x, left
    a, fa = 0.0, h_lo
    b = (i1 - kappa0) / (3.0 * bulk)
    x, left = position(b)
    y = _closest(i1, sq, left, x, alpha, lam, beta, theta, scale, bulk, shear)
    fb = b - (i1 - y) / (3.0 * bulk)
    side = 0
    c = b
    for _ in range(80):
        c = (a * fb - b * fa) / (fb - fa) if fb != fa else 0.5 * (a + b)
        x, left = position(c)
        y = _closest(i1, sq, left, x, alpha, lam, beta, theta, scale, bulk, shear)
        fc = c - (i1 - y) / (3.0 * bulk)
        if abs(fc) <= 1e-13 * (b + 1e-30) or abs(b - a) <= 1e-14:
            break
        if fc * fb > 0.0:
            b, fb = c, fc
            if side == -1:
                fa *= 0.5
            side = -1
        else:
            a, fa = c, fc
            if side == 1:
                fb *= 0.5
            side = 1
    return c, y, x, left


@njit(inline="always", cache=True)
def cap_return(s, epsv, alpha, lam, beta, theta, e, x0, w, d1, d2, kappa0, r_cap, bulk,
               shear, strength):
    """Returns (stress, d_eps_v^p, d_eps_p, plastic work density) for the trial stress ``s``,
    both (xx, yy, xy, zz, xz, yz) (xz = yz = 0 in 2D). ``x0``: the cap's initial I1 intercept
    X0, ``kappa0`` its κ0 (X0 = κ0 + R F_f(κ0)), ``r_cap`` R. ``strength`` = 1 - D_c scales
    the shear surface. The return of the module docstring."""
    sxx, syy, sxy, szz, sxz, syz = s
    i1 = -(sxx + syy + szz)
    if i1 <= 0.0:
        return (sxx, syy, sxy, szz, sxz, syz), 0.0, 0.0, 0.0
    x = cap_position(epsv, x0, w, d1, d2) if epsv > 0.0 else x0
    left = kappa0 if x <= x0 else cap_left(x, r_cap, alpha, lam, beta, theta)
    m = -i1 / 3.0
    dxx, dyy, dzz = sxx - m, syy - m, szz - m
    j2 = 0.5 * (dxx * dxx + dyy * dyy + dzz * dzz) + sxy * sxy + sxz * sxz + syz * syz
    sq = math.sqrt(max(j2, 0.0))
    scale = strength
    if sq > 0.0:
        # J3 = det(s); the xz, yz terms vanish in 2D
        j3 = (dzz * (dxx * dyy - sxy * sxy) - dxx * syz * syz - dyy * sxz * sxz
              + 2.0 * sxy * sxz * syz)
        c3 = 1.5 * math.sqrt(3.0) * j3 / (j2 * sq)
        c3 = min(1.0, max(-1.0, c3))
        scale = strength * willam_warnke(math.cos(math.acos(c3) / 3.0), e)
    if i1 < x and sq <= _limit(i1, left, x, alpha, lam, beta, theta, scale):
        return (sxx, syy, sxy, szz, sxz, syz), 0.0, 0.0, 0.0
    dv, y = 0.0, i1
    if i1 > left:
        dv, y, x, left = _compaction(i1, sq, epsv, alpha, lam, beta, theta, x0, w, d1, d2,
                                     kappa0, r_cap, scale, bulk, shear)
    limit = _limit(y, left, x, alpha, lam, beta, theta, scale)
    r = min(max(limit, 0.0) / sq, 1.0) if sq > 0.0 else 1.0
    mn = -y / 3.0
    work = y / 3.0 * dv
    deps = (1.0 - r) * sq / (math.sqrt(3.0) * shear)
    work += r * (1.0 - r) * j2 / shear if r > 0.0 else j2 / shear
    return ((mn + r * dxx, mn + r * dyy, r * sxy, mn + r * dzz, r * sxz, r * syz), dv, deps,
            work)
