r"""Right-hand side of Soft Dynamics (spec section 5), written once and specialised per effect set.

:func:`craquelure.codegen.specialise` compiles a copy with the flag block below set to the
scene's effect set; for runs ask ``engine.kernels(flags)``, do not import this module.

State ``y = (x - x0 (N,d), s (P) [hertz], q (P,d) [hertz + lubrication_tangential])``: the
centres are stored as displacements from the initial positions x0, so the solver's relative
tolerance acts on the motion (small on a blocked plateau), not on |x| ~ R; pairs ``(i, j)``
from ``pi, pj``; ``F0`` the nominal external forces (N,d) ramped as ``F0 min(t/t_r, 1)``;
``p`` the parameter vector in the order of :data:`PARAMS`.

Velocities (soft spheres): differentiating the particle balance :math:`F_i + \sum_j f_{ij} = 0`
with :math:`\dot f_{ij} = A_{ij}(v_i - v_j) + b_{ij}` (closed forms in the spec, section 5, and
in :func:`pair_terms`) and adding Baumgarte drift control,

.. math:: \sum_j A_{ij}(v_i - v_j) = -\dot F_i - \sum_j b_{ij} - (F_i + \sum_j f_{ij})/\tau_B,

with the last particle's equation replaced by :math:`\sum_i v_i = 0` (rows scaled to the block
magnitude). Rigid spheres (no ``hertz``): :math:`f_{ij} = -Z_{ij}(v_i - v_j)`, so
:math:`\sum_j Z_{ij}(v_i - v_j) = F_i`. Literal deflection rule: ``A`` gains
:math:`(E R (1 + \mathrm{sgn}\,s)/(2 a r))\, g q^T + E a (k_n n q^T - k_t s Q)/r`
with :math:`g = k_n s n + k_t q` (b unchanged).
"""

import math

import numpy as np
from numba import njit

from craquelure.codegen import param_indices
from craquelure.registry import parameter_names
from craquelure.softdyn.effects.hertz import interaction_radius2, sign
from craquelure.softdyn.effects.lubrication_normal import zeta_normal
from craquelure.softdyn.effects.lubrication_tangential import zeta_tangential

# BEGIN FLAGS
LUBRICATION_TANGENTIAL = True
HERTZ = True
LITERAL_DEFLECTION = False
# END FLAGS

# the parameter vector, as the effects declare it (craquelure.registry); the engine packs it
PARAMS = parameter_names("softdyn")
R_, ETA, E_, K_N, K_T, C_N, C_T, INV_TAU_B, T_R = param_indices(
    PARAMS, "R", "eta", "E", "k_n", "k_t", "c_n", "c_t", "inv_tau_B", "t_r")


@njit(cache=True)
def unpack(y, x0, n_pair):
    """The state as (x (N,d), s (P), q (P,d)); absent parts are zeros."""
    n_part, d = x0.shape
    x = y[: n_part * d].copy().reshape((n_part, d)) + x0
    s = np.zeros(n_pair)
    q = np.zeros((n_pair, d))
    off = n_part * d
    if HERTZ:
        s = y[off: off + n_pair].copy()
        off += n_pair
        if LUBRICATION_TANGENTIAL:
            q = y[off: off + n_pair * d].copy().reshape((n_pair, d))
    return x, s, q


@njit(cache=True)
def load_factors(t, t_r):
    """(ramp, d ramp/dt) of the linear load ramp over t_r."""
    if t_r <= 0.0:
        return 1.0, 0.0
    if t < t_r:
        return t / t_r, 1.0 / t_r
    return 1.0, 0.0


