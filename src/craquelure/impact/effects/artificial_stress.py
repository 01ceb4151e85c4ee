r"""Monaghan artificial stress against the tensile instability (Monaghan 2000; Gray, Monaghan &
Swift 2001; spec section 3).

The nominal stress :math:`\sigma_i` is rotated to principal axes
(:math:`\tan 2\theta = 2\sigma_{xy}/(\sigma_{xx}-\sigma_{yy})`);
:math:`R'_a = -\varepsilon_{AS}\sigma'_a/\rho_i^2` if :math:`\sigma'_a > 0`, else 0; rotated back:
:math:`R_{xx} = c^2R'_1 + s^2R'_2`, :math:`R_{yy} = s^2R'_1 + c^2R'_2`,
:math:`R_{xy} = cs(R'_1 - R'_2)`. The pair term :math:`f_{ij}^n (R_i + R_j)` with
:math:`f_{ij} = W(r_{ij}; h_{ij})/W(\Delta; h_{ij})`, n = ``numerics.as_n`` (4), is added to the
momentum bracket. In-plane components only (zz does not enter the 2D momentum equation).

Decisions: σ is the total nominal stress (Gray et al. 2001; a deviatoric R would vanish in
hydrostatic tension); Δ is the initial particle spacing ``particles.spacing`` (fixed; not h, not the
current spacing) and W(Δ; h_ij) uses the same kernel and h_ij as W(r_ij; h_ij), so the kernel
normalisation cancels and f(Δ) = 1 for every h. The pair term is symmetric in i, j and multiplies
∇_iW_ij, so it is antisymmetric and conserves momentum. No separate time-step limit: the AS
stiffness is ε_AS σ ≈ 1e-4 of the elastic one, and at CFL 0.15 instead of 0.3 check 8 still
grows (stress noise ×2.5 over steps 500-2000), so its growth is no time-step instability.

Known property (spec check 8, tests/impact/test_engine.py): in all-tensile states R_j follows the
stress fluctuation, δR_j = −ε_AS δσ_j/ρ_j², which with n = 4 and h = 1.2Δ weakens only the
nearest-neighbour (f = 1) part of the stress gradient (diagonal neighbours: f⁴ = 0.015). For
modes with k_yΔ = π the diagonal contributions have the opposite sign, and above ε_AS ≈ 0.25
(scalar estimate at kΔ = (π/2, π)) the gradient reverses: the linearised scheme (no AV) grows at
4.7e4 1/s at ε_AS = 0.3 versus 1.4e4 1/s without AS and 6.0e3 1/s with R frozen at the uniform
stress. The formula is kept as specified (Monaghan 2000; Gray et al. 2001).
"""

from numba import njit

from craquelure.impact.effects.damage import in_plane_principal
from craquelure.registry import Effect

EFFECT = Effect(
    name="artificial_stress",
    models=("impact",),
    description="Monaghan artificial stress (epsilon_AS, n) against tensile instability",
    requires={"impact": ("numerics.as_epsilon",)},
)


@njit(inline="always", cache=True)
def artificial_stress_tensor(sxx, syy, sxy, rho, eps):
    """(R_xx, R_yy, R_xy) of particle i from its nominal in-plane stress."""
    s1, s2, c2, s2t = in_plane_principal(sxx, syy, sxy)
    r1 = -eps * s1 / (rho * rho) if s1 > 0.0 else 0.0
    r2 = -eps * s2 / (rho * rho) if s2 > 0.0 else 0.0
    # c^2 = (1 + cos 2θ)/2, s^2 = (1 - cos 2θ)/2, cs = sin 2θ / 2
    cc, ss, cs = 0.5 * (1.0 + c2), 0.5 * (1.0 - c2), 0.5 * s2t
    return cc * r1 + ss * r2, ss * r1 + cc * r2, cs * (r1 - r2)
