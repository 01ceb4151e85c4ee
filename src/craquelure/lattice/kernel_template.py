"""Source template of the lattice time-step kernel (lattice spec sections 5-8).

:func:`craquelure.codegen.specialise` compiles a copy with the effect flags / ``PERIODIC_X`` /
``NODE_AVERAGED`` / ``BENDING`` / ``PARALLEL`` constants of one scene; this file itself is
never compiled.

One call of :func:`advance` performs up to ``n_steps`` central-difference steps (section 5):

1. bonds, in ``NCHUNK`` fixed chunks of the bond list (``prange`` over chunks): deformation,
   elastic and damping forces, energy; per-beam fracture and melting decisions (a bond that
   fails or melts carries no force in this step). Each chunk scatters its bond forces into
   its own node-force buffer ``fn[c]`` (race-free; bonds are sorted by their first end, so a
   chunk touches a narrow node range ``crange[:, c]``, the only part of its buffer that is
   cleared and read);
2. node-averaged fracture (serial, optional; a beam broken here has its force taken back
   out of its chunk's buffer);
3. contacts (serial, optional): repulsion and friction over the Verlet pair list;
4. particles, in ``NCHUNK`` node chunks (``prange``): sum the chunk buffers that cover the
   node, add gravity, buoyancy, bed, loads; update each dof in place with
   ``x+ = [2x - (1 - g dt/2) x- + dt^2 F/m] / (1 + g dt/2)`` (g: mass damping (until
   ``GAMMA_UNTIL``) + drag + bed damping rates, i.e. C = g M, implicit), clamp fixed dofs,
   prescribe driven ones;
5. energy sample every ``series_every`` steps: E_tot = KE + KE_rot + U_beams + U_contact +
   U_external - W_ext + E_damp + E_fract + E_melt (section 8), with KE = 1/2 m v- . v+ from
   the two half-step velocities; with work and damping booked as trapezoidal sums
   1/2 (f_k + f_k+1)(x_k+1 - x_k) this budget is exact for a linear system; the call
   stops with status NAN or RUNAWAY when E_tot is not finite or |E_tot - E_0| exceeds
   ``energy_tolerance`` times max(E_mech, |W_ext|, dissipated, floor) plus the round-off
   allowance 4 eps sum_i |x_i| (m_i |x+ - x|/dt^2 + sum over the steps of |F_i|): positions
   are absolute, so at tiny steps a displacement, hence v and the booked work, is only known
   to ~eps |x|.

Determinism: the chunk count is a constant (not the thread count) and the per-chunk partial
sums (energies, node forces) are added in chunk order, so the serial and the parallel kernel
and any number of threads give bit-identical trajectories. ``fastmath`` is restricted to
``FASTMATH`` (FMA contraction, reciprocal, no signed zeros): no ``nnan``/``ninf``, so the NaN
check stays valid.

Status codes: OK, NAN, RUNAWAY, REBUILD (contact list must be rebuilt; the step is complete).
"""

import math

import numpy as np
from numba import njit, prange

from craquelure.codegen import param_indices
from craquelure.lattice.effects.beams import deformation, elastic_energy
from craquelure.lattice.effects.bed import bed
from craquelure.lattice.effects.buoyancy import buoyancy
from craquelure.lattice.effects.contact import friction, repulsion
from craquelure.lattice.effects.drag import drag_rate
from craquelure.lattice.effects.fracture import beam_ratio_scaled, node_ratio
from craquelure.lattice.effects.gravity import gravity
from craquelure.lattice.effects.melting import melt_rate, uniform01
from craquelure.periodic import minimum_image
from craquelure.registry import parameter_names

# BEGIN FLAGS
BEAMS = True
FRACTURE = True
MELTING = True
CONTACT = True
GRAVITY = True
BUOYANCY = True
DRAG = True
BED = True
PERIODIC_X = True
NODE_AVERAGED = True
BENDING = True
PARALLEL = True
# END FLAGS

