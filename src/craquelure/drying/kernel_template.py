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

Pairs come from a cluster-pair structure (:func:`~craquelure.sph.neighbours.cluster_pairs`,
Verlet radius h + skin): clusters of LANES spatially close particles, each with the list of
every J near one of its members. An evaluation copies the state to slot order once
(``to_clusters``); for each cluster the pair loops hold its members in contiguous lanes and
broadcast each listed J to all of them, so every load is contiguous or a scalar broadcast (no
gather of neighbour data), and write the rates back in particle order. A lane farther than h
from J is a masked visit and adds exactly 0, as do removed particles (``alive == 0``: zero mass,
zero rates) and empty slots. Each particle's sums run over its cluster's J in list order, one
lane each, so the results do not depend on the thread count.

The lane loops are written for LLVM's loop vectoriser (measured by
benchmarks/drying_roofline.py; the comments in the loops say why each choice): no branch in the
body (the branch-free :func:`~craquelure.sph.kernels.kernel_w_g`), one local buffer per cluster,
an unsigned list index (a signed one gets numba's negative-index wraparound), the minimum image
by multiplication with 1/L, numpy's error model (a division by zero gives inf/NaN, which the
engine's guards stop) and ``PAIR_FASTMATH``."""

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
from craquelure.sph.kernels import QUINTIC, kernel_w_g, quintic_w_g_r

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

LANES = 8  # particles of a cluster, one per SIMD lane (8 doubles: AVX-512)
# rows of the slot-order copy of the state the pair loops read (V = m/rho)
C_X, C_Y, C_VX, C_VY, C_RHO, C_M, C_V = range(7)
NC = 7
# pass 1's pair sums, then (from row B) the lanes' own values
A_LXX, A_LXY, A_LYX, A_LYY, A_HX, A_HY, A_MXX, A_MXY, A_MYX, A_MYY = range(10)
B = 10


@njit(cache=True)
def rate(state, t, mass, alive, x0, y0, pairs, p, out, stress):
    """Fill ``out`` (NVAR, N) with dY/dt and ``stress`` (3, N) with the total stress.
    ``pairs`` is the :class:`~craquelure.sph.neighbours.ClusterPairs` of width LANES."""
    perm, start, jlist, outside = pairs
    c = np.empty((NC, perm.size))
    scaled = np.empty((3, perm.size))
    to_clusters(state, mass, perm, c)
    for i in outside:
        out[:, i] = 0.0
        stress[:, i] = 0.0
    gradient_pass(c, state, t, alive, perm, start, jlist, p, out, stress, scaled)
    momentum_pass(c, state, alive, x0, y0, perm, start, jlist, p, scaled, out)


@njit(**PAIR_OPTIONS)
def to_clusters(state, mass, perm, c):
    """The rows the pair loops read, in slot order (empty slots: at rest, rho 1, no mass)."""
    for s in prange(perm.size):
        i = perm[s]
        for r in range(C_M):  # x, y, vx, vy, rho: the state's first rows
            c[r, s] = state[r, i] if i >= 0 else (1.0 if r == C_RHO else 0.0)
        c[C_M, s] = mass[i] if i >= 0 else 0.0
        c[C_V, s] = mass[i] / state[RHO, i] if i >= 0 else 0.0


@njit(**PAIR_OPTIONS)
def gradient_pass(c, state, t, alive, perm, start, jlist, p, out, stress, scaled):
    """Pass 1: L, XSPH, the total stress (and sigma/rho^2 for pass 2, in slot order) and every
    rate but the velocity's."""
    s, box = p[P_SUPPORT], p[P_BOX]
    inv_s, inv_box = 1.0 / s, 1.0 / box
    for cl in prange(perm.size // LANES):
        base = cl * LANES
        # the cluster's sums (rows A_*) and its J-independent values (rows B + C_*) in one
        # buffer: LLVM then proves the lanes' loads and stores apart (no run-time alias
        # check, which stops the vectoriser on a loop of a few iterations)
        buf = np.empty((B + 5) * LANES)
        for m in range(LANES):
            for r in range(5):
                buf[(B + r) * LANES + m] = c[r, base + m]
            for r in range(B):
                buf[r * LANES + m] = 0.0
        for k in range(np.uint64(start[cl]), np.uint64(start[cl + 1])):
            j = jlist[k]
            xj, yj, vxj, vyj = c[C_X, j], c[C_Y, j], c[C_VX, j], c[C_VY, j]
            rhoj, mj, vj = c[C_RHO, j], c[C_M, j], c[C_V, j]
            # one J against the cluster's lanes, branch-free (vectorised by LLVM over the
            # lanes, contiguous loads): pairs beyond the support and coincident particles
            # have w = g = 0 and add exactly 0
            for m in range(LANES):
                dx = minimum_image_inv(buf[(B + C_X) * LANES + m] - xj, box, inv_box)
                dy = minimum_image_inv(buf[(B + C_Y) * LANES + m] - yj, box, inv_box)
                r2 = dx * dx + dy * dy
                rsum = buf[(B + C_RHO) * LANES + m] + rhoj
                if XSPH and KERNEL == QUINTIC:
                    # one division gives 1/r and XSPH's 1/(rho_I + rho_J)
                    r = np.sqrt(r2 if r2 > 1e-300 else 1e-300)
                    q = 1.0 / (r * rsum)
                    w, g = quintic_w_g_r(r, rsum * q, inv_s)
                    inv_sum = r * q
                else:
                    w, g = kernel_w_g(KERNEL, r2, s, inv_s)
                    inv_sum = 1.0 / rsum
                dvx = vxj - buf[(B + C_VX) * LANES + m]
                dvy = vyj - buf[(B + C_VY) * LANES + m]
                if XSPH:
                    cx, cy = xsph_pair(mj, inv_sum, dvx, dvy, w)
                    buf[A_HX * LANES + m] += cx
                    buf[A_HY * LANES + m] += cy
                f = vj * g
                gx = f * dx
                gy = f * dy
                buf[A_LXX * LANES + m] += dvx * gx
                buf[A_LXY * LANES + m] += dvx * gy
                buf[A_LYX * LANES + m] += dvy * gx
                buf[A_LYY * LANES + m] += dvy * gy
                if GRADIENT_CORRECTION:
                    # r_J - r_I = -(dx, dy)
                    buf[A_MXX * LANES + m] -= dx * gx
                    buf[A_MXY * LANES + m] -= dx * gy
                    buf[A_MYX * LANES + m] -= dy * gx
                    buf[A_MYY * LANES + m] -= dy * gy
        for m in range(LANES):
            i = perm[base + m]
            if i >= 0:
                particle_rates(state, t, alive, p, buf[m::LANES], i, base + m, out, stress,
                               scaled)


@njit(inline="always", cache=True)
def particle_rates(state, t, alive, p, a, i, slot, out, stress, scaled):
    """Pass 1 of particle I from its pair sums ``a``: the total stress, sigma/rho^2 (slot
    order) and every rate but the velocity's (all 0 for a removed particle)."""
    if not alive[i]:
        for v in range(NVAR):
            out[v, i] = 0.0
        for r in range(3):
            stress[r, i] = 0.0
            scaled[r, slot] = 0.0
        return
    lxx, lxy, lyx, lyy = a[A_LXX], a[A_LXY], a[A_LYX], a[A_LYY]
    if GRADIENT_CORRECTION:
        lxx, lxy, lyx, lyy = corrected_gradient(lxx, lxy, lyx, lyy, a[A_MXX], a[A_MXY],
                                                a[A_MYX], a[A_MYY])
    vxi, vyi, rhoi = state[VX, i], state[VY, i], state[RHO, i]
    sxx, syy, sxy = state[SXX, i], state[SYY, i], state[SXY, i]
    if VISCOSITY:
        vxx, vyy, vxy = viscous_stress(lxx, lxy, lyx, lyy, p[P_ETA])
        sxx, syy, sxy = sxx + vxx, syy + vyy, sxy + vxy
    if DRYING:
        dry = drying_stress(t, p[P_VR], p[P_DRYCAP])
        sxx, syy = sxx + dry, syy + dry
    stress[0, i], stress[1, i], stress[2, i] = sxx, syy, sxy
    inv2 = 1.0 / (rhoi * rhoi)
    scaled[0, slot], scaled[1, slot], scaled[2, slot] = sxx * inv2, syy * inv2, sxy * inv2
    if ELASTICITY:
        out[SXX, i], out[SYY, i], out[SXY, i] = jaumann_rate(
            lxx, lxy, lyx, lyy, state[SXX, i], state[SYY, i], state[SXY, i], p[P_LAMBDA],
            p[P_MU])
    else:
        out[SXX:SXY + 1, i] = 0.0
    out[RHO, i] = density_rate(rhoi, lxx, lyy) if CONTINUITY else 0.0
    out[X, i] = vxi + p[P_EPS] * a[A_HX] if XSPH else vxi
    out[Y, i] = vyi + p[P_EPS] * a[A_HY] if XSPH else vyi


@njit(**PAIR_OPTIONS)
def momentum_pass(c, state, alive, x0, y0, perm, start, jlist, p, scaled, out):
    """Pass 2: the velocity rate (antisymmetric pair momentum sum, substrate, body force)."""
    s, box = p[P_SUPPORT], p[P_BOX]
    inv_s, inv_box = 1.0 / s, 1.0 / box
    for cl in prange(perm.size // LANES):
        base = cl * LANES
        buf = np.empty(7 * LANES)  # sums (rows 0, 1) and lane values (rows 2-6), as pass 1
        for m in range(LANES):
            buf[m] = 0.0
            buf[LANES + m] = 0.0
            buf[2 * LANES + m] = c[C_X, base + m]
            buf[3 * LANES + m] = c[C_Y, base + m]
            buf[4 * LANES + m] = scaled[0, base + m]
            buf[5 * LANES + m] = scaled[1, base + m]
            buf[6 * LANES + m] = scaled[2, base + m]
        for k in range(np.uint64(start[cl]), np.uint64(start[cl + 1])):
            j = jlist[k]
            xj, yj, mj = c[C_X, j], c[C_Y, j], c[C_M, j]
            sxxj, syyj, sxyj = scaled[0, j], scaled[1, j], scaled[2, j]
            for m in range(LANES):
                dx = minimum_image_inv(buf[2 * LANES + m] - xj, box, inv_box)
                dy = minimum_image_inv(buf[3 * LANES + m] - yj, box, inv_box)
                # g recomputed, not stored by pass 1 (a per-pair store costs more memory
                # traffic than the arithmetic)
                _, g = kernel_w_g(KERNEL, dx * dx + dy * dy, s, inv_s)
                f = mj * g
                gx = f * dx
                gy = f * dy
                txx = buf[4 * LANES + m] + sxxj
                tyy = buf[5 * LANES + m] + syyj
                txy = buf[6 * LANES + m] + sxyj
                buf[m] += txx * gx + txy * gy
                buf[LANES + m] += txy * gx + tyy * gy
        for m in range(LANES):
            i = perm[base + m]
            if i < 0 or not alive[i]:
                continue
            ax, ay = buf[m], buf[LANES + m]
            if SUBSTRATE:
                bx, by = substrate_acceleration(state[X, i] - x0[i], state[Y, i] - y0[i],
                                                state[RHO, i], p[P_MU], p[P_THICK])
                ax += bx
                ay += by
            if BODY_FORCE:
                ax += p[P_BODY]
                ay += p[P_BODY + 1]
            out[VX, i] = ax
            out[VY, i] = ay
