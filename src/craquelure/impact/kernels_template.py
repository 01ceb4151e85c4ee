"""Template of the compiled SPH kernels of the impact model (spec section 3).

:mod:`craquelure.impact.engine` copies this file into a generated module per effect set, with the
flags below replaced by the scene's constants, so numba compiles each effect set separately and
the branches of absent effects fold away (globals are compile-time constants in numba). The
generated file's name hashes this template and every fragment it calls, so ``cache=True`` is
never stale. Importing the template itself (all effects on) is only for linting and reading.

Pair loops are gather-style over the CSR neighbour list (every pair in both rows, ``prange``
safe). Pair smoothing length h_ij = (h_i + h_j)/2, support 2 h_ij (cubic B-spline, kernel kind
``CUBIC`` with s = 2 h_ij); massless neighbours are skipped (m_j = 0 contributes nothing).
"""

import math

import numpy as np
from numba import njit, prange

from craquelure.impact.effects.artificial_stress import artificial_stress_tensor
from craquelure.impact.effects.artificial_viscosity import monaghan_pi
from craquelure.impact.effects.cap_plasticity import cap_return
from craquelure.impact.effects.compressive_damage import ductile_damage
from craquelure.impact.effects.contact_bulk import bulk_penalty
from craquelure.impact.effects.contact_mass import mass_penalty
from craquelure.impact.effects.damage import damage_update
from craquelure.impact.effects.elasticity import elastic_energy_density, jaumann_trial
from craquelure.impact.effects.plasticity import dp_return
from craquelure.impact.effects.rate_effects import increase_factor, principal_rates
from craquelure.impact.effects.variable_smoothing_length import benz_update
from craquelure.periodic import minimum_image
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
# END FLAGS
DIM = 2
KIND = CUBIC

# the parameter vector: names in order, declared once (the engine packs by name)
PARAMS = ("bulk", "shear", "young", "alpha_dp", "k_dp", "kappa0", "kappa_f", "wave_speed",
          "av_alpha", "av_beta", "as_epsilon", "as_n", "spacing", "h_min", "h_max", "base_y",
          "contact_radius", "contact_a", "k_bulk", "kinematic_ratio", "lx", "ly", "flush_below",
          # cap model (Concrete.cap_vector order; contiguous from P_CAP)
          "cap_alpha", "cap_lambda", "cap_beta", "cap_theta", "cap_e", "cap_x0", "cap_w",
          "cap_d1", "cap_d2", "eps_fc", "eta0_t", "n_t", "eta0_c", "n_c", "overt", "overc",
          "f_t", "f_c")
N_PARAMS = len(PARAMS)
_index = PARAMS.index
P_BULK, P_SHEAR, P_YOUNG, P_ALPHA_DP, P_K_DP, P_KAPPA0, P_KAPPA_F = (
    _index("bulk"), _index("shear"), _index("young"), _index("alpha_dp"), _index("k_dp"),
    _index("kappa0"), _index("kappa_f"),
)
P_C, P_AV_ALPHA, P_AV_BETA, P_AS_EPS, P_AS_N, P_SPACING = (
    _index("wave_speed"), _index("av_alpha"), _index("av_beta"), _index("as_epsilon"),
    _index("as_n"), _index("spacing"),
)
P_H_MIN, P_H_MAX, P_BASE, P_RC, P_CONTACT_A, P_K_BULK, P_KIN_RATIO = (
    _index("h_min"), _index("h_max"), _index("base_y"), _index("contact_radius"),
    _index("contact_a"), _index("k_bulk"), _index("kinematic_ratio"),
)
P_LX, P_LY = _index("lx"), _index("ly")
P_CAP = _index("cap_alpha")
CAP_PARAMS = PARAMS[P_CAP:P_CAP + 18]
P_FLUSH = _index("flush_below")


