r"""Rankine tensile damage, crack band with linear softening (spec section 2.3).

.. math::
    \varepsilon_{eq} = \langle\tilde\sigma_1\rangle_+/E, \quad
    \varepsilon_{max} = \max_{history}\varepsilon_{eq},
    \quad \varepsilon_0 = f_t/E, \quad \varepsilon_f = \frac{2G_F}{f_t\,\ell_c},

    D_t = \frac{\varepsilon_f(\varepsilon_{max}-\varepsilon_0)}
               {\varepsilon_{max}(\varepsilon_f-\varepsilon_0)}
          \;(\varepsilon_0<\varepsilon_{max}<\varepsilon_f),
    \quad D_t = 1 \;(\varepsilon_{max}\ge\varepsilon_f), \quad
    \sigma_a = \tilde\sigma_a - D_t\langle\tilde\sigma_a\rangle_+ \text{ in principal axes}.

:math:`\tilde\sigma_1` is the largest principal value including zz; in 3D (xz, yz non-zero) the
principal values and axes come from Jacobi rotations (:func:`principal`).

Crack-band width [D, calibrated by spec check 7, ``tests/impact/test_experiments.py``]: the spec's
first guess ℓ_c = h(0) over-dissipates (1.68 G_F at κ = 1 on the notched 200 mm bar pulled at
0.05 m/s): the crack between two particle columns softens *both* columns (the velocity gradient
across the opening is shared by the particles on either side), so the band is never narrower
than 2Δ (2 columns at κ = 0.7 and 1.0, 3 at κ = 1.5); with ℓ_c = 2Δ the bar dissipates 1.05 G_F
at Δ = 4 mm and 1.04 G_F at Δ = 2 mm. Hence

.. math::
    \ell_c = \max(2\Delta,\; \tfrac53 h(0))

(2Δ for κ ≤ 1.2, 3Δ at κ = 1.5: 1.14 G_F). ``material.crack_band_width`` overrides it.

Cracks close in compression (a fully damaged point
still carries compressive stress); unloading is secant because D_t depends on ε_max only.

Names: the spec writes the history variable κ, κ0, κ_f; here it is ε_max (``eps_max``), ε_0,
ε_f (``eps_0``, ``eps_f``), because κ names the support-domain multiplier everywhere else.
The stress returned is the *nominal* stress used by the momentum equation; the *effective*
stress stays the state variable.
"""

import math

import numpy as np
from numba import njit

from craquelure.impact.effects import F_T, G_F
from craquelure.registry import Effect, Param

EFFECT = Effect("impact", "damage", "DAMAGE",
                "Rankine tensile damage, crack band, linear softening (f_t, G_F)",
                params=(F_T, G_F, Param("eps_0"), Param("eps_f")))


def crack_band_width(spacing: float, h0: float) -> float:
    """Default ℓ_c = max(2Δ, 5 h(0)/3) (see the module docstring)."""
    return max(2.0 * spacing, 5.0 * h0 / 3.0)


@njit(inline="always", cache=True)
def in_plane_principal(sxx, syy, sxy):
    """(s1, s2, cos 2θ, sin 2θ) of the in-plane block, s1 >= s2."""
    c = 0.5 * (sxx + syy)
    a = 0.5 * (sxx - syy)
    rad = math.sqrt(a * a + sxy * sxy)
    if rad > 0.0:
        return c + rad, c - rad, a / rad, sxy / rad
    return c, c, 1.0, 0.0


@njit(inline="always", cache=True)
def damage_from_strain(eps_max, eps_0, eps_f):
    if eps_max <= eps_0:
        return 0.0
    if eps_max >= eps_f:
        return 1.0
    return eps_f * (eps_max - eps_0) / (eps_max * (eps_f - eps_0))