# the parameter vector, as the effects declare it (craquelure.registry); the engine packs it
PARAMS = parameter_names("lattice")
N_PARAMS = len(PARAMS)
DT, BETA, GAMMA, AREA, INERTIA, WIDTH, SIGMA0, TAU0, T_FRACTURE = param_indices(
    PARAMS, "dt", "beta", "gamma", "area", "inertia", "width", "sigma0", "tau0", "fracture_start")
MELT_A, E_B, BLOCK, FROZEN_RATE = param_indices(
    PARAMS, "melt_rate_factor", "E_b", "block", "frozen_rate")
KC, MU_F, C_T, SKIN = param_indices(
    PARAMS, "contact_stiffness", "friction", "friction_viscosity", "skin")
G, RHO, RHO_W, Y_WATER, C_DRAG, DRAG_ALL = param_indices(
    PARAMS, "g", "rho", "rho_w", "water_level", "drag_rate", "drag_everywhere")
Y_BED, K_BED, C_BED, C_FRIC_BED = param_indices(
    PARAMS, "bed_level", "bed_stiffness", "bed_damping", "bed_friction")
LX, DRIVE_VX, DRIVE_VY, DRIVE_AMP, DRIVE_PERIOD, DRIVE_T0, LOAD_RAMP = param_indices(
    PARAMS, "period_x", "drive_vx", "drive_vy", "drive_amplitude", "drive_period", "drive_start",
    "load_ramp")
ENERGY_TOL, ENERGY_FLOOR, CELL_AREA, GAMMA_UNTIL, SLOPE = param_indices(
    PARAMS, "energy_tolerance", "energy_floor", "cell_area", "mass_damping_until", "slope_angle")
# accumulator indices
A_DAMP, A_FRACT, A_MELT, A_WORK, A_BROKEN, A_MELTED, A_E0, A_E0SET, A_ROUND = range(9)
N_ACC = 9
# round-off allowance of the energy budget, in units of sum |x| (|F| + m |dx|/dt^2): positions
# are absolute, so a step's displacement, hence v and the booked work, is known to ~eps |x|
ROUNDOFF = 4.0 * 2.220446049250313e-16
# series columns
SERIES = ("time", "kinetic", "rotational", "elastic", "contact", "external", "work",
          "damping", "fracture", "melting", "total", "broken", "melted", "load_ux", "load_uy",
          "drive_fx", "drive_fy")
N_SERIES = len(SERIES)
OK, NAN, RUNAWAY, REBUILD = 0, 1, 2, 3
# fixed number of work chunks (bonds and particles); independent of the thread count
NCHUNK = 8
FASTMATH = {"arcp", "nsz"}
# per-chunk partial sums of the bond phase and of the particle phase
B_U, B_DAMP, B_FRACT, B_MELT, B_BROKEN, B_MELTED = 0, 1, 2, 3, 4, 5
N_BPART = 6
(P_KIN, P_ROT, P_UEXT, P_WORK, P_DISS, P_DISS_FWD, P_WORK_FWD, P_LUX, P_LUY, P_NLOAD, P_DFX,
 P_DFY, P_MOVED, P_ROUND_KIN, P_ROUND_WORK) = range(15)
N_PPART = 15


@njit(inline="always", cache=True)
def _drive(t, p):
    s = t - p[DRIVE_T0]
    if s <= 0.0:
        return 0.0, 0.0
    ux = p[DRIVE_VX] * s
    if p[DRIVE_PERIOD] > 0.0:
        ux += p[DRIVE_AMP] * math.sin(2.0 * math.pi * s / p[DRIVE_PERIOD])
    return ux, p[DRIVE_VY] * s


