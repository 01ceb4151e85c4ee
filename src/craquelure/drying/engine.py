"""Drying-paste SPH engine: state, specialised rate function, neighbour list, fracture and the
integrator loop (drying spec sections 2-8). No file I/O here (see :mod:`craquelure.drying.api`).

- The rate function is compiled for the scene's effect set only (:mod:`craquelure.codegen`).
- Neighbours: CSR Verlet list of radius h(1 + skin), rebuilt when a particle has moved more
  than skin h / 2 since the last build and at every checkpoint (so a resumed run repeats the
  summation order of an uninterrupted one: bit-identical results). Removed particles stay
  listed until the next rebuild; with zero mass they add exactly 0.
- Fracture (:mod:`craquelure.drying.effects.fracture`): after each accepted step, with the
  rates of the new state, particles whose criterion stress s exceeds sigma_Y are removed
  (alive = 0, mass = 0, v = 0) and the multistep integrator restarts with RK4.
- Onset diagnostics (spec open doubt 7): before any removal each particle's mean stress is
  sigma_bar_I = kappa_I F + (what is left of the initial stress), F the drying stress, so the
  first removal comes at t*/kappa_max (source criterion). :meth:`DryingEngine.onset_kappa`
  gives kappa_max and the criterion's max_I s_I/F while nothing has been removed and
  F >= 20 a sigma_Y (a = ``material.initial_stress_amplitude``: the initial stress, at most
  a sigma_Y, then shifts kappa by <= 0.05, small against kappa_max - 1); NaN otherwise.
- Time step, fixed-step integrators (abm4, rk4, rk2): the scene's dt; at the start and every
  ``spectral_check_every`` steps the viscous spectral radius is re-estimated by power iteration
  and dt is halved while it exceeds 0.6 of the integrator's real-axis limit (spec section 8).
- Time step, ``rkc2`` (:mod:`craquelure.drying.integrators`): the stage count follows
  1.2 x the viscous spectral radius (power iteration every ``step_control.spectral_radius_every``
  steps), so the step is not bound by the viscous limit. With ``adapt_dt`` the step is
  error-controlled: the local error estimate is scaled per state row so that 1 means
  ``tolerance`` x sigma_s in stress, where sigma_s = sigma_Y (else the largest stress the run
  reaches): sigma_e by tol sigma_s, positions by tol sigma_s h/M (a position error that changes
  the strain over h by tol sigma_s/M, M = lambda + 2 mu), velocities by tol sigma_s
  min(h/eta, 1/(rho0 c_L)) (viscous stress eta v/h, acoustic impedance rho0 c_L), density by
  tol rho0 sigma_s/M; the norm is the max over present particles. A removal event limit keeps
  the linearly predicted mean stress of every particle from passing sigma_Y by more than
  ``removal_tolerance`` sigma_Y within one step,
  dt <= min_I (sigma_Y (1 + tol_r) - sigma_bar_I) / (d sigma_bar_I/dt)_+,
  with the rates from the last accepted step, so steps shrink while cracks run and grow again
  between removal events. Steps end exactly on ``stop_at`` (the next snapshot, set by the run
  loop) and never exceed ``step_control.dt_max``.
- Guards: NaN/inf anywhere in the state, or a kinetic energy above ``energy_runaway_factor``
  times the energy the stresses can supply, stop the run with :class:`SimulationDiverged`."""

from __future__ import annotations

import math

import numpy as np

from craquelure.codegen import effect_flags, specialise
from craquelure.drying import kernel_template as template
from craquelure.drying.effects.fracture import criterion_stress, particles_to_remove
from craquelure.drying.integrators import (
    REAL_AXIS_LIMIT,
    RKC_SPECTRAL_SAFETY,
    StepController,
    Stepper,
    rkc2_error_norm,
    rkc_stages,
)
from craquelure.errors import SimulationDiverged
from craquelure.registry import energy_bound, parameter_vector
from craquelure.runner import Divergence, diverged, non_finite, runaway
from craquelure.scene import Scene
from craquelure.sph.kernels import kernel_kind
from craquelure.sph.neighbours import Box, cluster_pairs

