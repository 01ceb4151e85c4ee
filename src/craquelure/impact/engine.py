"""SPH engine of the impact model: effect-specialised kernels, kick-drift-kick leapfrog,
diagnostics (spec section 3).

Specialisation: :func:`kernels_for` compiles :mod:`.kernel_template` for the scene's effect set
with :func:`craquelure.codegen.specialise` (flags from the effect registry; numba folds the
branches of absent effects away).

One step of length Δt (the accelerations a_n at x_n are known):

1. half kick v_{n+1/2} = v_n + a_n Δt/2; kinematic v_y ≥ 0 for constrained particles (before
   the kick: arrival, energy removed; after it: the base's reaction, no work);
2. material pass with v_{n+1/2} at x_n: L, ρ, h, stress, internal energy to n+1;
3. drift x_{n+1} = x_n + v_{n+1/2} Δt; kinematic floor for constrained contact particles;
4. neighbour list at x_{n+1} (radius 2 max h; r < 2 h_ij checked in the loops);
5. artificial stress tensors, force pass (AV with v_{n+1/2}), base contact → a_{n+1};
6. half kick v_{n+1} = v_{n+1/2} + a_{n+1} Δt/2, constrained as in 1;
7. next Δt = cfl min h/(c + |v| + 1.2(α c + β max|μ|)), ≤ dt_max.

Energy balance: E = KE + Σ m e_int + E_AV + E_AS + E_pen + E_kin,removed, compared with E(0):
e_int integrates the nominal stress power σ:D/ρ from the material pass; E_AV and E_AS are the
pairwise powers of the force pass (rectangle rule); E_pen = Σ ½ k g². The internal energy
splits into the secant elastic energy, the plastic work, the damage dissipation and the rest
(:meth:`Engine.energies`). NaN/inf or E > factor·E(0) raises
:class:`~craquelure.errors.SimulationDiverged` (time, step, what).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from numba import njit

from craquelure.codegen import effect_flags, specialise
from craquelure.errors import SimulationDiverged
from craquelure.impact import kernel_template
from craquelure.impact.effects.contact_bulk import bulk_stiffness
from craquelure.impact.material import Concrete
from craquelure.registry import parameter_vector
from craquelure.runner import Divergence, diverged, non_finite, runaway
from craquelure.sph.neighbours import Box, neighbour_list, neighbour_list_points


def kernels_for(effects, periodic: bool, plane_stress: bool, dim: int):
    """The kernel module compiled for this effect set and dimension."""
    if dim not in (2, 3):
        raise ValueError(f"dim: {dim!r} is not allowed; allowed values: 2, 3")
    flags = effect_flags("impact", effects) | {
        "PERIODIC": bool(periodic), "PLANE_STRESS": bool(plane_stress), "DIM": int(dim)}
    return specialise(kernel_template.__name__, flags, "impact")


@njit(cache=True)
def mass_sum(m, q):
    """Σ m_i q_i in a plain loop: inside a step, np.dot would start BLAS's own thread pool."""
    total = 0.0
    for i in range(m.size):
        total += m[i] * q[i]
    return total


# An engine constant, not a scene parameter: accelerations, stresses, pair powers below it (SI)
# are set to 0 where produced, out of subnormal numbers
FLUSH_BELOW = 1e-100