@njit(cache=True)
def pair_terms(x, s, q, pi, pj, p):
    """Per pair: unit normal n (P,d), distance r, gap h, a, zeta_n, zeta_t, elastic force f (P,d),
    and the affine velocity response A (P,d,d), b (P,d) of df/dt (rigid: A = Z, b = 0, f = 0)."""
    R, eta, E, kn, kt, cn, ct = p[R_], p[ETA], p[E_], p[K_N], p[K_T], p[C_N], p[C_T]
    n_pair, d = pi.shape[0], x.shape[1]
    nv = np.empty((n_pair, d))
    r = np.empty(n_pair)
    h = np.empty(n_pair)
    a = np.empty(n_pair)
    zn = np.empty(n_pair)
    zt = np.zeros(n_pair)
    f = np.zeros((n_pair, d))
    A = np.zeros((n_pair, d, d))
    b = np.zeros((n_pair, d))
    g = np.empty(d)
    for k in range(n_pair):
        i, j = pi[k], pj[k]
        r2 = 0.0
        for c in range(d):
            nv[k, c] = x[i, c] - x[j, c]
            r2 += nv[k, c] * nv[k, c]
        rk = math.sqrt(r2)
        for c in range(d):
            nv[k, c] /= rk
        r[k] = rk
        sk = s[k]
        hk = rk - 2.0 * R + sk
        h[k] = hk
        if HERTZ:
            a2 = interaction_radius2(R, hk, sk)
        else:
            a2 = R * hk
        ak = math.sqrt(a2)
        a[k] = ak
        znk = zeta_normal(eta, cn, a2, hk)
        zn[k] = znk
        ztk = 0.0
        if LUBRICATION_TANGENTIAL:
            ztk = zeta_tangential(eta, ct, a2, hk)
            zt[k] = ztk
        if HERTZ:
            # g = k_n s n + k_t q ; f = E a g ; f_n = E a k_n s ; f_t = E a k_t q
            for c in range(d):
                g[c] = kn * sk * nv[k, c]
                if LUBRICATION_TANGENTIAL:
                    g[c] += kt * q[k, c]
                f[k, c] = E * ak * g[c]
            sg = sign(sk)
            rate_n = E * ak * kn * sk / znk  # f_n / zeta_n
            adot0 = -(R / (2.0 * ak)) * (1.0 + sg) * rate_n
            for c in range(d):
                b[k, c] = E * adot0 * g[c] - E * ak * kn * rate_n * nv[k, c]
                if LUBRICATION_TANGENTIAL:
                    b[k, c] -= E * ak * kt * (E * ak * kt * q[k, c] / ztk)
            for c in range(d):
                for e in range(d):
                    nn = nv[k, c] * nv[k, e]
                    qq = (1.0 if c == e else 0.0) - nn
                    val = -E * ak * kn * nn + E * ak * kn * (sk / rk) * qq
                    val -= (E * R * sg / (2.0 * ak)) * g[c] * nv[k, e]
                    if LUBRICATION_TANGENTIAL:
                        val -= E * ak * kt * qq
                        val -= E * ak * kt * nv[k, c] * q[k, e] / rk
                        if LITERAL_DEFLECTION:
                            val += (E * R * (1.0 + sg) / (2.0 * ak * rk)) * g[c] * q[k, e]
                            val += E * ak * (kn * nv[k, c] * q[k, e] - kt * sk * qq) / rk
                    A[k, c, e] = val
        else:
            for c in range(d):
                for e in range(d):
                    nn = nv[k, c] * nv[k, e]
                    val = znk * nn
                    if LUBRICATION_TANGENTIAL:
                        val += ztk * ((1.0 if c == e else 0.0) - nn)
                    A[k, c, e] = val
    return nv, r, h, a, zn, zt, f, A, b


@njit(cache=True)
def particle_terms(t, pi, pj, F0, p, f, b):
    """Right-hand side c (N,d) of the velocity system and the balance residual
    F_i + sum_j f_ij (N,d) (rigid spheres: c = F, residual from the solved velocities)."""
    n_part, d = F0.shape
    ramp, dramp = load_factors(t, p[T_R])
    c = np.zeros((n_part, d))
    resid = np.zeros((n_part, d))
    for i in range(n_part):
        for e in range(d):
            resid[i, e] = ramp * F0[i, e]
    if not HERTZ:
        for i in range(n_part):
            for e in range(d):
                c[i, e] = ramp * F0[i, e]
        return c, resid
    for k in range(pi.shape[0]):
        i, j = pi[k], pj[k]
        for e in range(d):
            resid[i, e] += f[k, e]
            resid[j, e] -= f[k, e]
            c[i, e] -= b[k, e]
            c[j, e] += b[k, e]
    inv_tb = p[INV_TAU_B]
    for i in range(n_part):
        for e in range(d):
            c[i, e] -= dramp * F0[i, e] + inv_tb * resid[i, e]
    return c, resid


