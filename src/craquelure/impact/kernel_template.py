"""Template of the compiled SPH kernels of the impact model (spec section 3).

:mod:`craquelure.impact.engine` copies this file into a generated module per effect set, with the
flags below replaced by the scene's constants, so numba compiles each effect set separately and
the branches of absent effects fold away (globals are compile-time constants in numba). The
generated file's name hashes this template and every fragment it calls, so ``cache=True`` is
never stale. Importing the template itself (all effects on) is only for linting and reading.

Dimension: ``DIM`` (2 or 3) is a generated constant like the effect flags. Positions and
velocities are separate arrays x, y, z and vx, vy, vz (z and vz are zeros in 2D, never read
there); the stress arrays hold ``NCOMP`` columns, (xx, yy, xy, zz) in 2D and (xx, yy, xy, zz,
xz, yz) in 3D. The z terms sit under ``if DIM == 3``, folded away in 2D.

Pair loops are gather-style over the CSR neighbour list (every pair in both rows, ``prange``
safe). Pair smoothing length h_ij = (h_i + h_j)/2, support 2 h_ij (cubic B-spline, kernel kind
``CUBIC`` with s = 2 h_ij); massless neighbours are skipped (m_j = 0 contributes nothing).
"""

import math

import numpy as np
from numba import njit, prange

from craquelure.codegen import param_indices
from craquelure.impact.effects.artificial_stress import artificial_stress_tensor
from craquelure.impact.effects.artificial_viscosity import monaghan_pi
from craquelure.impact.effects.cap_plasticity import cap_return
from craquelure.impact.effects.compressive_damage import ductile_damage
from craquelure.impact.effects.contact_bulk import bulk_penalty
from craquelure.impact.effects.contact_mass import mass_penalty
from craquelure.impact.effects.damage import damage_update
from craquelure.impact.effects.elasticity import jaumann_trial, secant_energy_density
from craquelure.impact.effects.plasticity import dp_return
from craquelure.impact.effects.rate_effects import (
    increase_factor,
    softening_left,
    strain_rate,
    viscoplastic,
)
from craquelure.impact.effects.variable_smoothing_length import benz_update
from craquelure.periodic import minimum_image
from craquelure.registry import parameter_names
from craquelure.sph.kernels import CUBIC, kernel_dwdr, kernel_w

# BEGIN FLAGS
ELASTICITY = True
PLASTICITY = True
CAP_PLASTICITY = False
COMPRESSIVE_DAMAGE = False
RATE_EFFECTS = False
DAMAGE = True
ARTIFICIAL_VISCOSITY = True
ARTIFICIAL_STRESS = True
VARIABLE_SMOOTHING_LENGTH = True
CONTACT_BULK = True
CONTACT_MASS = False
PERIODIC = False
PLANE_STRESS = False
DIM = 2
# END FLAGS
KIND = CUBIC
NCOMP = 4 if DIM == 2 else 6  # stored stress components

# the parameter vector, as the effects declare it (craquelure.registry); the engine packs it
PARAMS = parameter_names("impact")
N_PARAMS = len(PARAMS)
P_BULK, P_SHEAR, P_YOUNG, P_ALPHA_DP, P_K_DP, P_EPS_0, P_EPS_F = param_indices(
    PARAMS, "bulk", "shear", "young", "alpha_dp", "k_dp", "eps_0", "eps_f")
P_C, P_AV_ALPHA, P_AV_BETA, P_AS_EPS, P_AS_N, P_SPACING = param_indices(
    PARAMS, "wave_speed", "av_alpha", "av_beta", "as_epsilon", "as_n", "spacing")
P_H_MIN, P_H_MAX, P_BASE, P_RC, P_CONTACT_A, P_K_BULK, P_KIN_RATIO = param_indices(
    PARAMS, "h_min", "h_max", "base_y", "contact_radius", "contact_a", "k_bulk", "kinematic_ratio")