@dataclass
class Settings:
    """Numbers the engine needs (SI), the resolved scene's (:func:`.api.settings`)."""

    material: Concrete
    rho0: float
    spacing: float
    effects: tuple[str, ...]
    av_alpha: float
    av_beta: float
    as_epsilon: float
    cfl: float
    dt_max: float
    as_n: float
    h_min: float
    h_max: float
    base_y: float
    contact_radius: float  # units of spacing
    contact_a: float
    kinematic_ratio: float
    energy_runaway_factor: float
    neighbour_skin: float  # units of max h
    plane_stress: bool  # 2D plane stress (sigma_zz = 0) instead of plane strain
    dim: int  # 2: plane strain/stress slice (per metre of thickness); 3: full 3D
    periodic_box: tuple[float, ...] | None = None  # tests: (lx, ly) in 2D, (lx, ly, lz) in 3D
    flush_below: float = FLUSH_BELOW

    @property
    def wave_speed(self) -> float:
        """P-wave speed: sqrt((K + 4G/3)/rho), plane stress sqrt(E/((1-nu^2) rho))."""
        m = self.material
        if self.plane_stress:
            return math.sqrt(m.young / ((1.0 - m.poisson**2) * self.rho0))
        return math.sqrt((m.bulk + 4.0 * m.shear / 3.0) / self.rho0)

    def params(self) -> np.ndarray:
        """The kernel's parameter vector (:func:`craquelure.registry.parameter_vector`)."""
        m = self.material
        alpha, k = m.dp
        lx, ly, lz = (*(self.periodic_box or ()), 0.0, 0.0, 0.0)[:3]
        cap = m.cap_vector() if {"cap_plasticity", "rate_effects"} & set(self.effects) else 0.0
        return parameter_vector("impact", values=dict(
            bulk=m.bulk, shear=m.shear, young=m.young, alpha_dp=alpha, k_dp=k,
            eps_0=m.eps_0, eps_f=m.eps_f, wave_speed=self.wave_speed,
            av_alpha=self.av_alpha, av_beta=self.av_beta, as_epsilon=self.as_epsilon,
            as_n=self.as_n, spacing=self.spacing, h_min=self.h_min, h_max=self.h_max,
            base_y=self.base_y, contact_radius=self.contact_radius * self.spacing,
            contact_a=self.contact_a,
            k_bulk=bulk_stiffness(self.contact_a, m.bulk, self.spacing, self.dim),
            kinematic_ratio=self.kinematic_ratio, lx=lx, ly=ly, lz=lz,
            flush_below=self.flush_below, cap=cap))


@dataclass
class State:
    """Struct of arrays of the particles (SI). 2D: z and vz are zeros and the stresses have
    the columns xx, yy, xy, zz; 3D (``dim = 3``): xx, yy, xy, zz, xz, yz."""

    x: np.ndarray
    y: np.ndarray
    vx: np.ndarray
    vy: np.ndarray
    m: np.ndarray
    rho: np.ndarray
    h: np.ndarray
    h0: np.ndarray
    dim: int  # 2, or 3 when z is given (State.grid)
    sig: np.ndarray = field(default=None)   # effective stress xx, yy, xy, zz
    nom: np.ndarray = field(default=None)   # nominal stress
    eps_max: np.ndarray = field(default=None)
    dmg: np.ndarray = field(default=None)
    epsp: np.ndarray = field(default=None)
    wp: np.ndarray = field(default=None)    # plastic work per unit mass
    epsv: np.ndarray = field(default=None)  # plastic compaction (cap model)
    eint: np.ndarray = field(default=None)  # internal energy per unit mass
    eel: np.ndarray = field(default=None)   # elastic energy per unit mass
    wd: np.ndarray = field(default=None)    # damage dissipation per unit mass
    z: np.ndarray = field(default=None)     # 3D: out-of-plane position (2D: zeros)
    vz: np.ndarray = field(default=None)

    def __post_init__(self):
        n = self.x.size
        ncomp = 4 if self.dim == 2 else 6
        for name, shape in (("sig", (n, ncomp)), ("nom", (n, ncomp)), ("eps_max", n), ("dmg", n),
                            ("epsp", n), ("wp", n), ("epsv", n), ("eint", n), ("eel", n),
                            ("wd", n), ("z", n), ("vz", n)):
            if getattr(self, name) is None:
                setattr(self, name, np.zeros(shape))
        for name in ("x", "y", "z", "vx", "vy", "vz", "m", "rho", "h", "h0"):
            # always a private copy: the engine updates these arrays in place
            setattr(self, name, np.array(getattr(self, name), dtype=np.float64, copy=True))

    @classmethod
    def grid(cls, x, y, vx, vy, m, rho0, h0, z=None, vz=0.0):
        """Particles at rest density and h(0); 3D when ``z`` is given."""
        n = np.asarray(x).size
        return cls(x=x, y=y, vx=np.broadcast_to(vx, n).copy(), vy=np.broadcast_to(vy, n).copy(),
                   m=m, rho=np.full(n, rho0), h=np.full(n, h0), h0=np.full(n, h0), z=z,
                   vz=np.broadcast_to(vz, n).copy(), dim=2 if z is None else 3)