@njit(inline="always", cache=True)
def flushed(v, tiny):
    """v, or 0 where |v| < tiny (NaN passes, so divergence is still detected).

    Why: ahead of a wave front the explicit scheme spreads a precursor two supports per step
    that shrinks by orders of magnitude per hop; after a few hundred steps its accelerations,
    stresses and their squares (energy densities, pair powers) fall below 2.2e-308, and
    subnormal arithmetic made steps up to 40 % slower. The accelerations, the stresses and the
    pair powers are flushed where they are produced, at ``prm[P_FLUSH]`` (1e-100 SI: a hundred
    orders below round-off of any resolved value, so results are unchanged beyond round-off)."""
    return 0.0 if abs(v) < tiny else v


@njit(inline="always", cache=True)
def pair_vector(x, y, i, j, prm):
    dx = x[i] - x[j]
    dy = y[i] - y[j]
    if PERIODIC:
        dx = minimum_image(dx, prm[P_LX])
        dy = minimum_image(dy, prm[P_LY])
    return dx, dy


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
    txx, tyy, txy, tzz = jaumann_trial(sxx, syy, sxy, szz, dxx, dyy, dxy, dzz, w, prm[P_BULK],
                                       prm[P_SHEAR], dt)
    if CAP_PLASTICITY:
        return plastic_return(txx, tyy, txy, tzz, epsv, epsp, dxx, dyy, dxy, dzz, prm)[3]
    return dp_return(txx, tyy, txy, tzz, prm[P_ALPHA_DP], prm[P_K_DP], prm[P_SHEAR])[3]


@njit(inline="always", cache=True)
def plastic_return(sxx, syy, sxy, szz, epsv, epsp, dxx, dyy, dxy, dzz, prm):
    """Cap model return (CAP_PLASTICITY) with the compressive damage and the compressive rate
    factor when those effects are on; returns (sxx, syy, sxy, szz, d_eps_v, d_eps_p, work)."""
    c = P_CAP
    strength = 1.0
    if COMPRESSIVE_DAMAGE:
        strength = 1.0 - ductile_damage(epsp, prm[c + 9])
    dif = 1.0
    if RATE_EFFECTS:
        dif = increase_factor(-principal_rates(dxx, dyy, dxy, dzz)[1], prm[P_YOUNG],
                              prm[c + 12], prm[c + 13], prm[c + 15], prm[c + 17])
    return cap_return(sxx, syy, sxy, szz, epsv, prm[c], prm[c + 1], prm[c + 2], prm[c + 3],
                      prm[c + 4], prm[c + 5], prm[c + 6], prm[c + 7], prm[c + 8], prm[P_BULK],
                      prm[P_SHEAR], strength, dif)