P_LX, P_LY, P_LZ = param_indices(PARAMS, "lx", "ly", "lz")
P_CAP = PARAMS.index("cap")  # Concrete.cap_vector(), contiguous from P_CAP
P_RATE = P_CAP + 10  # its rate constants (rate_effects.RATE_PARAMS), then f_t, f_c, κ0, R
P_FLUSH = PARAMS.index("flush_below")


@njit(inline="always", cache=True)
def flushed(v, tiny):
    """v, or 0 where |v| < tiny (NaN passes, so divergence is still detected).

    Why: ahead of a wave front the explicit scheme spreads a precursor that shrinks by orders of
    magnitude per hop, down to subnormal numbers, whose arithmetic made steps up to 40 % slower;
    ``prm[P_FLUSH]`` (1e-100 SI) lies a hundred orders below round-off of any resolved value."""
    return 0.0 if abs(v) < tiny else v


@njit(inline="always", cache=True)
def pair_vector(x, y, z, i, j, prm):
    dx = x[i] - x[j]
    dy = y[i] - y[j]
    dz = 0.0
    if DIM == 3:
        dz = z[i] - z[j]
    if PERIODIC:
        dx = minimum_image(dx, prm[P_LX])
        dy = minimum_image(dy, prm[P_LY])
        if DIM == 3:
            dz = minimum_image(dz, prm[P_LZ])
    return dx, dy, dz


@njit(inline="always", cache=True)
def stress_of(a, i):
    """Row i of a stress array as (xx, yy, xy, zz, xz, yz) (xz = yz = 0 in 2D)."""
    if DIM == 3:
        return a[i, 0], a[i, 1], a[i, 2], a[i, 3], a[i, 4], a[i, 5]
    return a[i, 0], a[i, 1], a[i, 2], a[i, 3], 0.0, 0.0


@njit(inline="always", cache=True)
def store_stress(a, i, s, tiny):
    """Row i of a stress array from (xx, yy, xy, zz, xz, yz), flushed below ``tiny``."""
    for c in range(NCOMP):
        a[i, c] = flushed(s[c], tiny)


@njit(inline="always", cache=True)
def plane_stress_dzz(sxx, syy, sxy, szz, epsv, epsp, dxx, dyy, dxy, w, dt, prm):
    """Plane stress (``domain.plane: stress``): the out-of-plane strain rate D_zz that leaves
    σ_zz = 0 after the Jaumann trial and, with plasticity, after the Drucker-Prager return.
    Elastic: D_zz = −(λ(D_xx + D_yy) + σ_zz/Δt)/(λ + 2G), exact. Plastic: the return maps the
    trial's σ_zz to g(D_zz), piecewise smooth and increasing; secant iterations from the elastic
    value until |g| < 1e-9 (|σ| + k_DP) (at most 30)."""
    bulk, shear = prm[P_BULK], prm[P_SHEAR]
    lam = bulk - 2.0 * shear / 3.0
    d0 = -(lam * (dxx + dyy) + szz / dt) / (lam + 2.0 * shear)
    if not (PLASTICITY or CAP_PLASTICITY):
        return d0
    tol = 1e-9 * (abs(sxx) + abs(syy) + abs(sxy) + prm[P_K_DP])
    g0 = _returned_szz(d0, sxx, syy, sxy, szz, epsv, epsp, dxx, dyy, dxy, w, dt, prm)
    if abs(g0) <= tol:
        return d0
    # second point from the elastic slope (λ + 2G)Δt, then secant steps
    d1 = d0 - g0 / ((lam + 2.0 * shear) * dt)
    g1 = _returned_szz(d1, sxx, syy, sxy, szz, epsv, epsp, dxx, dyy, dxy, w, dt, prm)
    for _ in range(30):
        if abs(g1) <= tol or g1 == g0:
            break
        d0, g0, d1 = d1, g1, d1 - g1 * (d1 - d0) / (g1 - g0)
        g1 = _returned_szz(d1, sxx, syy, sxy, szz, epsv, epsp, dxx, dyy, dxy, w, dt, prm)
    return d1