class Engine:
    """Leapfrog KDK integration of one state with one effect set."""

    def __init__(self, settings: Settings, state: State):
        self.s = settings
        self.state = state
        if state.dim != settings.dim:
            raise ValueError(f"state of dimension {state.dim} given to a {settings.dim}D engine")
        self.k = kernels_for(settings.effects, settings.periodic_box is not None,
                             settings.plane_stress, settings.dim)
        self.prm = self.s.params()
        n = state.x.size
        self.ax, self.ay, self.az, self.pav, self.pas, self.mumax = (np.zeros(n) for _ in range(6))
        self.rst = np.zeros((n, 3 if settings.dim == 2 else 6))
        self.kinematic = np.zeros(n, np.bool_)
        self.t = 0.0
        self.step_count = 0
        self.e_av = self.e_as = self.e_pen = 0.0
        self.e_kin = 0.0          # kinetic energy removed by the kinematic constraint
        self.impulse = 0.0        # total momentum (y) given by the base
        self.impulse_kin = 0.0
        self.force = 0.0          # penalty force at the current positions
        self.force_peak = self.max_penetration = 0.0
        self.dt = self.s.dt_max
        self._neighbours()
        self._forces(self.dt)
        self.dt = self._time_step()
        self.dt_min_seen = self.dt
        self.e0 = self.total_energy()

    # --- pieces of a step -------------------------------------------------------------
    def _neighbours(self, force: bool = True):
        """Verlet list with a skin (open boxes): rebuilt when a particle has moved more than
        half the skin, or a support 2 h_ij could exceed the listed radius; the kernels check
        r < 2 h_ij, so the skin changes which pairs are visited, never the result."""
        st = self.state
        periodic = self.s.periodic_box is not None
        if not force and not periodic:
            moved = (st.x - self._x_built) ** 2 + (st.y - self._y_built) ** 2
            if self.s.dim == 3:
                moved += (st.z - self._z_built) ** 2
            moved = np.max(moved)
            if (math.sqrt(moved) < 0.5 * self._skin
                    and 2.0 * float(st.h.max()) + math.sqrt(moved) * 2.0 < self._radius):
                return
        skin = 0.0 if periodic else self.s.neighbour_skin * float(st.h.max())
        radius = 2.0 * float(st.h.max()) * (1.0 + 1e-9) + skin
        if self.s.dim == 3:
            self.offsets, self.index = neighbour_list_points(
                np.column_stack([st.x, st.y, st.z]), radius, self.s.periodic_box)
        else:
            box = (Box(*self.s.periodic_box, True, 0.0, 0.0) if periodic
                   else Box.around(st.x, st.y, radius))
            self.offsets, self.index = neighbour_list(st.x, st.y, radius, box)
        self._x_built, self._y_built, self._z_built = st.x.copy(), st.y.copy(), st.z.copy()
        self._skin, self._radius = skin, radius

    def _forces(self, dt):
        st, k = self.state, self.k
        k.artificial_stress_pass(st.nom, st.rho, self.prm, self.rst)
        k.force_pass(st.x, st.y, st.z, st.vx, st.vy, st.vz, st.m, st.rho, st.h, st.nom, self.rst,
                     self.offsets, self.index, self.prm, self.ax, self.ay, self.az, self.pav,
                     self.pas, self.mumax)
        self.force, self.e_pen = k.contact_pass(st.y, st.m, self.ay, dt, self.prm,
                                                self.kinematic)
        gap = self.prm[k.P_BASE] + self.prm[k.P_RC] - st.y[st.m > 0]
        if gap.size:
            self.max_penetration = max(self.max_penetration, float(gap.max()))

    def _time_step(self):
        st = self.state
        return min(self.s.dt_max, self.k.time_step(st.h, st.vx, st.vy, st.vz, self.mumax,
                                                   self.prm, self.s.cfl))

    def _kick(self, dt):
        """Half kick with the kinematic constraint on both sides of it (so the material pass and the
        drift never see a motion into the base). Returns (momentum to the base, energy removed)."""
        st, k = self.state, self.k
        mom, ke = k.kinematic_velocity(st.y, st.vy, st.m, self.kinematic, self.prm, True)
        st.vx += 0.5 * dt * self.ax
        st.vy += 0.5 * dt * self.ay
        if self.s.dim == 3:
            st.vz += 0.5 * dt * self.az
        mom_reaction, _ = k.kinematic_velocity(st.y, st.vy, st.m, self.kinematic, self.prm,
                                               False)
        return mom + mom_reaction, ke

    def step(self, dt: float | None = None) -> None:
        """One KDK step; a kernel's arithmetic failure (a density or length collapsed to zero,
        an overflow) stops it as :class:`SimulationDiverged`, not a traceback."""
        try:
            self._step(dt)
        except ArithmeticError as exc:
            raise SimulationDiverged(
                f"t = {self.t:.6g} s, step {self.step_count}: the state can no longer be "
                f"computed ({type(exc).__name__}: {exc}); the run diverged") from exc

    def _step(self, dt: float | None) -> None:
        st, k = self.state, self.k
        dt = self.dt if dt is None else dt
        f_old = self.force
        self.e_av += dt * mass_sum(st.m, self.pav)
        self.e_as += dt * mass_sum(st.m, self.pas)
        mom_half, ke_half = self._kick(dt)
        k.material_pass(st.x, st.y, st.z, st.vx, st.vy, st.vz, st.m, st.rho, st.h, st.h0, st.sig,
                        st.nom, st.eps_max, st.dmg, st.epsp, st.wp, st.epsv, st.eint, st.eel,
                        st.wd, self.offsets, self.index, dt, self.prm)
        st.x += dt * st.vx
        st.y += dt * st.vy
        if self.s.dim == 3:
            st.z += dt * st.vz
        for axis, length in zip("xyz", self.s.periodic_box or (), strict=False):
            coord = getattr(st, axis)
            np.mod(coord, length, out=coord)  # periodic tests: back into the box
        k.kinematic_position(st.y, self.kinematic, self.prm)
        self._neighbours(force=False)
        self._forces(dt)
        mom, ke = self._kick(dt)
        mom += mom_half
        self.impulse += 0.5 * (f_old + self.force) * dt + mom
        self.impulse_kin += mom
        self.e_kin += ke + ke_half
        self.force_peak = max(self.force_peak, self.force)
        self.t += dt
        self.step_count += 1
        self.dt = self._time_step()
        # the stability step, not the last step shortened to hit an output time
        self.dt_min_seen = min(self.dt_min_seen, self.dt)

    # --- diagnostics --------------------------------------------------------------------
    def kinetic_energy(self) -> float:
        st = self.state
        v2 = st.vx**2 + st.vy**2
        if self.s.dim == 3:
            v2 = v2 + st.vz**2
        return 0.5 * float(np.dot(st.m, v2))

    def energies(self) -> dict[str, float]:
        st = self.state
        e_int, e_el, e_p, e_d = (float(np.dot(st.m, e)) for e in (st.eint, st.eel, st.wp, st.wd))
        # damage: booked by its own law (the secant energy the damage growth releases);
        # unattributed: what the internal energy holds beyond elastic, plastic and damage;
        # it sits in fully damaged points (the stress split is no potential's gradient when
        # their axes turn; docs/impact.md, energy partition)
        return {"kinetic": self.kinetic_energy(), "internal": e_int, "elastic": e_el,
                "plastic": e_p, "damage": e_d, "unattributed": e_int - e_el - e_p - e_d,
                "viscous": self.e_av,
                "artificial_stress": self.e_as, "penalty": self.e_pen,
                "kinematic_removed": self.e_kin}

    def total_energy(self) -> float:
        e = self.energies()
        return (e["kinetic"] + e["internal"] + e["viscous"] + e["artificial_stress"]
                + e["penalty"] + e["kinematic_removed"])

    def balance_error(self) -> float:
        return (self.total_energy() - self.e0) / self.e0 if self.e0 > 0 else 0.0

    def momentum(self) -> tuple[float, ...]:
        """(p_x, p_y), and p_z in 3D."""
        st = self.state
        p = (float(np.dot(st.m, st.vx)), float(np.dot(st.m, st.vy)))
        return p + (float(np.dot(st.m, st.vz)),) if self.s.dim == 3 else p

    def health(self) -> Divergence | None:
        """The runner's guards: NaN/inf, energy above the runaway factor x E(0), dt collapsed."""
        st = self.state
        bad = non_finite({name: getattr(st, name)
                          for name in ("x", "y", "z", "vx", "vy", "vz", "rho", "h")}
                         | {"stress": st.sig.T})
        if bad is not None:
            return bad
        if self.e0 > 0:
            ke = 0.5 * st.m * (st.vx**2 + st.vy**2 + st.vz**2)
            bad = runaway(self.total_energy(), self.s.energy_runaway_factor * self.e0,
                          "total energy [J/m]" if self.s.dim == 2 else "total energy [J]",
                          ke + st.m * st.eint)
            if bad is not None:
                return bad
        if self.dt < 1e-6 * self.s.dt_max and self.dt < 1e-12:
            return Divergence("time step", f"dt collapsed to {self.dt:.3g} s")
        return None

    def check_health(self) -> None:
        """Raise :class:`SimulationDiverged` when :meth:`health` fails (outside the runner)."""
        bad = self.health()
        if bad is not None:
            raise diverged("impact", bad, self.step_count, self.t, "s")