@njit(cache=True)
def assemble_dense(pi, pj, A, c):
    """Dense (N d)^2 velocity matrix and right-hand side, last particle's rows -> sum v = 0."""
    n_part, d = c.shape
    m = n_part * d
    M = np.zeros((m, m))
    for k in range(pi.shape[0]):
        i, j = pi[k], pj[k]
        for e in range(d):
            for g in range(d):
                val = A[k, e, g]
                M[i * d + e, i * d + g] += val
                M[i * d + e, j * d + g] -= val
                M[j * d + e, j * d + g] += val
                M[j * d + e, i * d + g] -= val
    rhs = c.copy().reshape(m)
    scale = 0.0
    for k in range(m):
        scale = max(scale, abs(M[k, k]))
    if scale == 0.0:
        scale = 1.0
    last = n_part - 1
    for e in range(d):
        row = last * d + e
        for col in range(m):
            M[row, col] = 0.0
        for i in range(n_part):
            M[row, i * d + e] = scale
        rhs[row] = 0.0
    return M, rhs


@njit(cache=True)
def solve_dense(M, rhs):
    if LUBRICATION_TANGENTIAL:
        return np.linalg.solve(M, rhs)
    return np.linalg.lstsq(M, rhs)[0]


@njit(cache=True)
def rates(v, pi, pj, nv, r, a, zn, zt, s, q, p, n_part, d):
    """dy/dt from the particle velocities v (N d): x' = v and the deflection rule."""
    E, kn, kt = p[E_], p[K_N], p[K_T]
    n_pair = pi.shape[0]
    size = n_part * d
    if HERTZ:
        size += n_pair
        if LUBRICATION_TANGENTIAL:
            size += n_pair * d
    ydot = np.zeros(size)
    ydot[: n_part * d] = v
    if not HERTZ:
        return ydot
    off_s = n_part * d
    off_q = off_s + n_pair
    vij = np.empty(d)
    for k in range(n_pair):
        i, j = pi[k], pj[k]
        vn = qv = 0.0
        for e in range(d):
            vij[e] = v[i * d + e] - v[j * d + e]
            vn += nv[k, e] * vij[e]
            qv += q[k, e] * vij[e]
        sdot = -vn - E * a[k] * kn * s[k] / zn[k]
        if LITERAL_DEFLECTION:
            sdot += qv / r[k]
        ydot[off_s + k] = sdot
        if LUBRICATION_TANGENTIAL:
            for e in range(d):
                tang = vij[e] - vn * nv[k, e]
                val = -tang - E * a[k] * kt * q[k, e] / zt[k] - nv[k, e] * qv / r[k]
                if LITERAL_DEFLECTION:
                    val -= s[k] * tang / r[k]
                ydot[off_q + k * d + e] = val
    return ydot


@njit(cache=True)
def rigid_forces(v, pi, pj, A, d):
    """Rigid spheres: f_ij = -Z_ij (v_i - v_j)."""
    n_pair = pi.shape[0]
    f = np.zeros((n_pair, d))
    for k in range(n_pair):
        i, j = pi[k], pj[k]
        for e in range(d):
            for g in range(d):
                f[k, e] -= A[k, e, g] * (v[i * d + g] - v[j * d + g])
    return f


@njit(cache=True)
def rhs_dense(t, y, x0, pi, pj, F0, p):
    """dy/dt with the dense velocity solve (small N)."""
    n_part, d = F0.shape
    n_pair = pi.shape[0]
    x, s, q = unpack(y, x0, n_pair)
    nv, r, h, a, zn, zt, f, A, b = pair_terms(x, s, q, pi, pj, p)
    c, resid = particle_terms(t, pi, pj, F0, p, f, b)
    M, rhs = assemble_dense(pi, pj, A, c)
    v = solve_dense(M, rhs)
    return rates(v, pi, pj, nv, r, a, zn, zt, s, q, p, n_part, d)


@njit(cache=True)
def min_gap(y, x0, pi, pj, radius):
    """Smallest surface gap h = r - 2R + s over the pairs (cheap guard)."""
    n_part, d = x0.shape
    out = np.inf
    off = n_part * d
    for k in range(pi.shape[0]):
        i, j = pi[k], pj[k]
        r2 = 0.0
        for e in range(d):
            dx = y[i * d + e] + x0[i, e] - y[j * d + e] - x0[j, e]
            r2 += dx * dx
        hk = math.sqrt(r2) - 2.0 * radius
        if HERTZ:
            hk += y[off + k]
        out = min(out, hk)
    return out
