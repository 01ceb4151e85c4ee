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
   \partial_b W_{IJ} - \mu u^I_a/(H^2\rho^I) + g_a`.

Pairs come from a CSR Verlet list (radius h + skin); pairs beyond h contribute exactly 0.
Removed particles (``alive == 0``) have zero mass and zero rates.

The pair loops are written for LLVM's loop vectoriser (issue 28; measured by
benchmarks/drying_roofline.py): no branch in the loop body (the branch-free quintic
:func:`~craquelure.sph.kernels.kernel_w_g` from r^2, 0 beyond the support and g = 0 at r = 0), no
per-pair store (pass 2 recomputes dW/dr / r: a store next to the gathers cannot be proven free
of aliasing and blocks vectorisation), an unsigned loop index (a signed one makes numba's
negative-index wraparound, which LLVM turns into a gather of the index array), the minimum image
by multiplication with 1/L, numpy's error model (no ZeroDivisionError branch: a division by zero
gives inf/NaN, which the engine's guards stop) and reassociated sums (``PAIR_FASTMATH``; the
sums' order, hence their last bits, depends on the vector width). Particles are in cell order
(the initial state sorts them, :mod:`craquelure.drying.initial_state`), so the gathers of a
particle's neighbours hit few cache lines.
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
from craquelure.periodic import minimum_image_inv
from craquelure.registry import parameter_names
from craquelure.sph.kernels import kernel_w_g

# BEGIN FLAGS
BODY_FORCE = False
CONTINUITY = True
DRYING = True
ELASTICITY = True
GRADIENT_CORRECTION = False
KERNEL = 0
SUBSTRATE = True
VISCOSITY = True
XSPH = True
# END FLAGS

# Reassociation lets LLVM vectorise the pair sums (their order, hence the last bits, changes);
# contraction allows FMA. No finite-math assumptions: a NaN in the state still propagates
# to the guards.
PAIR_FASTMATH = {"reassoc", "contract", "nsz"}

X, Y, VX, VY, RHO, SXX, SYY, SXY = 0, 1, 2, 3, 4, 5, 6, 7
NVAR = 8
# the parameter vector, as the effects declare it (craquelure.registry); the engine packs it
PARAMS = parameter_names("drying")
P_LAMBDA, P_MU, P_ETA, P_VR, P_THICK, P_EPS, P_SUPPORT, P_BOX, P_DRYCAP, P_BODY = param_indices(
    PARAMS, "lame_lambda", "lame_mu", "eta", "drying_rate", "thickness", "xsph_epsilon", "support",
    "box_length", "drying_stress_cap", "body_force")


PAIR_OPTIONS = dict(parallel=True, cache=True, fastmath=PAIR_FASTMATH, error_model="numpy")


@njit(cache=True)
def rate(state, t, mass, alive, x0, y0, offsets, index, p, out, stress):
    """Fill ``out`` (NVAR, N) with dY/dt and ``stress`` (3, N) with the total stress. Two
    parallel loops (pass 1 and pass 2; V_J = m_J/rho_J is formed in the pair loop, not in a
    loop of its own: one parallel region and one gather fewer)."""
    scaled = np.empty((3, state.shape[1]))
    gradient_pass(state, t, mass, alive, offsets, index, p, out, stress, scaled)
    momentum_pass(state, mass, alive, x0, y0, offsets, index, p, scaled, out)


@njit(**PAIR_OPTIONS)
def gradient_pass(state, t, mass, alive, offsets, index, p, out, stress, scaled):
    """Pass 1: L, XSPH, the total stress (and sigma/rho^2 for pass 2) and every rate but the
    velocity's."""
    n = state.shape[1]
    s = p[P_SUPPORT]
    inv_s = 1.0 / s
    box = p[P_BOX]
    inv_box = 1.0 / box
    xs, ys, vxs, vys, rhos = state[X], state[Y], state[VX], state[VY], state[RHO]
    for i in prange(n):
        if not alive[i]:
            for v in range(NVAR):
                out[v, i] = 0.0
            stress[0, i] = 0.0
            stress[1, i] = 0.0
            stress[2, i] = 0.0
            scaled[0, i] = 0.0
            scaled[1, i] = 0.0
            scaled[2, i] = 0.0
            continue
        xi, yi = xs[i], ys[i]
        vxi, vyi = vxs[i], vys[i]
        rhoi = rhos[i]
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
        # branch-free pair loop (vectorised by LLVM): pairs beyond the support and coincident
        # particles have w = g = 0 and add exactly 0. An unsigned k makes index[k] a plain
        # load (a signed one gets numba's negative-index wraparound, which LLVM turns into a
        # gather of the index array: 8x slower)
        for k in range(np.uint64(offsets[i]), np.uint64(offsets[i + 1])):
            j = index[k]
            dx = minimum_image_inv(xi - xs[j], box, inv_box)
            dy = minimum_image_inv(yi - ys[j], box, inv_box)
            w, g = kernel_w_g(KERNEL, dx * dx + dy * dy, s, inv_s)
            dvx = vxs[j] - vxi
            dvy = vys[j] - vyi
            mj = mass[j]
            rhoj = rhos[j]
            if XSPH:
                # one division gives V_J = m_J/rho_J and 1/(rho_I + rho_J) for XSPH
                rsum = rhoi + rhoj
                dinv = 1.0 / (rhoj * rsum)
                vj = mj * (rsum * dinv)
                cx, cy = xsph_pair(mj, rhoj * dinv, dvx, dvy, w)
                hx += cx
                hy += cy
            else:
                vj = mj / rhoj
            f = vj * g
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
        inv2 = 1.0 / (rhoi * rhoi)
        scaled[0, i] = sxx * inv2
        scaled[1, i] = syy * inv2
        scaled[2, i] = sxy * inv2
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


@njit(**PAIR_OPTIONS)
def momentum_pass(state, mass, alive, x0, y0, offsets, index, p, scaled, out):
    """Pass 2: the velocity rate (pairwise antisymmetric momentum sum, substrate, body
    force)."""
    n = state.shape[1]
    s = p[P_SUPPORT]
    inv_s = 1.0 / s
    box = p[P_BOX]
    inv_box = 1.0 / box
    xs, ys, rhos = state[X], state[Y], state[RHO]
    sxxs, syys, sxys = scaled[0], scaled[1], scaled[2]
    for i in prange(n):
        if not alive[i]:
            continue
        xi, yi = xs[i], ys[i]
        rhoi = rhos[i]
        axx = scaled[0, i]
        ayy = scaled[1, i]
        axy = scaled[2, i]
        ax = 0.0
        ay = 0.0
        for k in range(np.uint64(offsets[i]), np.uint64(offsets[i + 1])):
            j = index[k]
            dx = minimum_image_inv(xi - xs[j], box, inv_box)
            dy = minimum_image_inv(yi - ys[j], box, inv_box)
            # g recomputed, not stored by pass 1: a per-pair store stops the vectoriser (it
            # cannot rule out aliasing) and costs more memory traffic than the arithmetic
            _, g = kernel_w_g(KERNEL, dx * dx + dy * dy, s, inv_s)
            f = mass[j] * g
            gx = f * dx
            gy = f * dy
            txx = axx + sxxs[j]
            tyy = ayy + syys[j]
            txy = axy + sxys[j]
            ax += txx * gx + txy * gy
            ay += txy * gx + tyy * gy
        if SUBSTRATE:
            bx, by = substrate_acceleration(xi - x0[i], yi - y0[i], rhoi, p[P_MU], p[P_THICK])
            ax += bx
            ay += by
        if BODY_FORCE:
            ax += p[P_BODY]
            ay += p[P_BODY + 1]
        out[VX, i] = ax
        out[VY, i] = ay