@njit(cache=True)
def _dof(xa, xm, f, g, mm, dt, fixed, driven, target):
    """One dof of the central-difference update with implicit damping rate g; returns
    (x+, kinetic 1/2 m v- v+, dissipation, its forward half, support work, its forward half,
    support force)."""
    if fixed:
        xn = xa
    elif driven:
        xn = target
    else:
        h2 = 0.5 * g * dt
        # x+ (1 + h2) = 2 x - (1 - h2) x- + dt^2 f/m, written as an increment of x: the
        # absolute form rounds 1 + h2 and leaves x (1 + h2)/fl(1 + h2) != x at rest, a
        # spurious force ~ eps |x| m/dt^2 that outgrows the physics at tiny steps
        xn = xa + ((1.0 - h2) * (xa - xm) + dt * dt * f / mm) / (1.0 + h2)
    ke = 0.5 * mm * (xa - xm) * (xn - xa) / (dt * dt)
    if fixed or driven:
        fsup = mm * (xn - 2.0 * xa + xm) / (dt * dt) - f
        return xn, ke, 0.0, 0.0, fsup * 0.5 * (xn - xm), fsup * 0.5 * (xn - xa), fsup
    vc = (xn - xm) / (2.0 * dt)
    return xn, ke, g * mm * vc * vc * dt, g * mm * vc * 0.5 * (xn - xa), 0.0, 0.0, 0.0


@njit(inline="always", cache=True)
def _chord(q, i, j, lx):
    dx = q[0, j] - q[0, i]
    if PERIODIC_X:
        dx = minimum_image(dx, lx)
    return dx, q[1, j] - q[1, i]


@njit(cache=True, parallel=PARALLEL)
def bond_deformations(q, bi, bj, bref, state, lx, out):
    """(e, phi1', phi2') of every bond at configuration q (used to start bond damping)."""
    for b in prange(bi.size):
        if state[b] != 1:
            continue
        dx, dy = _chord(q, bi[b], bj[b], lx)
        _, _, _, e, p1, p2, _ = deformation(dx, dy, q[2, bi[b]], q[2, bj[b]], bref[0, b],
                                             bref[1, b], bref[2, b], bref[3, b], bref[4, b],
                                             0.0)
        out[0, b], out[1, b], out[2, b] = e, p1, p2