@njit(parallel=True, cache=True)
def material_pass(x, y, vx, vy, m, rho, h, h0, sig, nom, kap, dmg, epsp, wp, epsv, eint, eel,
                  offsets, index, dt, prm):
    """Velocity gradient with the mid-step velocities, then per particle: ρ and h (exact
    exponential update), Jaumann trial → DP return → damage → nominal stress; stress power
    (trapezoidal in the nominal stress) accumulated into the specific internal energy.
    The pair sums read ρ and h of the step's start (copies): this loop updates ρ_i and h_i in
    place, and reading a neighbour's value as it is being overwritten made the result depend
    on the particle order and, with several threads, on their timing."""
    n = x.size
    rho_start = rho.copy()
    h_start = h.copy()
    for i in prange(n):
        lxx = 0.0
        lxy = 0.0
        lyx = 0.0
        lyy = 0.0
        for p in range(offsets[i], offsets[i + 1]):
            j = index[p]
            if m[j] == 0.0:
                continue
            dx, dy = pair_vector(x, y, i, j, prm)
            r = math.sqrt(dx * dx + dy * dy)
            s = h_start[i] + h_start[j]  # support 2 h_ij
            if r >= s or r == 0.0:
                continue
            dw = kernel_dwdr(KIND, r, s, DIM) / r
            vol = m[j] / rho_start[j]
            dvx = vx[j] - vx[i]
            dvy = vy[j] - vy[i]
            lxx += vol * dvx * dw * dx
            lxy += vol * dvx * dw * dy
            lyx += vol * dvy * dw * dx
            lyy += vol * dvy * dw * dy
        tr = lxx + lyy
        rho_old = rho[i]
        rho[i] = rho_old * math.exp(-tr * dt)
        if VARIABLE_SMOOTHING_LENGTH:
            h[i] = benz_update(h[i], h0[i], tr, dt, DIM, prm[P_H_MIN], prm[P_H_MAX])
        dxy = 0.5 * (lxy + lyx)
        w = 0.5 * (lxy - lyx)
        oxx, oyy, oxy = nom[i, 0], nom[i, 1], nom[i, 2]
        sxx, syy, sxy, szz = sig[i, 0], sig[i, 1], sig[i, 2], sig[i, 3]
        dzz = 0.0
        if ELASTICITY:
            if PLANE_STRESS:
                dzz = plane_stress_dzz(sxx, syy, sxy, szz, epsv[i], epsp[i], lxx, lyy, dxy, w,
                                       dt, prm)
            sxx, syy, sxy, szz = jaumann_trial(sxx, syy, sxy, szz, lxx, lyy, dxy, dzz, w,
                                               prm[P_BULK], prm[P_SHEAR], dt)
        if PLASTICITY:
            sxx, syy, sxy, szz, deps, work = dp_return(sxx, syy, sxy, szz, prm[P_ALPHA_DP],
                                                       prm[P_K_DP], prm[P_SHEAR])
            epsp[i] += deps
            wp[i] += work / rho[i]
        if CAP_PLASTICITY:
            sxx, syy, sxy, szz, dv, deps, work = plastic_return(sxx, syy, sxy, szz, epsv[i],
                                                                epsp[i], lxx, lyy, dxy, dzz,
                                                                prm)
            epsp[i] += deps
            epsv[i] += dv
            wp[i] += work / rho[i]
        if PLANE_STRESS:
            szz = 0.0  # removes the solve's round-off residual
        tiny = prm[P_FLUSH]
        sxx, syy = flushed(sxx, tiny), flushed(syy, tiny)
        sxy, szz = flushed(sxy, tiny), flushed(szz, tiny)
        sig[i, 0], sig[i, 1], sig[i, 2], sig[i, 3] = sxx, syy, sxy, szz
        if DAMAGE:
            young = prm[P_YOUNG]
            if RATE_EFFECTS:
                young *= increase_factor(principal_rates(lxx, lyy, dxy, dzz)[0], young,
                                         prm[P_CAP + 10], prm[P_CAP + 11], prm[P_CAP + 14],
                                         prm[P_CAP + 16])
            k, d, nxx, nyy, nxy, nzz = damage_update(sxx, syy, sxy, szz, kap[i], young,
                                                     prm[P_KAPPA0], prm[P_KAPPA_F])
            kap[i] = k
            dmg[i] = d
            nom[i, 0], nom[i, 1] = flushed(nxx, tiny), flushed(nyy, tiny)
            nom[i, 2], nom[i, 3] = flushed(nxy, tiny), flushed(nzz, tiny)
        else:
            nom[i, 0], nom[i, 1], nom[i, 2], nom[i, 3] = sxx, syy, sxy, szz
        power = ((oxx + nom[i, 0]) * lxx + (oyy + nom[i, 1]) * lyy
                 + 2.0 * (oxy + nom[i, 2]) * dxy)
        eint[i] += 0.5 * dt * power * 2.0 / (rho_old + rho[i])
        if ELASTICITY:
            eel[i] = (1.0 - dmg[i]) * elastic_energy_density(
                sxx, syy, sxy, szz, prm[P_BULK], prm[P_SHEAR]) / rho[i]


