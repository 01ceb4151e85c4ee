"""A strain-driven single material point of the concrete (no SPH), for check 6 (impact spec
section 10): the update order of :mod:`craquelure.impact.material` composed from the effect
fragments, with stress-free lateral directions: the prescribed strain-rate components are
imposed, the free ones are found by a Newton iteration (finite-difference Jacobian) so that the
free *nominal* stresses vanish."""

from __future__ import annotations

import numpy as np
from numba import njit

from craquelure.impact.effects.cap_plasticity import cap_return
from craquelure.impact.effects.compressive_damage import ductile_damage
from craquelure.impact.effects.damage import damage_update
from craquelure.impact.effects.elasticity import jaumann_trial
from craquelure.impact.effects.plasticity import dp_return
from craquelure.impact.effects.rate_effects import (
    increase_factor,
    softening_left,
    strain_rate,
    viscoplastic,
)
from craquelure.impact.material import Concrete

# Plasticity variants of the material point (the SPH kernels select them by effect flags).
NO_PLASTICITY, DRUCKER_PRAGER, CAP = 0, 1, 2


# Not cached: numba's cache does not see edits in the inlined effect fragments, and this
# driver is not a hot path (the SPH kernels are generated per effect set, see engine.py).
@njit
def point_update(state, dxx, dyy, dxy, dzz, w, dt, bulk, shear, alpha, k, young, eps_0,
                 eps_f, plastic, damage, cap, compressive, rate):
    """Advance one point with strain rate D (xx, yy, xy, zz), spin w over ``dt``.
    ``state`` = [sxx, syy, sxy, szz (effective, inviscid), kappa, D_t, eps_p, wp, eps_v^p,
    nominal xx, yy, xy, zz]; ``plastic``: NO_PLASTICITY, DRUCKER_PRAGER or CAP (constants
    ``cap`` = Concrete.cap_vector()); returns the nominal stress (xx, yy, xy, zz), with ``rate``
    the viscoplastic one."""
    d = (dxx, dyy, dxy, dzz, 0.0, 0.0)
    s = jaumann_trial((state[0], state[1], state[2], state[3], 0.0, 0.0), d, (w, 0.0, 0.0),
                      bulk, shear, dt)
    if plastic == DRUCKER_PRAGER:
        s, deps, work = dp_return(s, alpha, k, shear)
        state[6] += deps
        state[7] += work
    elif plastic == CAP:
        strength = 1.0
        if compressive:
            strength = 1.0 - ductile_damage(state[6], cap[9])
        s, dv, deps, work = cap_return(
            s, state[8], cap[0], cap[1], cap[2], cap[3], cap[4], cap[5],
            cap[6], cap[7], cap[8], cap[20], cap[21], bulk, shear, strength)
        state[6] += deps
        state[7] += work
        state[8] += dv
    state[0], state[1], state[2], state[3] = s[0], s[1], s[2], s[3]
    n = s
    ed = strain_rate(d)
    intact = 1.0
    dif_t = increase_factor(ed, young, cap[10], cap[11], cap[14], cap[18]) if rate else 1.0
    if damage:
        eps_f *= dif_t ** (cap[17] - 1.0)  # G_F DIF_t^REPOW with the overstress
        eps_max, dt_, n = damage_update(s, state[4], young, eps_0, eps_f,
                                        state[5] if rate else 0.0)
        state[4], state[5] = eps_max, dt_
        intact = softening_left(eps_max, eps_0, eps_f, dif_t)
    if rate:
        old = (state[9], state[10], state[11], state[12], 0.0, 0.0)
        n = viscoplastic(jaumann_trial(old, d, (w, 0.0, 0.0), bulk, shear, dt), n, ed, dt,
                         cap[10], cap[11], cap[12], cap[13], cap[14], cap[15], cap[16], young,
                         intact)
    state[9], state[10], state[11], state[12] = n[0], n[1], n[2], n[3]
    nom = np.empty(4)
    nom[0], nom[1], nom[2], nom[3] = n[0], n[1], n[2], n[3]
    return nom


# Strain components of the driver, in the order of the state: xx, yy, xy, zz.
COMPONENTS = ("xx", "yy", "xy", "zz")


def drive(mat: Concrete, strain_path: np.ndarray, free: tuple[str, ...],
          plastic: bool | str = True, damage: bool = True, compressive: bool = False,
          rate: bool = False, targets: np.ndarray | None = None,
          dt: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
    """Strain-driven material point without spin.

    ``strain_path``: (n, 4) prescribed total strains (xx, yy, xy, zz) at each step; components
    named in ``free`` are ignored and solved so that their nominal stress is zero, or equals
    ``targets`` (n, len(free)) when given. ``plastic``: True (Drucker-Prager), False or "cap";
    ``compressive`` and ``rate`` switch on the compressive damage and rate effects (cap only);
    ``dt`` is the time per step (the strain rate is the increment / dt).
    Returns (strains (n, 4) actually followed, nominal stresses (n, 4)); state starts at zero.
    """
    alpha, k = mat.dp
    variant = {True: DRUCKER_PRAGER, False: NO_PLASTICITY, "cap": CAP}[plastic]
    cap = mat.cap_vector() if variant == CAP or rate else np.zeros(22)
    free_idx = [COMPONENTS.index(c) for c in free]
    goal = np.zeros((strain_path.shape[0], len(free_idx))) if targets is None else targets
    state = np.zeros(13)
    eps = np.zeros(4)
    out_eps = np.zeros_like(strain_path)
    out_sig = np.zeros_like(strain_path)
    lam = mat.bulk - 2 * mat.shear / 3
    # Elastic stiffness restricted to the free components: Newton's first guess.
    stiff = np.full((4, 4), lam)
    stiff[[0, 1, 3], [0, 1, 3]] += 2 * mat.shear
    stiff[2, :] = 0
    stiff[:, 2] = 0
    stiff[2, 2] = 2 * mat.shear
    guess_free = np.zeros(len(free_idx))

    def trial(d):
        st = state.copy()
        nom = point_update(st, d[0] / dt, d[1] / dt, d[2] / dt, d[3] / dt, 0.0, dt, mat.bulk,
                           mat.shear, alpha, k, mat.young, mat.eps_0, mat.eps_f, variant,
                           damage, cap, compressive, rate)
        return st, nom

    for n in range(strain_path.shape[0]):
        d = strain_path[n] - eps
        d[2] = 0.5 * d[2] if "xy" not in free else 0.0  # tensor shear = engineering / 2
        if free_idx:
            d[free_idx] = guess_free
            scale = max(abs(d).max(), 1e-14)
            for _ in range(50):
                st, nom = trial(d)
                res = nom[free_idx] - goal[n]
                if np.abs(res).max() < 1e-9 * max(mat.f_c, 1.0):
                    break
                jac = np.empty((len(free_idx), len(free_idx)))
                for a, ia in enumerate(free_idx):
                    dd = d.copy()
                    dd[ia] += 1e-6 * scale
                    jac[:, a] = (trial(dd)[1][free_idx] - goal[n] - res) / (1e-6 * scale)
                if abs(np.linalg.det(jac)) < 1e-12 * abs(np.linalg.det(
                        stiff[np.ix_(free_idx, free_idx)])):
                    jac = stiff[np.ix_(free_idx, free_idx)]
                d[free_idx] -= np.linalg.solve(jac, res)
            guess_free = d[free_idx]
        st, nom = trial(d)
        state[:] = st
        eps = eps + d
        out_eps[n] = eps
        out_sig[n] = nom
    return out_eps, out_sig