@njit(cache=True, fastmath=FASTMATH)
def _bond_chunk(lo, hi, nlo, nhi, q, qm, bi, bj, bref, bk, state, unbreak, bprev, bforce,
                benergy, bratio, tbreak, p, seed, gstep, t, fn, out):
    """Bonds lo..hi-1: forces scattered into fn (3, n) (nodes nlo..nhi-1 cleared first),
    partial sums into out[B_*]."""
    dt = p[DT]
    lx = p[LX]
    bd = p[BETA] / dt
    inv_area = 1.0 / p[AREA]
    bend = p[WIDTH] / (2.0 * p[INERTIA])
    inv_sigma0 = 1.0 / p[SIGMA0]
    inv_tau0 = 1.0 / p[TAU0]
    for a in range(3):
        for i in range(nlo, nhi):
            fn[a, i] = 0.0
    u_beams = e_damp = e_fract = e_melt = n_broken = n_melted = 0.0
    for b in range(lo, hi):
        if state[b] != 1:
            continue
        i, j = bi[b], bj[b]
        dx, dy = _chord(q, i, j, lx)
        dref = (qm[2, i] - bref[3, b]) - bprev[1, b]  # chord rotation at t - dt
        ell, c, s, e, p1, p2, _ = deformation(dx, dy, q[2, i], q[2, j], bref[0, b], bref[1, b],
                                              bref[2, b], bref[3, b], bref[4, b], dref)
        kn, ka, kb = bk[0, b], bk[1, b], bk[2, b]
        nax = kn * e
        m1 = ka * p1 + kb * p2
        m2 = kb * p1 + ka * p2
        u = elastic_energy(kn, ka, kb, e, p1, p2)
        benergy[b] = u
        if FRACTURE:
            r = beam_ratio_scaled(nax, (m1 + m2) / ell, m1, m2, inv_area, bend, inv_sigma0,
                                  inv_tau0, BENDING)
            bratio[b] = r
            if (not NODE_AVERAGED) and t >= p[T_FRACTURE] and unbreak[b] == 0 and r >= 1.0:
                state[b] = 0
                tbreak[b] = t
                e_fract += u
                n_broken += 1.0
                continue
        if MELTING:
            lam = melt_rate(u, p[MELT_A], p[E_B], p[BLOCK], p[FROZEN_RATE])
            if uniform01(seed, gstep, b) < -math.expm1(-lam * dt):
                bref[0, b] = ell
                bref[1, b] = c
                bref[2, b] = s
                bref[3, b] = q[2, i]
                bref[4, b] = q[2, j]
                for r in range(6):
                    bprev[r, b] = 0.0
                if NODE_AVERAGED:
                    for r in range(4):
                        bforce[r, b] = 0.0
                benergy[b] = 0.0
                e_melt += u
                n_melted += 1.0
                continue
        # bond damping on the backward deformation rates; dissipation booked as the
        # trapezoidal sum 1/2 (f_d(t - dt) + f_d(t)) . (d(t) - d(t - dt))
        de = e - bprev[0, b]
        dp1 = p1 - bprev[1, b]
        dp2 = p2 - bprev[2, b]
        nd = bd * kn * de
        m1d = bd * (ka * dp1 + kb * dp2)
        m2d = bd * (kb * dp1 + ka * dp2)
        e_damp += 0.5 * ((bprev[3, b] + nd) * de + (bprev[4, b] + m1d) * dp1
                         + (bprev[5, b] + m2d) * dp2)
        bprev[0, b] = e
        bprev[1, b] = p1
        bprev[2, b] = p2
        bprev[3, b] = nd
        bprev[4, b] = m1d
        bprev[5, b] = m2d
        nax += nd
        m1 += m1d
        m2 += m2d
        v = (m1 + m2) / ell
        fx = -nax * c - v * s  # force on j; on i it is the opposite
        fy = -nax * s + v * c
        fn[0, i] -= fx
        fn[1, i] -= fy
        fn[2, i] -= m1
        fn[0, j] += fx
        fn[1, j] += fy
        fn[2, j] -= m2
        if NODE_AVERAGED:
            bforce[0, b] = fx
            bforce[1, b] = fy
            bforce[2, b] = -m1
            bforce[3, b] = -m2
        u_beams += u
    sums = (u_beams, e_damp, e_fract, e_melt, n_broken, n_melted)  # in the order of B_*
    for r in range(N_BPART):
        out[r] = sums[r]