@njit(parallel=True, cache=True)
def force_pass(x, y, vx, vy, m, rho, h, nom, rst, offsets, index, prm, ax, ay, pav, pas,
               mumax):
    """Accelerations from the pair bracket σ_i/ρ_i² + σ_j/ρ_j² − Π_ij 1 + f^n (R_i + R_j);
    per-particle AV and artificial-stress powers (per unit mass of i, symmetric halves) and
    max |μ_ij| for the time step."""
    n = x.size
    for i in prange(n):
        axi = 0.0
        ayi = 0.0
        pa = 0.0
        ps = 0.0
        mu_max = 0.0
        ri2 = 1.0 / (rho[i] * rho[i])
        ixx, iyy, ixy = nom[i, 0] * ri2, nom[i, 1] * ri2, nom[i, 2] * ri2
        for p in range(offsets[i], offsets[i + 1]):
            j = index[p]
            if m[j] == 0.0:
                continue
            dx, dy = pair_vector(x, y, i, j, prm)
            r2 = dx * dx + dy * dy
            r = math.sqrt(r2)
            s = h[i] + h[j]
            if r >= s or r == 0.0:
                continue
            dw = kernel_dwdr(KIND, r, s, DIM) / r
            gx = dw * dx
            gy = dw * dy
            rj2 = 1.0 / (rho[j] * rho[j])
            bxx = ixx + nom[j, 0] * rj2
            byy = iyy + nom[j, 1] * rj2
            bxy = ixy + nom[j, 2] * rj2
            dvx = vx[i] - vx[j]
            dvy = vy[i] - vy[j]
            vg = dvx * gx + dvy * gy
            if ARTIFICIAL_VISCOSITY:
                pi, mu = monaghan_pi(dvx * dx + dvy * dy, r2, 0.5 * s, 0.5 * (rho[i] + rho[j]),
                                     prm[P_C], prm[P_AV_ALPHA], prm[P_AV_BETA])
                bxx -= pi
                byy -= pi
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
                ps -= 0.5 * m[j] * (dvx * (cxx * gx + cxy * gy) + dvy * (cxy * gx + cyy * gy))
            axi += m[j] * (bxx * gx + bxy * gy)
            ayi += m[j] * (bxy * gx + byy * gy)
        tiny = prm[P_FLUSH]
        ax[i] = flushed(axi, tiny)
        ay[i] = flushed(ayi, tiny)
        pav[i] = flushed(pa, tiny)
        pas[i] = flushed(ps, tiny)
        mumax[i] = mu_max


@njit(cache=True)
def artificial_stress_pass(nom, rho, prm, rst):
    for i in range(rho.size):
        if ARTIFICIAL_STRESS:
            rst[i, 0], rst[i, 1], rst[i, 2] = artificial_stress_tensor(
                nom[i, 0], nom[i, 1], nom[i, 2], rho[i], prm[P_AS_EPS])


@njit(cache=True)
def contact_pass(y, m, ay, dt, prm, kinematic):
    """Penalty forces of the rigid base (added to ay); returns (total force, penalty energy).
    ``kinematic[i]`` marks particles left to the kinematic constraint (bulk contact)."""
    force = 0.0
    energy = 0.0
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
    (momentum given to the base, kinetic energy removed). Called before a kick with
    ``arrival`` (a particle still moving into the base is stopped: inelastic, its kinetic
    energy is removed) and after it without (the base's reaction cancels the kick's pull into
    it: the particle does not move, so the reaction does no work and no energy is logged;
    logging the kick's ½ m (a Δt/2)² would count energy the drift never took from the
    stress)."""
    mom = 0.0
    ke = 0.0
    limit = prm[P_BASE] + prm[P_RC]
    for i in range(y.size):
        if kinematic[i] and y[i] < limit and vy[i] < 0.0:
            mom += m[i] * (-vy[i])
            if arrival:
                ke += 0.5 * m[i] * vy[i] * vy[i]
            vy[i] = 0.0
    return mom, ke


@njit(cache=True)
def time_step(h, vx, vy, mumax, prm, cfl):
    """Δt = cfl min_i h_i / (c + |v_i| + 1.2 (α c + β max_j |μ_ij|))."""
    best = np.inf
    c = prm[P_C]
    for i in range(h.size):
        speed = c + math.sqrt(vx[i] * vx[i] + vy[i] * vy[i])
        if ARTIFICIAL_VISCOSITY:
            speed += 1.2 * (prm[P_AV_ALPHA] * c + prm[P_AV_BETA] * mumax[i])
        t = cfl * h[i] / speed
        if t < best:
            best = t
    return best
