r"""Rate function template of the drying paste (drying spec section 6); specialised per effect
set by :mod:`craquelure.codegen` (the FLAGS block is replaced, absent effects compile out).

State rows (struct of arrays, shape ``(NVAR, N)``): x, y (unwrapped positions), vx, vy, rho,
sigma_e xx, yy, xy. Two pair passes per evaluation:

1. velocity gradient :math:`L^I_{ab} = \sum_J V_J (v^J_a - v^I_a)\,\partial_b W_{IJ}` (times
   :math:`M^{-1}` with ``gradient_correction``) and the XSPH sum; then per particle the total
   stress :math:`\sigma = \eta D + \sigma_e + v_r t \mathbf 1`,
   the Jaumann rate of :math:`\sigma_e`, :math:`\dot\rho = -\rho\,\mathrm{tr} L`,
   :math:`\dot{\mathbf r} = \mathbf v + \epsilon\,\text{XSPH}`;
2. momentum :math:`\dot v^I_a = \sum_J m_J (\sigma^I_{ab}/\rho_I^2 + \sigma^J_{ab}/\rho_J^2)\,
   \partial_b W_{IJ} - \mu u^I_a/(H^2\rho^I)`.

Pairs come from a CSR Verlet list (radius h + skin); pairs beyond h contribute exactly 0.
Removed particles (``alive == 0``) have zero mass and zero rates.
"""

import numpy as np
from numba import njit, prange

from craquelure.codegen import param_indices
from craquelure.drying.effects.continuity import density_rate
from craquelure.drying.effects.drying import drying_stress
from craquelure.drying.effects.elasticity import jaumann_rate
from craquelure.drying.effects.gradient_correction import corrected_gradient
from craquelure.drying.effects.substrate import substrate_acceleration
from craquelure.drying.effects.viscosity import viscous_stress
from craquelure.drying.effects.xsph import xsph_pair
from craquelure.periodic import minimum_image
from craquelure.sph.kernels import kernel_dwdr, kernel_w_dwdr

# BEGIN FLAGS
CONTINUITY = True
DRYING = True
ELASTICITY = True
GRADIENT_CORRECTION = False
KERNEL = 0
SUBSTRATE = True
VISCOSITY = True
XSPH = True
# END FLAGS

X, Y, VX, VY, RHO, SXX, SYY, SXY = 0, 1, 2, 3, 4, 5, 6, 7
NVAR = 8
# the parameter vector: names in order, declared once (the engine packs by name)
PARAMS = ("lame_lambda", "lame_mu", "eta", "drying_rate", "thickness", "xsph_epsilon", "support",
          "box_length", "drying_stress_cap")
P_LAMBDA, P_MU, P_ETA, P_VR, P_THICK, P_EPS, P_SUPPORT, P_BOX, P_DRYCAP = param_indices(
    PARAMS, "lame_lambda", "lame_mu", "eta", "drying_rate", "thickness", "xsph_epsilon", "support",
    "box_length", "drying_stress_cap")