NVAR = template.NVAR
KAPPA_AMPLITUDE_FACTOR = 20.0  # kappa from F >= 20 a sigma_Y (module docstring)
X, Y, VX, VY, RHO, SXX, SYY, SXY = range(8)


def compile_rate(effects, kernel: str):
    """The rate module specialised on ``effects`` (effects without a kernel flag, such as
    ``fracture``, act between steps)."""
    flags: dict[str, bool | int] = effect_flags("drying", effects)
    flags["KERNEL"] = kernel_kind(kernel)
    return specialise(template.__name__, flags, "drying")


def parameters(scene: Scene) -> np.ndarray:
    """The rate kernel's parameter vector, as the effects declare it
    (:func:`craquelure.registry.parameter_vector`): each effect's constants when it is on, their
    neutral values when it is off."""
    return parameter_vector("drying", scene)


class DryingEngine:
    """Holds the state of one drying-paste run and advances it."""

    def __init__(self, scene: Scene, x, y, mass, rho, sigma_e, vx=None, vy=None) -> None:
        self.scene = scene
        self.n = n = len(x)
        self.box_length = float(scene.get("domain.box_length"))
        self.h = float(scene.get("numerics.h"))
        self.box = Box.square(self.box_length)
        self.state = np.zeros((NVAR, n))
        self.state[X], self.state[Y] = x, y
        self.state[VX] = 0.0 if vx is None else vx
        self.state[VY] = 0.0 if vy is None else vy
        self.state[RHO] = rho
        self.state[SXX:SXY + 1] = sigma_e
        self.x0, self.y0 = np.array(x, float), np.array(y, float)
        self.mass = np.array(mass, float)
        self.alive = np.ones(n, np.bool_)
        self.t, self.step_count = 0.0, 0
        self.dt = float(scene.get("numerics.dt"))
        self.params = parameters(scene)
        self.effects = scene.effects
        self.fracture = scene.has("fracture")
        # no yield stress (only without fracture, which requires it): nothing is removed, and
        # kappa is recorded from the first F > 0
        sigma_y = scene.optional("material.yield_stress")
        self.yield_stress = math.inf if sigma_y is None else float(sigma_y)
        self.fracture_measure = str(scene.get("material.fracture_stress_measure"))
        self.kappa_min_f = (KAPPA_AMPLITUDE_FACTOR
                            * float(scene.get("material.initial_stress_amplitude"))
                            * (0.0 if sigma_y is None else float(sigma_y)))
        kernel = scene.get("numerics.kernel")
        self.rate_module = compile_rate(self.effects, kernel)
        self.viscous_module = compile_rate(("viscosity",), kernel)
        self.stepper = Stepper(scene.get("numerics.integrator"),
                               scene.get("numerics.restart_steps"))
        self.skin = float(scene.get("numerics.neighbour_skin")) * self.h
        self.stop_at = math.inf
        self.controller = (StepController.from_scene(scene, self.dt) if self.stepper.adaptive
                           else None)
        self.overwrite_velocity = bool(scene.get("numerics.xsph_overwrite_velocity"))
        self.n_removed = self.evaluations = self.stage_evaluations = self.viscous_evaluations = 0
        self.stress = np.zeros((3, n))
        self._build_neighbours()
        self.f_current = self.evaluate(self.state, self.t)
        self.energy_bound = self._energy_bound()
        if self.controller is not None:
            self.controller.error_scale = self._error_scale()

    def _build_neighbours(self, state: np.ndarray | None = None) -> None:
        """The neighbour list of ``state`` (default: the current state)."""
        state = self.state if state is None else state
        self.pairs = cluster_pairs(state[X], state[Y], self.h + self.skin, self.box,
                                   template.LANES, self.alive)
        self._built_x = state[X].copy()
        self._built_y = state[Y].copy()
        self.neighbour_builds = getattr(self, "neighbour_builds", 0) + 1

    def evaluate(self, state: np.ndarray, t: float, stress: np.ndarray | None = None):
        """dY/dt at (state, t); the total stress goes to ``stress`` (default: self.stress)."""
        moved2 = (state[X] - self._built_x) ** 2 + (state[Y] - self._built_y) ** 2
        if self.skin <= 0 or moved2.max(initial=0.0) > (0.5 * self.skin) ** 2:
            self._build_neighbours(state)
        out = np.empty_like(state)
        self.rate_module.rate(state, t, self.mass, self.alive, self.x0, self.y0, self.pairs,
                              self.params, out,
                              self.stress if stress is None else stress)
        self.evaluations += 1
        return out

    def _stage_rate(self, state: np.ndarray, t: float) -> np.ndarray:
        return self.evaluate(state, t, stress=np.empty_like(self.stress))

    @property
    def mean_stress(self) -> np.ndarray:
        """tr(sigma)/2 of the total stress of the current state (0 for removed particles)."""
        return 0.5 * (self.stress[0] + self.stress[1])

    @property
    def criterion(self) -> np.ndarray:
        """The fracture criterion's stress measure of the current total stress."""
        return criterion_stress(self.stress, self.fracture_measure)

    def drying_stress(self) -> float:
        """F = min(v_r t, cap) of the current time (0 without the drying effect)."""
        return (min(self.params[template.P_VR] * self.t, self.params[template.P_DRYCAP])
                if self.scene.has("drying") else 0.0)

    def onset_kappa(self) -> tuple[float, float]:
        """(max_I sigma_bar_I / F, max_I s_I / F) before the first removal once F >= 20 a
        sigma_Y (module docstring); (nan, nan) otherwise."""
        f = self.drying_stress()
        if self.n_removed > 0 or f <= 0 or f < self.kappa_min_f or not self.alive.any():
            return math.nan, math.nan
        return (float(self.mean_stress[self.alive].max()) / f,
                float(self.criterion[self.alive].max()) / f)

    def kinetic_energy(self) -> float:
        return float(0.5 * np.sum(self.mass * (self.state[VX] ** 2 + self.state[VY] ** 2)))

    def elastic_energy(self) -> float:
        """sum_I V_I w_I, w = (tr s)^2 / (8 (lambda + mu)) + (s_dev : s_dev) / (4 mu) for the
        elastic stress s of a 2D isotropic solid with Lame constants lambda, mu."""
        lam, mu = self.params[template.P_LAMBDA], self.params[template.P_MU]
        if mu <= 0:
            return 0.0
        sxx, syy, sxy = self.state[SXX], self.state[SYY], self.state[SXY]
        tr = sxx + syy
        dev2 = (0.5 * (sxx - syy)) ** 2 * 2 + 2 * sxy**2
        w = tr**2 / (8 * (lam + mu)) + dev2 / (4 * mu)
        volume = np.where(self.alive, self.mass / self.state[RHO], 0.0)
        return float(np.sum(volume * w))

    def momentum(self) -> tuple[float, float]:
        return (float(np.sum(self.mass * self.state[VX])),
                float(np.sum(self.mass * self.state[VY])))

    def _energy_bound(self) -> float:
        """Energy the stresses and the effects can supply over the run (the runaway guard's)."""
        lam, mu = self.params[template.P_LAMBDA], self.params[template.P_MU]
        t_end = float(self.scene.get("outputs.t_end"))
        sigma = max(float(np.abs(self.state[SXX:SXY + 1]).max(initial=0.0)),
                    self.params[template.P_VR] * t_end,
                    self.yield_stress if math.isfinite(self.yield_stress) else 0.0)
        modulus = max(min(mu, lam + mu), 1e-12)
        area = self.box_length**2
        return (self.kinetic_energy() + area * sigma**2 / (2 * modulus) + 1e-300
                + energy_bound("drying", self))

    def health(self) -> Divergence | None:
        """NaN/inf in the state, or kinetic energy above ``numerics.energy_runaway_factor``
        times the energy the stresses can supply (the runner's guards)."""
        rows = ("x", "y", "vx", "vy", "rho", "sigma_e_xx", "sigma_e_yy", "sigma_e_xy")
        bad = non_finite({rows[r]: self.state[r] for r in range(NVAR)})
        if bad is not None:
            return bad
        factor = float(self.scene.get("numerics.energy_runaway_factor"))
        per_particle = 0.5 * self.mass * (self.state[VX] ** 2 + self.state[VY] ** 2)
        return runaway(float(per_particle.sum()), factor * self.energy_bound,
                       f"kinetic energy at dt = {self.dt:g} (limit {factor:g} x the energy the "
                       f"stresses can supply; try a smaller numerics.dt)", per_particle)

    def check_health(self) -> None:
        """Raise :class:`SimulationDiverged` if :meth:`health` fails (runs outside the runner)."""
        bad = self.health()
        if bad is not None:
            raise diverged("drying", bad, self.step_count, self.t, "eta/lambda")

    def viscous_spectral_radius(self, iterations: int = 40, seed: int = 12345) -> float:
        """Largest |eigenvalue| of the linear map v -> dv/dt of the viscous term alone, by
        power iteration on the current configuration."""
        if not self.scene.has("viscosity") or self.params[template.P_ETA] == 0:
            return 0.0
        rng = np.random.default_rng(seed)
        probe = self.state.copy()
        probe[SXX:SXY + 1] = 0.0
        v = rng.standard_normal((2, self.n)) * self.alive
        out = np.empty_like(probe)
        stress = np.empty_like(self.stress)
        radius = 0.0
        for _ in range(iterations):
            v /= np.linalg.norm(v)
            probe[VX], probe[VY] = v
            self.viscous_module.rate(probe, 0.0, self.mass, self.alive, self.x0, self.y0,
                                     self.pairs, self.params, out, stress)
            self.viscous_evaluations += 1
            v = out[VX:VY + 1].copy()
            radius = float(np.linalg.norm(v))
        return radius

    def control_time_step(self) -> float | None:
        """Halve dt while it exceeds 0.6 of the stability limit; returns the new dt if changed."""
        if not self.scene.get("numerics.adapt_dt") or self.stepper.adaptive:
            return None
        radius = self.viscous_spectral_radius()
        if radius <= 0:
            return None
        limit = REAL_AXIS_LIMIT[self.stepper.name] / radius
        if self.dt <= 0.6 * limit:
            return None
        while self.dt > 0.6 * limit:
            self.dt *= 0.5
        self.stepper.restart()
        return self.dt

    def step(self) -> int:
        """Advance one step; returns the number of particles removed in it. A kernel's
        arithmetic failure is the guard's stop, :class:`SimulationDiverged`, not a traceback:
        the rate kernel uses numpy's error model (a division by zero gives inf/NaN, which
        :meth:`health` reports); an ArithmeticError raised elsewhere is caught here."""
        try:
            removed = self._rkc_step() if self.stepper.adaptive else self._step()
        except ArithmeticError as exc:
            raise SimulationDiverged(
                f"drying run diverged at t = {self.t:.6g} (step {self.step_count}, dt = "
                f"{self.dt:.6g}): the state can no longer be computed ({type(exc).__name__}: "
                f"{exc})") from exc
        if self.overwrite_velocity:
            self.state[VX] = self.f_current[X]
            self.state[VY] = self.f_current[Y]
        return removed

    def _step(self) -> int:
        self.state = self.stepper.step(self.state, self.f_current, self.t, self.dt,
                                       self._stage_rate)
        self.t += self.dt
        self.step_count += 1
        self.f_current = self.evaluate(self.state, self.t)
        return self.remove_overstressed() if self.fracture else 0

    def _error_scale(self) -> np.ndarray:
        """Per-row scales of the local error (engine docstring): 1 = tolerance x sigma_s."""
        p = self.params
        lam, mu, eta = p[template.P_LAMBDA], p[template.P_MU], p[template.P_ETA]
        rho0 = float(self.scene.get("material.rho0"))
        sigma = (self.yield_stress if math.isfinite(self.yield_stress)
                 else max(p[template.P_VR] * float(self.scene.get("outputs.t_end")),
                          float(np.abs(self.state[SXX:SXY + 1]).max(initial=0.0))))
        sigma = sigma if sigma > 0 else 1.0
        modulus = lam + 2 * mu if lam + 2 * mu > 0 else 1.0
        velocity = min(self.h / eta if eta > 0 else math.inf,
                       1.0 / math.sqrt(rho0 * modulus))
        scale = np.empty(NVAR)
        scale[X] = scale[Y] = sigma * self.h / modulus
        scale[VX] = scale[VY] = sigma * velocity
        scale[RHO] = rho0 * sigma / modulus
        scale[SXX:SXY + 1] = sigma
        return self.controller.tolerance * scale

    def _removal_step_limit(self, before: np.ndarray, dt: float) -> float:
        """Largest next step for which no particle's linearly predicted mean stress passes
        sigma_Y by more than removal_tolerance sigma_Y."""
        if not self.fracture or not math.isfinite(self.yield_stress):
            return math.inf
        now = self.criterion
        # Particles already above sigma_Y (loaded by this step's removals) go at the end of the
        # next step whatever its size; the limit concerns those still below.
        rising = self.alive & (now > before) & (now <= self.yield_stress)
        if not rising.any():
            return math.inf
        rate = (now[rising] - before[rising]) / dt
        room = self.yield_stress * (1.0 + self.controller.removal_tolerance) - now[rising]
        return float(np.min(room / rate))

    def _rkc_step(self) -> int:
        ctrl = self.controller
        if self.step_count % ctrl.spectral_every == 0:
            ctrl.spectral_radius = RKC_SPECTRAL_SAFETY * self.viscous_spectral_radius()
        while True:
            dt = min(ctrl.dt_next, ctrl.dt_event) if ctrl.adapt else self.dt
            remaining = self.stop_at - self.t
            landing = remaining <= dt * (1.0 + 1e-9)
            if landing:
                dt = remaining
            elif ctrl.adapt and remaining < 2.0 * dt:
                dt = 0.5 * remaining
            self.stepper.stages = rkc_stages(dt, ctrl.spectral_radius)
            new = self.stepper.step(self.state, self.f_current, self.t, dt, self._stage_rate)
            t_new = self.stop_at if landing else self.t + dt
            stress = np.empty_like(self.stress)
            f_new = self.evaluate(new, t_new, stress=stress)
            self.stage_evaluations += self.stepper.stages
            if not ctrl.adapt:
                break
            err = rkc2_error_norm(self.state, new, self.f_current, f_new, dt,
                                  ctrl.error_scale, self.alive)
            if ctrl.propose(err, dt):
                break
            if ctrl.dt_next < ctrl.dt_floor:
                raise diverged("drying", Divergence(
                    "time step", f"the rkc2 error-controlled step fell below "
                    f"numerics.step_control.dt_min = {ctrl.dt_floor:g} (scaled error "
                    f"{err:.3g}); loosen numerics.step_control.tolerance or use abm4"),
                    self.step_count, self.t, "eta/lambda")
        before = self.criterion
        self.state, self.f_current, self.stress = new, f_new, stress
        self.t, self.dt = t_new, dt
        self.step_count += 1
        removed = self.remove_overstressed() if self.fracture else 0
        if removed:
            ctrl.forget()
        ctrl.dt_event = self._removal_step_limit(before, dt) if ctrl.adapt else math.inf
        return removed

    def time_tolerance(self) -> float:
        """How close to an output time counts as on it: half a fixed step; adaptive steps end
        exactly on ``stop_at``."""
        if self.controller is not None and self.controller.adapt:
            return 1e-9 * max(1.0, abs(self.t))
        return 0.5 * self.dt

    def remove_overstressed(self) -> int:
        doomed = particles_to_remove(self.criterion, self.alive, self.yield_stress)
        if doomed.size == 0:
            return 0
        self.alive[doomed] = False
        self.mass[doomed] = 0.0
        self.state[VX:VY + 1, doomed] = 0.0
        self.n_removed += doomed.size
        # No neighbour rebuild: a removed particle left in the list has m = 0, hence V = 0,
        # and adds exactly 0 to every pair sum (its own row is skipped); the next regular
        # rebuild drops it. (A rebuild per removal step cost more than an evaluation.)
        self.f_current = self.evaluate(self.state, self.t)
        self.stepper.restart()
        return int(doomed.size)

    def rebuild(self) -> None:
        """Fresh neighbour list and rate of the current state (checkpoint/resume points)."""
        self._build_neighbours()
        self.f_current = self.evaluate(self.state, self.t)
