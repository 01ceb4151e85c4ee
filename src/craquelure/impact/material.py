r"""Material point model of the concrete (spec section 2), composed from the effect fragments.

Update order per particle and step (spec section 3): Jaumann trial effective stress
(:mod:`.effects.elasticity`) → Drucker-Prager return (:mod:`.effects.plasticity`) or the
CSCM-like cap return (:mod:`.effects.cap_plasticity`, shear strength scaled by the compressive
damage of :mod:`.effects.compressive_damage`) → Rankine damage and nominal stress
(:mod:`.effects.damage`) → with :mod:`.effects.rate_effects` the viscoplastic blend of the
trial and that inviscid stress. :class:`Concrete` holds the derived
constants.
:func:`drive` is a strain-driven single-point driver (no SPH) with stress-free lateral directions,
used by check 6: the prescribed strain-rate components are imposed, the free ones are found by a
Newton iteration (finite-difference Jacobian) so that the free *nominal* stresses vanish.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numba import njit

from craquelure.impact.effects.cap_plasticity import CapSurface, cap_return, surface_constants
from craquelure.impact.effects.compressive_damage import ductile_damage, softening_strain
from craquelure.impact.effects.damage import damage_update
from craquelure.impact.effects.elasticity import jaumann_trial
from craquelure.impact.effects.plasticity import dp_constants, dp_return
from craquelure.impact.effects.rate_effects import (
    RATE_PARAMS,
    increase_factor,
    rate_constants,
    softening_left,
    strain_rate,
    viscoplastic,
)

# Plasticity variants of the material point (the SPH kernels select them by effect flags).
NO_PLASTICITY, DRUCKER_PRAGER, CAP = 0, 1, 2

# The constants a scene gives the concrete (declared by the effects that read them,
# :mod:`craquelure.impact.effects`; neutral when those are all off).
MATERIAL_CONSTANTS = ("bulk", "shear", "f_c", "f_t", "G_F")


@dataclass(frozen=True)
class Concrete:
    """Derived constants of the concrete model (SI units)."""

    bulk: float
    shear: float
    f_c: float
    f_bc_ratio: float
    f_t: float
    G_F: float
    band: float  # crack-band width l_c
    gfc_ratio: float = 100.0  # G_fc / G_F (compressive damage)

    @property
    def young(self) -> float:
        return 9.0 * self.bulk * self.shear / (3.0 * self.bulk + self.shear)

    @property
    def poisson(self) -> float:
        return (3.0 * self.bulk - 2.0 * self.shear) / (2.0 * (3.0 * self.bulk + self.shear))

    @property
    def dp(self) -> tuple[float, float]:
        return dp_constants(self.f_c, self.f_bc_ratio)

    @property
    def cap(self) -> CapSurface:
        return surface_constants(self.f_c, self.f_bc_ratio)

    @property
    def eps_fc(self) -> float:
        """Plastic strain at full compressive damage (G_fc = gfc_ratio G_F dissipated over l_c
        in uniaxial compression)."""
        return softening_strain(self.f_c, self.G_F, self.band, self.cap, self.gfc_ratio)

    @property
    def rates(self) -> dict[str, float]:
        return rate_constants(self.f_c)

    def cap_vector(self) -> np.ndarray:
        """Constants of :func:`point_update`'s cap/rate branches, in its order (the kernels'
        ``CAP_PARAMS``)."""
        c, r = self.cap, self.rates
        return np.array([c.alpha, c.lam, c.beta, c.theta, c.e, c.X0, c.W, c.D1, c.D2,
                         self.eps_fc, *(r[k] for k in RATE_PARAMS), self.f_t, self.f_c,
                         c.kappa0, c.R])

    @property
    def eps_0(self) -> float:
        return self.f_t / self.young

    @property
    def eps_f(self) -> float:
        return 2.0 * self.G_F / (self.f_t * self.band)

    @property
    def hillerborg_length(self) -> float:
        return self.young * self.G_F / self.f_t**2

    def validate(self) -> None:
        from craquelure.errors import SceneError

        if self.eps_f <= self.eps_0:
            raise SceneError(
                f"material.crack_band_width: the crack band width {self.band:g} m is >= 2 l_ch "
                f"= {2 * self.hillerborg_length:g} m (l_ch = E G_F/f_t^2 from material.G_F, "
                f"material.f_t and the moduli): linear softening would snap back")


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


def standard_concrete(band: float = 0.0048) -> Concrete:
    """Spec Table 1 values (K, G, f_c, f_t, G_F) with l_c = h(0) = 1.2 * 4 mm by default."""
    return Concrete(bulk=14.15e9, shear=12.92e9, f_c=43.1e6, f_bc_ratio=1.16,
                    f_t=0.30 * (43.1 - 8.0) ** (2.0 / 3.0) * 1e6, G_F=83.25, band=band)


__all__ = ["Concrete", "drive", "point_update", "standard_concrete"]