@njit(inline="always", cache=True)
def principal(s):
    """Eigen-decomposition of the symmetric tensor s = (xx, yy, xy, zz, xz, yz) by cyclic
    Jacobi rotations: (eigenvalues (3,), eigenvectors as the columns of a (3, 3) array); stops
    when the off-diagonal part is below 1e-30 of the norm² (round-off), at most 20 sweeps."""
    a = np.empty((3, 3))
    a[0, 0], a[1, 1], a[2, 2] = s[0], s[1], s[3]
    a[0, 1] = a[1, 0] = s[2]
    a[0, 2] = a[2, 0] = s[4]
    a[1, 2] = a[2, 1] = s[5]
    v = np.eye(3)
    norm2 = 0.0
    for p in range(3):
        for q in range(3):
            norm2 += a[p, q] * a[p, q]
    for _ in range(20):
        off = a[0, 1] * a[0, 1] + a[0, 2] * a[0, 2] + a[1, 2] * a[1, 2]
        if off <= 1e-30 * norm2:
            break
        for p, q in ((0, 1), (0, 2), (1, 2)):
            apq = a[p, q]
            if apq == 0.0:
                continue
            theta = (a[q, q] - a[p, p]) / (2.0 * apq)
            if abs(theta) > 1e150:
                t = 0.5 / theta
            else:
                t = (1.0 if theta >= 0.0 else -1.0) / (abs(theta) + math.sqrt(theta * theta
                                                                                + 1.0))
            c = 1.0 / math.sqrt(t * t + 1.0)
            sn = t * c
            for k in range(3):  # A <- A J (columns p, q)
                akp, akq = a[k, p], a[k, q]
                a[k, p] = c * akp - sn * akq
                a[k, q] = sn * akp + c * akq
            for k in range(3):  # A <- J^T A (rows p, q)
                apk, aqk = a[p, k], a[q, k]
                a[p, k] = c * apk - sn * aqk
                a[q, k] = sn * apk + c * aqk
            for k in range(3):  # V <- V J
                vkp, vkq = v[k, p], v[k, q]
                v[k, p] = c * vkp - sn * vkq
                v[k, q] = sn * vkp + c * vkq
    lam = np.empty(3)
    for k in range(3):
        lam[k] = a[k, k]
    return lam, v


@njit(inline="always", cache=True)
def principal_bound(s):
    """Gershgorin's upper bound of the principal values of s = (xx, yy, xy, zz, xz, yz): the
    3D paths skip the Jacobi rotations when it shows no tensile part (compressed particles)."""
    return max(s[0] + abs(s[2]) + abs(s[4]),
               max(s[1] + abs(s[2]) + abs(s[5]), s[3] + abs(s[4]) + abs(s[5])))


@njit(inline="always", cache=True)
def from_principal(r, v):
    """Σ_a r_a v_a v_aᵀ as (xx, yy, xy, zz, xz, yz) (v_a the columns of v)."""
    xx = yy = xy = zz = xz = yz = 0.0
    for a in range(3):
        x, y, z = v[0, a], v[1, a], v[2, a]
        xx += r[a] * x * x
        yy += r[a] * y * y
        xy += r[a] * x * y
        zz += r[a] * z * z
        xz += r[a] * x * z
        yz += r[a] * y * z
    return xx, yy, xy, zz, xz, yz


@njit(inline="always", cache=True)
def damage_update(s, eps_max, young, eps_0, eps_f, d_min=0.0):
    """Returns (kappa, D_t, nominal stress) for the effective stress s, both (xx, yy, xy, zz,
    xz, yz); D_t is at least ``d_min`` (rate effects: the softening strain grows with the
    rate, the damage stays). With xz = yz = 0 (2D, or a 3D state with z principal) the
    in-plane block is diagonalised in closed form; otherwise by :func:`principal`."""
    sxx, syy, sxy, szz, sxz, syz = s
    if sxz == 0.0 and syz == 0.0:
        s1, s2, c2, s2t = in_plane_principal(sxx, syy, sxy)
        eps_max = max(eps_max, max(max(s1, szz), 0.0) / young)
        d = max(damage_from_strain(eps_max, eps_0, eps_f), d_min)
        if d == 0.0:
            return eps_max, d, s
        n1 = s1 - d * max(s1, 0.0)
        n2 = s2 - d * max(s2, 0.0)
        nzz = szz - d * max(szz, 0.0)
        c = 0.5 * (n1 + n2)
        a = 0.5 * (n1 - n2)
        return eps_max, d, (c + a * c2, c - a * c2, a * s2t, nzz, 0.0, 0.0)
    bound = principal_bound(s)
    if bound <= 0.0 or bound <= eps_max * young:
        # no principal value above the history: kappa unchanged; no tensile part to soften
        # when all are <= 0, nothing to soften when D = 0
        d = max(damage_from_strain(eps_max, eps_0, eps_f), d_min)
        if bound <= 0.0 or d == 0.0:
            return eps_max, d, s
    lam, vec = principal(s)
    eps_max = max(eps_max, max(lam.max(), 0.0) / young)
    d = max(damage_from_strain(eps_max, eps_0, eps_f), d_min)
    if d == 0.0:
        return eps_max, d, s
    # σ − D Σ_a <σ_a>+ n_a n_aᵀ
    for a in range(3):
        lam[a] = d * max(lam[a], 0.0)
    cxx, cyy, cxy, czz, cxz, cyz = from_principal(lam, vec)
    return eps_max, d, (sxx - cxx, syy - cyy, sxy - cxy, szz - czz, sxz - cxz, syz - cyz)