@njit(parallel=True, cache=True)
def rate(state, t, mass, alive, x0, y0, offsets, index, p, out, stress):
    """Fill ``out`` (NVAR, N) with dY/dt and ``stress`` (3, N) with the total stress."""
    n = state.shape[1]
    s = p[P_SUPPORT]
    box = p[P_BOX]
    s2 = s * s
    # Per-particle factors hoisted out of the pair loops: V_J = m_J/rho_J (pass 1) and
    # sigma_J/rho_J^2 (pass 2).
    volume = np.empty(n)
    # dW/dr / r of every listed pair, written by pass 1 for every pair of a present particle
    # and reused by pass 2 (0 beyond the support and for coincident particles)
    gfac = np.empty(index.size)
    for i in prange(n):
        volume[i] = mass[i] / state[RHO, i] if alive[i] else 0.0
    for i in prange(n):
        if not alive[i]:
            for v in range(NVAR):
                out[v, i] = 0.0
            stress[0, i] = 0.0
            stress[1, i] = 0.0
            stress[2, i] = 0.0
            continue
        xi, yi = state[X, i], state[Y, i]
        vxi, vyi = state[VX, i], state[VY, i]
        rhoi = state[RHO, i]
        lxx = 0.0
        lxy = 0.0
        lyx = 0.0
        lyy = 0.0
        hx = 0.0
        hy = 0.0
        mxx = 0.0
        mxy = 0.0
        myx = 0.0
        myy = 0.0
        for k in range(offsets[i], offsets[i + 1]):
            j = index[k]
            dx = minimum_image(xi - state[X, j], box)
            dy = minimum_image(yi - state[Y, j], box)
            r2 = dx * dx + dy * dy
            if r2 >= s2:
                gfac[k] = 0.0
                continue
            r = np.sqrt(r2)
            dvx = state[VX, j] - vxi
            dvy = state[VY, j] - vyi
            if XSPH:
                w, dwdr = kernel_w_dwdr(KERNEL, r, s, 2)
            else:
                w, dwdr = 0.0, kernel_dwdr(KERNEL, r, s, 2)
            g = dwdr / r if r > 0.0 else 0.0
            gfac[k] = g
            if r > 0.0:
                f = volume[j] * g
                gx = f * dx
                gy = f * dy
                lxx += dvx * gx
                lxy += dvx * gy
                lyx += dvy * gx
                lyy += dvy * gy
                if GRADIENT_CORRECTION:
                    # r_J - r_I = -(dx, dy)
                    mxx -= dx * gx
                    mxy -= dx * gy
                    myx -= dy * gx
                    myy -= dy * gy
            if XSPH:
                cx, cy = xsph_pair(mass[j], rhoi, state[RHO, j], dvx, dvy, w)
                hx += cx
                hy += cy
        if GRADIENT_CORRECTION:
            lxx, lxy, lyx, lyy = corrected_gradient(lxx, lxy, lyx, lyy, mxx, mxy, myx, myy)
        sxx = state[SXX, i]
        syy = state[SYY, i]
        sxy = state[SXY, i]
        if VISCOSITY:
            vxx, vyy, vxy = viscous_stress(lxx, lxy, lyx, lyy, p[P_ETA])
            sxx += vxx
            syy += vyy
            sxy += vxy
        if DRYING:
            dry = drying_stress(t, p[P_VR], p[P_DRYCAP])
            sxx += dry
            syy += dry
        stress[0, i] = sxx
        stress[1, i] = syy
        stress[2, i] = sxy
        if ELASTICITY:
            a, b, c = jaumann_rate(lxx, lxy, lyx, lyy, state[SXX, i], state[SYY, i],
                                   state[SXY, i], p[P_LAMBDA], p[P_MU])
            out[SXX, i] = a
            out[SYY, i] = b
            out[SXY, i] = c
        else:
            out[SXX, i] = 0.0
            out[SYY, i] = 0.0
            out[SXY, i] = 0.0
        if CONTINUITY:
            out[RHO, i] = density_rate(rhoi, lxx, lyy)
        else:
            out[RHO, i] = 0.0
        if XSPH:
            out[X, i] = vxi + p[P_EPS] * hx
            out[Y, i] = vyi + p[P_EPS] * hy
        else:
            out[X, i] = vxi
            out[Y, i] = vyi
    scaled = np.empty((3, n))
    for i in prange(n):
        inv2 = 1.0 / (state[RHO, i] * state[RHO, i])
        scaled[0, i] = stress[0, i] * inv2
        scaled[1, i] = stress[1, i] * inv2
        scaled[2, i] = stress[2, i] * inv2
    for i in prange(n):
        if not alive[i]:
            continue
        xi, yi = state[X, i], state[Y, i]
        rhoi = state[RHO, i]
        axx = scaled[0, i]
        ayy = scaled[1, i]
        axy = scaled[2, i]
        ax = 0.0
        ay = 0.0
        for k in range(offsets[i], offsets[i + 1]):
            g = gfac[k]
            if g == 0.0:
                continue
            j = index[k]
            dx = minimum_image(xi - state[X, j], box)
            dy = minimum_image(yi - state[Y, j], box)
            f = mass[j] * g
            gx = f * dx
            gy = f * dy
            txx = axx + scaled[0, j]
            tyy = ayy + scaled[1, j]
            txy = axy + scaled[2, j]
            ax += txx * gx + txy * gy
            ay += txy * gx + tyy * gy
        if SUBSTRATE:
            bx, by = substrate_acceleration(xi - x0[i], yi - y0[i], rhoi, p[P_MU], p[P_THICK])
            ax += bx
            ay += by
        out[VX, i] = ax
        out[VY, i] = ay
