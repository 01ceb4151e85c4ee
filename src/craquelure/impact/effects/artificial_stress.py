r"""Monaghan artificial stress against the tensile instability (Monaghan 2000; Gray, Monaghan &
Swift 2001; spec section 3).

The nominal stress :math:`\sigma_i` is rotated to principal axes
(:math:`\tan 2\theta = 2\sigma_{xy}/(\sigma_{xx}-\sigma_{yy})`);
:math:`R'_a = -\varepsilon_{AS}\sigma'_a/\rho_i^2` if :math:`\sigma'_a > 0`, else 0; rotated back:
:math:`R_{xx} = c^2R'_1 + s^2R'_2`, :math:`R_{yy} = s^2R'_1 + c^2R'_2`,
:math:`R_{xy} = cs(R'_1 - R'_2)`. The pair term :math:`f_{ij}^n (R_i + R_j)` with
:math:`f_{ij} = W(r_{ij}; h_{ij})/W(\Delta; h_{ij})`, n = ``numerics.as_n`` (4), is added to the
momentum bracket. 2D: in-plane components only (zz does not enter the 2D momentum equation);
3D: all six components, principal axes of the full 3x3 stress (Jacobi rotations).

Decisions: σ is the total nominal stress (Gray et al. 2001; a deviatoric R would vanish in
hydrostatic tension); Δ is the initial particle spacing ``particles.spacing`` (fixed; not h, not the
current spacing) and W(Δ; h_ij) uses the same kernel and h_ij as W(r_ij; h_ij), so the kernel
normalisation cancels and f(Δ) = 1 for every h. The pair term is symmetric in i, j and multiplies
∇_iW_ij, so it is antisymmetric and conserves momentum. No separate time-step limit: the AS
stiffness is ε_AS σ ≈ 1e-4 of the elastic one (the growth below persists at half the CFL).

Decision on ε_AS (spec: 0.3, a [D] value; check 8, tests/impact/test_engine.py). In all-tensile
states R_j follows the stress fluctuation, δR_j = −ε_AS δσ_j/ρ_j², which with n = 4 weakens only
the nearest-neighbour (f = 1) part of the SPH stress gradient (diagonal neighbours at h = 1.2Δ:
f⁴ = 0.015). Too large an ε_AS therefore reverses the gradient for short modes and makes the
instability worse, not better. Linearised one leapfrog step of this code (8 × 8 periodic lattice
in 0.8 f_t biaxial tension, no AV; same rates in uniaxial tension), growth rate in 1/s:

    h(0)/Δ (κ)     ε_AS = 0   0.1     0.15    0.2     0.25    0.3
    0.84 (0.7)     2.8e4      2.0e4   1.3e4   7.0e3   7.7e3   8.3e3
    1.2  (1.0)     1.4e4      8.7e3   4.2e3   2.1e4   3.4e4   4.7e4
    1.8  (1.5)     0.3        4.1e3   8.1e3   1.1e4   -       1.5e4

At h(0) = 1.8Δ the nearest neighbour sits inside the cubic spline's inflection point
(q = 0.56 < 2/3): the scheme has no tensile instability (0.3 1/s is neutral: e^3e-4 over a
1 ms run; 0.05 is neutral too) and ε_AS ≥ 0.1 creates one. So
``numerics.as_epsilon: auto`` takes the minimiser measured at the paper's three supports,
ε_AS = 0.2 / 0.15 / 0 at h(0)/Δ = 0.84 / 1.2 / 1.8, linearly interpolated in h(0)/Δ between
them and held constant outside; with it check 8 passes at every κ, while the spec's 0.3 at κ = 1
lets the velocity noise grow ×2.2 in 2000 steps (the growing mode is kΔ = (π/2, π)). The
value used is recorded in each run's attributes (``as_epsilon``).
"""

import numpy as np
from numba import njit

from craquelure.impact.effects.damage import (
    from_principal,
    in_plane_principal,
    principal,
    principal_bound,
)
from craquelure.registry import Effect, Param

EFFECT = Effect("impact", "artificial_stress", "ARTIFICIAL_STRESS",
                "Monaghan artificial stress (epsilon_AS, n) against tensile instability",
                requires=("numerics.as_epsilon",),
                params=(Param("as_epsilon"), Param("as_n", "numerics.as_n")))


# (h(0)/Delta, eps_AS minimising the linearised tensile growth); see the table above.
AUTO_EPSILON = ((0.84, 0.2), (1.2, 0.15), (1.8, 0.0))


def as_epsilon(value: float | str, support_ratio: float) -> float:
    """ε_AS of a run: ``numerics.as_epsilon`` (a number, or ``auto``: :func:`auto_epsilon` at
    h(0)/Δ = ``support_ratio``)."""
    return auto_epsilon(support_ratio) if value == "auto" else float(value)


def auto_epsilon(support_ratio: float) -> float:
    """ε_AS for ``as_epsilon: auto`` at h(0)/Δ = ``support_ratio``."""
    ratio, eps = zip(*AUTO_EPSILON, strict=True)
    # rounded: 1.2 * 1.5 = 1.7999999999999998 would give 6e-17 instead of 0
    return round(float(np.interp(support_ratio, ratio, eps)), 12)


@njit(inline="always", cache=True)
def artificial_stress_tensor(s, rho, eps):
    """R of particle i, (xx, yy, xy, zz, xz, yz), from its nominal stress s in the same order.
    2D uses the in-plane part (xx, yy, xy); with xz = yz = 0 the in-plane block is rotated in
    closed form (R_zz from σ_zz alone), otherwise by the Jacobi decomposition of the 3x3 stress."""
    sxx, syy, sxy, szz, sxz, syz = s
    inv = -eps / (rho * rho)
    if sxz == 0.0 and syz == 0.0:
        s1, s2, c2, s2t = in_plane_principal(sxx, syy, sxy)
        r1 = inv * s1 if s1 > 0.0 else 0.0
        r2 = inv * s2 if s2 > 0.0 else 0.0
        # c^2 = (1 + cos 2θ)/2, s^2 = (1 - cos 2θ)/2, cs = sin 2θ / 2
        cc, ss, cs = 0.5 * (1.0 + c2), 0.5 * (1.0 - c2), 0.5 * s2t
        rzz = inv * szz if szz > 0.0 else 0.0
        return cc * r1 + ss * r2, ss * r1 + cc * r2, cs * (r1 - r2), rzz, 0.0, 0.0
    if principal_bound(s) <= 0.0:  # no tensile principal stress
        return 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    lam, vec = principal(s)
    for a in range(3):
        lam[a] = inv * lam[a] if lam[a] > 0.0 else 0.0
    return from_principal(lam, vec)
