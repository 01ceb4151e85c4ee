r"""Drucker-Prager perfect plasticity with radial return, zero dilatancy (spec section 2.2).

.. math::
    f = \sqrt{J_2} + \alpha I_1 - k \le 0, \quad I_1 = \mathrm{tr}\tilde\sigma, \quad
    \alpha = \frac{f_{bc} - f_c}{\sqrt3\,(2f_{bc} - f_c)}, \quad k = f_c(1/\sqrt3 - \alpha),

fitted to uniaxial (:math:`f_c`) and equibiaxial (:math:`f_{bc} = 1.16 f_c`) compression
(:math:`\alpha = 0.0700`, :math:`k = 21.87` MPa). If :math:`f > 0`: :math:`s \leftarrow r s`,
:math:`r = (k - \alpha I_1)/\sqrt{J_2}` (:math:`s = 0` if :math:`r < 0`), the pressure is
unchanged; :math:`\Delta\bar\varepsilon_p = (1-r)\sqrt{J_2^{trial}}/(\sqrt3 G)`; plastic work
density :math:`s:(s^{tr}-s)/(2G) = r(1-r) J_2^{tr}/G` (:math:`J_2^{tr}/G` if r is clipped to 0).
:math:`J_2 = \tfrac12 s:s` includes :math:`s_{zz}` (plane strain keeps it) and, in 3D,
:math:`s_{xz}, s_{yz}`.

Decision [D]: the return is applied only for a compressive mean stress (:math:`I_1 < 0`). The
cone's tensile side (uniaxial tension at :math:`k/(1/\sqrt3+\alpha)` = 33.8 MPa effective) would
otherwise cap :math:`\tilde\sigma_1` far below :math:`E\varepsilon_f` (320 MPa at ℓ_c = 4.8 mm), so
the Rankine softening could never complete and G_F would not be dissipated; tension is the
damage model's domain (check 6 tests both).
"""

import math

from numba import njit

from craquelure.impact.effects import F_C
from craquelure.registry import Effect, Param

EFFECT = Effect("impact", "plasticity", "PLASTICITY",
                "Drucker-Prager radial return (f_c, f_bc = 1.16 f_c), zero dilatancy",
                params=(F_C, Param("alpha_dp"), Param("k_dp", None, "Pa")))


def dp_constants(f_c: float, f_bc_ratio: float) -> tuple[float, float]:
    """(alpha, k) of the Drucker-Prager cone through f_c and f_bc = ratio f_c."""
    f_bc = f_bc_ratio * f_c
    alpha = (f_bc - f_c) / (math.sqrt(3.0) * (2.0 * f_bc - f_c))
    return alpha, f_c * (1.0 / math.sqrt(3.0) - alpha)


@njit(inline="always", cache=True)
def dp_return(s, alpha, k, shear):
    """Returns (stress (xx, yy, xy, zz, xz, yz), d_eps_p, plastic work density) for the trial
    stress ``s`` in the same order (xz = yz = 0 in 2D)."""
    sxx, syy, sxy, szz, sxz, syz = s
    i1 = sxx + syy + szz
    m = i1 / 3.0
    dxx, dyy, dzz = sxx - m, syy - m, szz - m
    j2 = 0.5 * (dxx * dxx + dyy * dyy + dzz * dzz) + sxy * sxy + sxz * sxz + syz * syz
    sq = math.sqrt(j2)
    if i1 >= 0.0 or sq + alpha * i1 - k <= 0.0:
        return s, 0.0, 0.0
    r = (k - alpha * i1) / sq
    if r < 0.0:
        r = 0.0
    deps = (1.0 - r) * sq / (math.sqrt(3.0) * shear)
    work = r * (1.0 - r) * j2 / shear if r > 0.0 else j2 / shear
    return (m + r * dxx, m + r * dyy, r * sxy, m + r * dzz, r * sxz, r * syz), deps, work