@njit(inline="always", cache=True)
def _returned_szz(dzz, sxx, syy, sxy, szz, epsv, epsp, dxx, dyy, dxy, w, dt, prm):
    """σ_zz after the Jaumann trial with out-of-plane rate ``dzz`` and the DP return."""
    d = (dxx, dyy, dxy, dzz, 0.0, 0.0)
    trial = jaumann_trial((sxx, syy, sxy, szz, 0.0, 0.0), d, (w, 0.0, 0.0), prm[P_BULK],
                          prm[P_SHEAR], dt)
    if CAP_PLASTICITY:
        return plastic_return(trial, epsv, epsp, d, prm)[0][3]
    return dp_return(trial, prm[P_ALPHA_DP], prm[P_K_DP], prm[P_SHEAR])[0][3]


@njit(inline="always", cache=True)
def plastic_return(s, epsv, epsp, d, prm):
    """Cap model return (CAP_PLASTICITY) of the trial stress s, with the compressive damage
    when that effect is on; returns (stress, d_eps_v, d_eps_p, work)."""
    c = P_CAP
    strength = 1.0
    if COMPRESSIVE_DAMAGE:
        strength = 1.0 - ductile_damage(epsp, prm[c + 9])
    return cap_return(s, epsv, prm[c], prm[c + 1], prm[c + 2], prm[c + 3],
                      prm[c + 4], prm[c + 5], prm[c + 6], prm[c + 7], prm[c + 8],
                      prm[c + 20], prm[c + 21], prm[P_BULK], prm[P_SHEAR], strength)


