r"""Beams: elastic bonds between particles with bond damping (lattice spec sections 3-5).

Per bond, the chord-frame energy, forces and torques of :mod:`craquelure.lattice.beam`.

Bond damping [D, departs from HiDEM's dashpot on the global relative displacement]: a
stiffness-proportional dashpot on the deformation rates, :math:`N \mathrel{+}= \beta k_n \dot e`,
:math:`M_1 \mathrel{+}= \beta(a\dot\varphi_1' + b\dot\varphi_2')` (and M2), rates by backward
differences over one step; :math:`\beta = 2\zeta\sqrt{m/k_n}` for a damping ratio
:math:`\zeta` of the critical :math:`2\sqrt{k_n m}`. It is frame-indifferent (no damping of
rigid rotation) and conserves linear and angular momentum. The dissipated energy is booked
as the trapezoidal sum of the damping forces times the deformation increments (the form that
closes the central-difference energy budget).
"""

import math

from numba import njit

from craquelure.registry import Effect

EFFECT = Effect("lattice", "beams", "BEAMS",
                "elastic beams (Euler-Bernoulli or shear-beam) with bond damping",
                requires=("material.bond_model",))


@njit(inline="always", cache=True)
def wrap_angle(a):
    """Angle in (-pi, pi] (no arithmetic when it already is)."""
    if -math.pi < a <= math.pi:
        return a
    return a - 2.0 * math.pi * math.floor((a + math.pi) / (2.0 * math.pi))


@njit(inline="always", cache=True)
def chord_rotation(cr, dt):
    """atan2(cr, dt): the angle from the rest direction e0 to the chord, given
    cr = e0 x d and dt = e0 . d. For |cr| <= 0.1 dt (the usual case: chord within 5.7 deg of
    its rest direction) atan(t), t = cr/dt, from its Taylor series to t^15 (truncation
    t^17/17 < 1e-17 |t|, i.e. below double round-off); exact atan2 otherwise."""
    if dt > 0.0 and abs(cr) <= 0.1 * dt:
        t = cr / dt
        t2 = t * t
        p = -1.0 / 15.0
        p = p * t2 + 1.0 / 13.0
        p = p * t2 - 1.0 / 11.0
        p = p * t2 + 1.0 / 9.0
        p = p * t2 - 1.0 / 7.0
        p = p * t2 + 1.0 / 5.0
        p = p * t2 - 1.0 / 3.0
        p = p * t2 + 1.0
        return t * p
    return math.atan2(cr, dt)


@njit(inline="always", cache=True)
def deformation(dx, dy, thi, thj, l0, c0, s0, t0i, t0j, dref):
    """(ell, cos alpha, sin alpha, e, phi1', phi2', Delta alpha) of a bond with chord (dx, dy)
    and rest direction e0 = (c0, s0) = (cos alpha0, sin alpha0).

    Delta alpha = alpha - alpha0 = atan2(e0 x d, e0 . d) is a function of the current chord
    only (path-independent form); it is unwrapped against ``dref`` (its value one step
    earlier): Delta alpha = dref + wrap(Delta alpha - dref), so a tumbling fragment whose bonds
    turn by more than pi keeps continuous end rotations (no 2 pi jump in phi')."""
    ell = math.sqrt(dx * dx + dy * dy)
    rel = chord_rotation(c0 * dy - s0 * dx, c0 * dx + s0 * dy)
    dalpha = dref + wrap_angle(rel - dref)
    inv = 1.0 / ell
    return (ell, dx * inv, dy * inv, ell - l0, (thi - t0i) - dalpha, (thj - t0j) - dalpha, dalpha)


@njit(inline="always", cache=True)
def elastic_energy(kn, ka, kb, e, p1, p2):
    return 0.5 * kn * e * e + 0.5 * ka * (p1 * p1 + p2 * p2) + kb * p1 * p2