@njit(cache=True, fastmath=FASTMATH)
def _particle_chunk(lo, hi, qm, q, qref, qbuild, mass, inertia, diam, fix, drive, load, fn,
                    crange, fc, p, t, out):
    """Particles lo..hi-1: total force, central-difference update in place
    ((qm, q) <- (q, q+)), partial sums into out[P_*]."""
    dt = p[DT]
    ux_d, uy_d = _drive(t + dt, p)
    ramp = min(1.0, t / p[LOAD_RAMP]) if p[LOAD_RAMP] > 0.0 else 1.0
    gam = p[GAMMA] if t < p[GAMMA_UNTIL] else 0.0
    g_x = p[G] * math.sin(p[SLOPE])
    g_y = -p[G] * math.cos(p[SLOPE])
    kin = rot = u_ext = work = diss = diss_fwd = work_fwd = lux = luy = nload = dfx = dfy = 0.0
    moved = round_kin = round_work = 0.0
    for i in range(lo, hi):
        m = mass[i]
        fx = fy = tq = 0.0
        if BEAMS:
            for c in range(NCHUNK):
                if crange[0, c] <= i < crange[1, c]:
                    fx += fn[c, 0, i]
                    fy += fn[c, 1, i]
                    tq += fn[c, 2, i]
        if CONTACT:
            fx += fc[0, i]
            fy += fc[1, i]
            # cleared here, in the parallel phase, for the next step's contact sums
            fc[0, i] = 0.0
            fc[1, i] = 0.0
        yi = q[1, i]
        gx = gam
        gy = gam
        if GRAVITY:
            fgx, fgy, ug = gravity(m, g_x, g_y, q[0, i], yi, qref[0, i], qref[1, i])
            fx += fgx
            fy += fgy
            u_ext += ug
        if BUOYANCY:
            fb, ub = buoyancy(m, p[RHO], p[RHO_W], p[G], yi, qref[1, i], p[Y_WATER])
            fy += fb
            u_ext += ub
        if DRAG:
            cd = drag_rate(yi, p[Y_WATER], p[C_DRAG], p[DRAG_ALL] > 0.0)
            gx += cd
            gy += cd
        if BED:
            h, fbed, ubed = bed(yi, diam[i], p[Y_BED], p[K_BED])
            if h > 0.0:
                fy += fbed
                u_ext += ubed
                gy += p[C_BED]
                gx += p[C_FRIC_BED]
        lfx = load[0, i] * ramp
        lfy = load[1, i] * ramp
        fx += lfx
        fy += lfy
        # update each dof (x, y with the mass, theta with J)
        xn, kx, dx1, dx2, wx1, wx2, fsx = _dof(q[0, i], qm[0, i], fx, gx, m, dt, fix[0, i],
                                               drive[0, i], qref[0, i] + ux_d)
        yn, ky, dy1, dy2, wy1, wy2, fsy = _dof(q[1, i], qm[1, i], fy, gy, m, dt, fix[1, i],
                                               drive[1, i], qref[1, i] + uy_d)
        tn, kt, dt1, dt2, wt1, wt2, _ = _dof(q[2, i], qm[2, i], tq, gam, inertia[i], dt,
                                             fix[2, i], 0, 0.0)
        kin += kx + ky
        rot += kt
        ax_, ay_ = abs(q[0, i]), abs(q[1, i])
        round_kin += m * (ax_ * abs(xn - q[0, i]) + ay_ * abs(yn - q[1, i])) / (dt * dt)
        round_work += abs(fx) * ax_ + abs(fy) * ay_
        diss += dx1 + dy1 + dt1
        diss_fwd += dx2 + dy2 + dt2
        work += (wx1 + wy1 + wt1 + lfx * 0.5 * (xn - qm[0, i])
                 + lfy * 0.5 * (yn - qm[1, i]))
        work_fwd += (wx2 + wy2 + wt2 + lfx * 0.5 * (xn - q[0, i])
                     + lfy * 0.5 * (yn - q[1, i]))
        if drive[0, i]:
            dfx += fsx
        if drive[1, i]:
            dfy += fsy
        if load[0, i] != 0.0 or load[1, i] != 0.0:
            lux += q[0, i] - qref[0, i]
            luy += q[1, i] - qref[1, i]
            nload += 1.0
        if CONTACT:
            ddx = xn - qbuild[0, i]
            ddy = yn - qbuild[1, i]
            moved = max(moved, ddx * ddx + ddy * ddy)
        # node i is read by no other node in this phase: rotate (qm, q) <- (q, q+) in place
        qm[0, i] = q[0, i]
        qm[1, i] = q[1, i]
        qm[2, i] = q[2, i]
        q[0, i] = xn
        q[1, i] = yn
        q[2, i] = tn
    sums = (kin, rot, u_ext, work, diss, diss_fwd, work_fwd, lux, luy, nload, dfx, dfy, moved,
            round_kin, round_work)  # in the order of P_*
    for r in range(N_PPART):
        out[r] = sums[r]