@njit(parallel=True, cache=True)
def material_pass(x, y, z, vx, vy, vz, m, rho, h, h0, sig, nom, eps_max, dmg, epsp, wp, epsv, eint,
                  eel, wd, offsets, index, dt, prm):
    """Velocity gradient with the mid-step velocities, then per particle: ρ and h (exact
    exponential update), Jaumann trial → DP return → damage → nominal stress; stress power
    (trapezoidal in the nominal stress) accumulated into the specific internal energy; the
    damage dissipation per unit mass ``wd`` is the energy the damage growth releases at the
    step's effective stress, (D_new − D_old) ½ P₊σ̃ : C⁻¹σ̃ (P₊σ̃ the tensile principal part,
    = (σ̃ − σ)/D_new): the secant energy lost, booked by its own law. The pair sums read ρ and h
    of the step's start (copies), so the in-place update does not depend on particle order or
    thread timing."""
    n = x.size
    rho_start = rho.copy()
    h_start = h.copy()
    for i in prange(n):
        lxx = lxy = lyx = lyy = lxz = lyz = lzx = lzy = lzz = 0.0
        for p in range(offsets[i], offsets[i + 1]):
            j = index[p]
            if m[j] == 0.0:
                continue
            dx, dy, dz = pair_vector(x, y, z, i, j, prm)
            r = math.sqrt(dx * dx + dy * dy + dz * dz)
            sup = h_start[i] + h_start[j]  # support 2 h_ij
            if r >= sup or r == 0.0:
                continue
            dw = kernel_dwdr(KIND, r, sup, DIM) / r
            vol = m[j] / rho_start[j]
            dvx = vx[j] - vx[i]
            dvy = vy[j] - vy[i]
            lxx += vol * dvx * dw * dx
            lxy += vol * dvx * dw * dy
            lyx += vol * dvy * dw * dx
            lyy += vol * dvy * dw * dy
            if DIM == 3:
                dvz = vz[j] - vz[i]
                lxz += vol * dvx * dw * dz
                lyz += vol * dvy * dw * dz
                lzx += vol * dvz * dw * dx
                lzy += vol * dvz * dw * dy
                lzz += vol * dvz * dw * dz
        tr = lxx + lyy
        if DIM == 3:
            tr += lzz
        rho_old = rho[i]
        rho[i] = rho_old * math.exp(-tr * dt)
        if VARIABLE_SMOOTHING_LENGTH:
            h[i] = benz_update(h[i], h0[i], tr, dt, DIM, prm[P_H_MIN], prm[P_H_MAX])
        dxy = 0.5 * (lxy + lyx)
        w = (0.5 * (lxy - lyx), 0.5 * (lxz - lzx), 0.5 * (lyz - lzy))
        old = stress_of(nom, i)
        s = stress_of(sig, i)
        dzz = lzz
        if PLANE_STRESS:
            dzz = plane_stress_dzz(s[0], s[1], s[2], s[3], epsv[i], epsp[i], lxx, lyy, dxy,
                                   w[0], dt, prm)
        d = (lxx, lyy, dxy, dzz, 0.5 * (lxz + lzx), 0.5 * (lyz + lzy))
        if ELASTICITY:
            s = jaumann_trial(s, d, w, prm[P_BULK], prm[P_SHEAR], dt)
        if PLASTICITY:
            s, deps, work = dp_return(s, prm[P_ALPHA_DP], prm[P_K_DP], prm[P_SHEAR])
            epsp[i] += deps
            wp[i] += work / rho[i]
        if CAP_PLASTICITY:
            s, dv, deps, work = plastic_return(s, epsv[i], epsp[i], d, prm)
            epsp[i] += deps
            epsv[i] += dv
            wp[i] += work / rho[i]
        if PLANE_STRESS:
            s = (s[0], s[1], s[2], 0.0, 0.0, 0.0)  # removes the solve's round-off residual
        tiny = prm[P_FLUSH]
        store_stress(sig, i, s, tiny)
        s = stress_of(sig, i)
        nominal = s
        rate = strain_rate(d) if RATE_EFFECTS else 0.0
        eps_f = prm[P_EPS_F]
        dif_t = 1.0
        if RATE_EFFECTS:
            q = P_RATE
            dif_t = increase_factor(rate, prm[P_YOUNG], prm[q], prm[q + 1], prm[q + 4],
                                     prm[q + 8])
        if DAMAGE:
            d_min = 0.0
            if RATE_EFFECTS:
                eps_f *= dif_t ** (prm[q + 7] - 1.0)  # G_F DIF_t^REPOW with the overstress
                d_min = dmg[i]
            k, dmg_i, nominal = damage_update(s, eps_max[i], prm[P_YOUNG], prm[P_EPS_0], eps_f,
                                              d_min)
            eps_max[i] = k
            if dmg_i > dmg[i]:
                grow = (dmg_i - dmg[i]) / dmg_i
                tensile = (s[0] - nominal[0], s[1] - nominal[1], s[2] - nominal[2],
                           s[3] - nominal[3], s[4] - nominal[4], s[5] - nominal[5])
                wd[i] += grow * secant_energy_density(tensile, s, prm[P_BULK],
                                                      prm[P_SHEAR]) / rho[i]
            dmg[i] = dmg_i
        if RATE_EFFECTS:
            q = P_RATE
            intact = softening_left(eps_max[i], prm[P_EPS_0], eps_f, dif_t) if DAMAGE else 1.0
            nominal = viscoplastic(jaumann_trial(old, d, w, prm[P_BULK], prm[P_SHEAR], dt),
                                   nominal, rate, dt, prm[q], prm[q + 1], prm[q + 2],
                                   prm[q + 3], prm[q + 4], prm[q + 5], prm[q + 6],
                                   prm[P_YOUNG], intact)
        store_stress(nom, i, nominal, tiny if DAMAGE or RATE_EFFECTS else 0.0)
        new = stress_of(nom, i)
        power = ((old[0] + new[0]) * lxx + (old[1] + new[1]) * lyy
                 + 2.0 * (old[2] + new[2]) * dxy)
        if DIM == 3:
            power += ((old[3] + new[3]) * lzz + 2.0 * (old[4] + new[4]) * d[4]
                      + 2.0 * (old[5] + new[5]) * d[5])
        eint[i] += 0.5 * dt * power * 2.0 / (rho_old + rho[i])
        if ELASTICITY:  # recoverable energy of the secant (damaged) point: ½ σ : C⁻¹σ̃
            eel[i] = secant_energy_density(new, s, prm[P_BULK], prm[P_SHEAR]) / rho[i]


@njit(parallel=True, cache=True)
def force_pass(x, y, z, vx, vy, vz, m, rho, h, nom, rst, offsets, index, prm, ax, ay, az, pav,
               pas, mumax):
    """Accelerations from the pair bracket σ_i/ρ_i² + σ_j/ρ_j² − Π_ij 1 + f^n (R_i + R_j);
    per-particle AV and artificial-stress powers (per unit mass of i, symmetric halves) and
    max |μ_ij| for the time step."""
    n = x.size
    for i in prange(n):
        axi = ayi = azi = pa = ps = mu_max = 0.0
        ri2 = 1.0 / (rho[i] * rho[i])
        ixx, iyy, ixy = nom[i, 0] * ri2, nom[i, 1] * ri2, nom[i, 2] * ri2
        izz = ixz = iyz = 0.0
        if DIM == 3:
            izz, ixz, iyz = nom[i, 3] * ri2, nom[i, 4] * ri2, nom[i, 5] * ri2
        for p in range(offsets[i], offsets[i + 1]):
            j = index[p]
            if m[j] == 0.0:
                continue
            dx, dy, dz = pair_vector(x, y, z, i, j, prm)
            r2 = dx * dx + dy * dy + dz * dz
            r = math.sqrt(r2)
            s = h[i] + h[j]
            if r >= s or r == 0.0:
                continue
            dw = kernel_dwdr(KIND, r, s, DIM) / r
            gx = dw * dx
            gy = dw * dy
            gz = dw * dz
            rj2 = 1.0 / (rho[j] * rho[j])
            bxx = ixx + nom[j, 0] * rj2
            byy = iyy + nom[j, 1] * rj2
            bxy = ixy + nom[j, 2] * rj2
            bzz = bxz = byz = 0.0
            if DIM == 3:
                bzz = izz + nom[j, 3] * rj2
                bxz = ixz + nom[j, 4] * rj2
                byz = iyz + nom[j, 5] * rj2
            dvx = vx[i] - vx[j]
            dvy = vy[i] - vy[j]
            dvz = 0.0
            vg = dvx * gx + dvy * gy
            vdotr = dvx * dx + dvy * dy
            if DIM == 3:
                dvz = vz[i] - vz[j]
                vg += dvz * gz
                vdotr += dvz * dz
            if ARTIFICIAL_VISCOSITY:
                pi, mu = monaghan_pi(vdotr, r2, 0.5 * s, 0.5 * (rho[i] + rho[j]),
                                     prm[P_C], prm[P_AV_ALPHA], prm[P_AV_BETA])
                bxx -= pi
                byy -= pi
                bzz -= pi
                pa += 0.5 * m[j] * pi * vg
                if -mu > mu_max:
                    mu_max = -mu
            if ARTIFICIAL_STRESS:
                wd = kernel_w(KIND, prm[P_SPACING], s, DIM)
                fn = 0.0
                if wd > 0.0:
                    f = kernel_w(KIND, r, s, DIM) / wd
                    if prm[P_AS_N] == 4.0:
                        f2 = f * f
                        fn = f2 * f2
                    else:
                        fn = f ** prm[P_AS_N]
                cxx = fn * (rst[i, 0] + rst[j, 0])
                cyy = fn * (rst[i, 1] + rst[j, 1])
                cxy = fn * (rst[i, 2] + rst[j, 2])
                bxx += cxx
                byy += cyy
                bxy += cxy
                work = dvx * (cxx * gx + cxy * gy) + dvy * (cxy * gx + cyy * gy)
                if DIM == 3:
                    czz = fn * (rst[i, 3] + rst[j, 3])
                    cxz = fn * (rst[i, 4] + rst[j, 4])
                    cyz = fn * (rst[i, 5] + rst[j, 5])
                    bzz += czz
                    bxz += cxz
                    byz += cyz
                    work += (dvx * cxz * gz + dvy * cyz * gz
                             + dvz * (cxz * gx + cyz * gy + czz * gz))
                ps -= 0.5 * m[j] * work
            if DIM == 3:
                axi += m[j] * (bxx * gx + bxy * gy + bxz * gz)
                ayi += m[j] * (bxy * gx + byy * gy + byz * gz)
                azi += m[j] * (bxz * gx + byz * gy + bzz * gz)
            else:
                axi += m[j] * (bxx * gx + bxy * gy)
                ayi += m[j] * (bxy * gx + byy * gy)
        tiny = prm[P_FLUSH]
        ax[i] = flushed(axi, tiny)
        ay[i] = flushed(ayi, tiny)
        az[i] = flushed(azi, tiny)
        pav[i] = flushed(pa, tiny)
        pas[i] = flushed(ps, tiny)
        mumax[i] = mu_max