@njit(cache=True, parallel=PARALLEL)
def advance(qm, q, qref, qbuild, mass, inertia, diam, fix, drive, load,
            bi, bj, bref, bk, state, unbreak, bprev, bforce, benergy, bratio, tbreak,
            poff, pidx, cb, crange, cn, fn, cpi, cpj, fc, p, acc, seed, step0, n_steps,
            series_every, record_last, series):
    """Advance up to n_steps; returns (status, steps done, series rows written).

    A series row is written every series_every steps and, if record_last, at the last step.

    qm, q: configurations (x, y, theta rows) at t - dt and t on entry, at the new
    (t - dt, t) on exit. cb (NCHUNK + 1): bond chunk bounds; crange (2, NCHUNK): node range
    touched by each bond chunk; cn (NCHUNK + 1): particle chunk bounds; fn (NCHUNK, 3, n):
    node-force buffers. Bond and accumulator arrays are updated in place.
    """
    n, ncp = q.shape[1], cpi.size
    dt = p[DT]
    lx = p[LX]
    rows = 0
    status = OK
    done = 0
    # per-chunk partial sums, each row written whole by its chunk before it is read (np.zeros
    # in a parallel function would be a parallel region of its own)
    bpart = np.empty((NCHUNK, N_BPART))
    ppart = np.empty((NCHUNK, N_PPART))
    psum = np.empty(N_PPART)
    for k in range(n_steps):
        gstep = step0 + k
        t = gstep * dt
        broken_before = acc[A_BROKEN]
        # 1. bonds
        u_beams = e_fract = n_broken = 0.0
        if BEAMS:
            for c in prange(NCHUNK):
                _bond_chunk(cb[c], cb[c + 1], crange[0, c], crange[1, c], q, qm, bi, bj, bref,
                            bk, state, unbreak, bprev, bforce, benergy, bratio, tbreak, p,
                            seed, gstep, t, fn[c], bpart[c])
            for c in range(NCHUNK):
                u_beams += bpart[c, B_U]
                acc[A_DAMP] += bpart[c, B_DAMP]
                e_fract += bpart[c, B_FRACT]
                acc[A_MELT] += bpart[c, B_MELT]
                n_broken += bpart[c, B_BROKEN]
                acc[A_MELTED] += bpart[c, B_MELTED]
        # 2. node-averaged fracture
        if BEAMS and FRACTURE and NODE_AVERAGED and t >= p[T_FRACTURE]:
            vol = 2.0 * p[CELL_AREA]
            for i in range(n):
                sxx = syy = sxy = 0.0
                best = -1
                best_r = -1.0
                for kk in range(poff[i], poff[i + 1]):
                    b = pidx[kk]
                    if state[b] != 1:
                        continue
                    dx, dy = _chord(q, bi[b], bj[b], lx)
                    fx, fy = bforce[0, b], bforce[1, b]  # on j; on i it is -f, r_i->j = -d
                    if bi[b] == i:
                        fx, fy = -fx, -fy
                    else:
                        dx, dy = -dx, -dy
                    sxx += dx * fx
                    syy += dy * fy
                    sxy += 0.5 * (dx * fy + dy * fx)
                    if unbreak[b] == 0 and bratio[b] > best_r:
                        best_r = bratio[b]
                        best = b
                if best >= 0 and node_ratio(sxx / vol, syy / vol, sxy / vol, p[SIGMA0],
                                            p[TAU0]) >= 1.0:
                    state[best] = 0
                    tbreak[best] = t
                    e_fract += benergy[best]
                    u_beams -= benergy[best]
                    n_broken += 1.0
                    # take the beam's force back out of its chunk's buffer
                    c = 0
                    while cb[c + 1] <= best:
                        c += 1
                    ib, jb = bi[best], bj[best]
                    fn[c, 0, ib] += bforce[0, best]
                    fn[c, 1, ib] += bforce[1, best]
                    fn[c, 2, ib] -= bforce[2, best]
                    fn[c, 0, jb] -= bforce[0, best]
                    fn[c, 1, jb] -= bforce[1, best]
                    fn[c, 2, jb] -= bforce[3, best]
        acc[A_FRACT] += e_fract
        acc[A_BROKEN] += n_broken
        # 3. contacts
        u_contact = 0.0
        if CONTACT:
            # fc is zero here: the particle phase clears what it read (a whole-array
            # assignment would be a parallel region of its own)
            for kk in range(ncp):
                i, j = cpi[kk], cpj[kk]
                dx, dy = _chord(q, i, j, lx)
                r = math.sqrt(dx * dx + dy * dy)
                f, uc = repulsion(r, 0.5 * (diam[i] + diam[j]), p[KC])
                if f == 0.0:
                    continue
                nx, ny = dx / r, dy / r
                fc[0, j] += f * nx
                fc[1, j] += f * ny
                fc[0, i] -= f * nx
                fc[1, i] -= f * ny
                u_contact += uc
                if p[MU_F] > 0.0:
                    vt = (((q[0, j] - qm[0, j]) - (q[0, i] - qm[0, i])) * (-ny)
                          + ((q[1, j] - qm[1, j]) - (q[1, i] - qm[1, i])) * nx) / dt
                    ft = friction(f, vt, p[MU_F], p[C_T])
                    fc[0, j] -= ft * ny
                    fc[1, j] += ft * nx
                    fc[0, i] += ft * ny
                    fc[1, i] -= ft * nx
                    acc[A_DAMP] += abs(ft * vt) * dt
        # 4. particles (updated in place)
        for c in prange(NCHUNK):
            _particle_chunk(cn[c], cn[c + 1], qm, q, qref, qbuild, mass, inertia, diam, fix,
                            drive, load, fn, crange, fc, p, t, ppart[c])
        # the chunks' partial sums, added in chunk order (the largest displacement is a max;
        # the round-off allowance of the work goes straight into its accumulator)
        for r in range(N_PPART):
            psum[r] = 0.0
        for c in range(NCHUNK):
            for r in range(N_PPART):
                if r == P_MOVED:
                    psum[r] = max(psum[r], ppart[c, r])
                else:
                    psum[r] += ppart[c, r]
            acc[A_ROUND] += ppart[c, P_ROUND_WORK]
        kin, rot, u_ext = psum[P_KIN], psum[P_ROT], psum[P_UEXT]
        acc[A_DAMP] += psum[P_DISS]
        acc[A_WORK] += psum[P_WORK]
        done = k + 1
        # 5. energy sample and checks
        if (gstep + 1) % series_every == 0 or (record_last and k == n_steps - 1):
            # work and dissipation up to t (the trapezoidal sums that make 1/2 m v- v+ + U
            # exact): drop the forward half-steps booked in this step
            w_t = acc[A_WORK] - psum[P_WORK_FWD]
            d_t = acc[A_DAMP] - psum[P_DISS_FWD]
            total = kin + rot + u_beams + u_contact + u_ext - w_t + d_t + acc[A_FRACT] + acc[A_MELT]
            if acc[A_E0SET] == 0.0:
                acc[A_E0] = total
                acc[A_E0SET] = 1.0
            if rows < series.shape[0]:
                row = series[rows]
                row[0], row[1], row[2], row[3] = t, kin, rot, u_beams
                row[4], row[5], row[6], row[7] = u_contact, u_ext, w_t, d_t
                row[8], row[9], row[10] = acc[A_FRACT], acc[A_MELT], total
                row[11], row[12] = acc[A_BROKEN], acc[A_MELTED]
                nload = psum[P_NLOAD]
                row[13] = psum[P_LUX] / nload if nload > 0 else 0.0
                row[14] = psum[P_LUY] / nload if nload > 0 else 0.0
                row[15], row[16] = psum[P_DFX], psum[P_DFY]
                rows += 1
            if not math.isfinite(total):
                status = NAN
                break
            scale = max(abs(kin) + abs(rot) + u_beams + u_contact + abs(u_ext),
                        abs(w_t), d_t + acc[A_FRACT] + acc[A_MELT],
                        p[ENERGY_FLOOR])
            # plus what round-off alone can do (tiny steps: displacements near eps |x|)
            allowance = ROUNDOFF * (psum[P_ROUND_KIN] + acc[A_ROUND])
            if abs(total - acc[A_E0]) > p[ENERGY_TOL] * scale + allowance:
                status = RUNAWAY
                break
        if CONTACT and (psum[P_MOVED] > 0.25 * p[SKIN] * p[SKIN]
                            or acc[A_BROKEN] > broken_before):
            status = REBUILD
            break
    return status, done, rows