@njit(parallel=True, cache=True)
def artificial_stress_pass(nom, rho, prm, rst):
    """R_i of every particle: (xx, yy, xy) in 2D, (xx, yy, xy, zz, xz, yz) in 3D (per particle,
    so threads do not change it)."""
    for i in prange(rho.size):
        if ARTIFICIAL_STRESS:
            r = artificial_stress_tensor(stress_of(nom, i), rho[i], prm[P_AS_EPS])
            for c in range(rst.shape[1]):
                rst[i, c] = r[c]


@njit(cache=True)
def contact_pass(y, m, ay, dt, prm, kinematic):
    """Penalty forces of the rigid base (added to ay); returns (total force, penalty energy).
    ``kinematic[i]`` marks particles left to the kinematic constraint (bulk contact)."""
    force = energy = 0.0
    limit = prm[P_BASE] + prm[P_RC]
    for i in range(y.size):
        kinematic[i] = False
        gap = limit - y[i]
        if gap <= 0.0:
            continue
        if CONTACT_BULK:
            f, e, kin = bulk_penalty(gap, m[i], prm[P_K_BULK], dt, prm[P_KIN_RATIO])
            kinematic[i] = kin
        elif CONTACT_MASS:
            f, e = mass_penalty(gap, m[i], prm[P_CONTACT_A], dt)
        else:
            f, e = 0.0, 0.0
        if f != 0.0:
            ay[i] += f / m[i]
        force += f
        energy += e
    return force, energy


@njit(cache=True)
def kinematic_position(y, kinematic, prm):
    """Kinematic fallback after the drift: y <- max(y, r_c - 0.05 Δ)."""
    floor = prm[P_BASE] + prm[P_RC] - 0.05 * prm[P_SPACING]
    for i in range(y.size):
        if kinematic[i] and y[i] < floor:
            y[i] = floor


@njit(cache=True)
def kinematic_velocity(y, vy, m, kinematic, prm, arrival):
    """Kinematic fallback, v_y <- max(v_y, 0) for constrained particles in contact; returns
    (momentum given to the base, kinetic energy removed): before a kick with ``arrival`` (an
    inelastic stop), after it without (the base's reaction does no work)."""
    mom = ke = 0.0
    limit = prm[P_BASE] + prm[P_RC]
    for i in range(y.size):
        if kinematic[i] and y[i] < limit and vy[i] < 0.0:
            mom += m[i] * (-vy[i])
            if arrival:
                ke += 0.5 * m[i] * vy[i] * vy[i]
            vy[i] = 0.0
    return mom, ke


@njit(cache=True)
def time_step(h, vx, vy, vz, mumax, prm, cfl):
    """Δt = cfl min_i h_i / (c + |v_i| + 1.2 (α c + β max_j |μ_ij|))."""
    best = np.inf
    c = prm[P_C]
    for i in range(h.size):
        v2 = vx[i] * vx[i] + vy[i] * vy[i]
        if DIM == 3:
            v2 += vz[i] * vz[i]
        speed = c + math.sqrt(v2)
        if ARTIFICIAL_VISCOSITY:
            speed += 1.2 * (prm[P_AV_ALPHA] * c + prm[P_AV_BETA] * mumax[i])
        t = cfl * h[i] / speed
        if t < best:
            best = t
    return best
