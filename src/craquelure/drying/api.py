"""Model API of the drying paste for the CLI: initial state and derived numbers."""

from __future__ import annotations

import math

from craquelure.drying.initial_state import build_initial_state
from craquelure.scene import Scene
from craquelure.sph.integrators import RKC_SPECTRAL_SAFETY, rkc_stages
from craquelure.throughput import prediction_lines

RK4_REAL_AXIS, ABM4_REAL_AXIS = 2.785, 1.285
EVALS_PER_STEP = {"rk4": 4, "abm4": 2, "rk2": 2}

__all__ = ["build_initial_state", "derived_numbers", "run"]


def evaluations_per_step(scene: Scene, dt: float) -> int:
    """Rate evaluations per step: fixed for abm4/rk4/rk2; rkc2's stage count at step dt
    (between removal events its controlled step sits at step_control.dt_max)."""
    integrator = scene.get("numerics.integrator")
    if integrator == "rkc2":
        return rkc_stages(dt, RKC_SPECTRAL_SAFETY * viscous_spectral_radius(scene))
    return EVALS_PER_STEP[integrator]


def viscous_spectral_radius(scene: Scene) -> float:
    """Estimate 6.7 eta/(rho0 h^2) of the viscous operator (drying spec section 8)."""
    eta = scene.get("material.eta", 0.0) if scene.has("viscosity") else 0.0
    return 6.7 * eta / (scene.get("material.rho0") * scene.get("numerics.h") ** 2)


def stable_time_step(scene: Scene) -> float:
    """Largest stable step of the scene's integrator, from the viscous and acoustic limits
    (rkc2: its stages cover the viscous spectrum, so the cap ``step_control.dt_max``)."""
    radius = viscous_spectral_radius(scene)
    integrator = scene.get("numerics.integrator")
    if integrator == "rkc2":
        return float(scene.get("numerics.step_control")["dt_max"])
    axis = {"rk4": RK4_REAL_AXIS, "abm4": ABM4_REAL_AXIS, "rk2": 2.0}[integrator]
    limits = [axis / radius] if radius > 0 else []
    if scene.has("elasticity"):
        lam, mu = scene.get("material.lame_lambda"), scene.get("material.lame_mu")
        c_l = math.sqrt((lam + 2 * mu) / scene.get("material.rho0"))
        # Largest SPH wavenumber of this kernel ~ 3.2/h (16 at h = 0.2, spec section 8).
        limits.append(2.785 / (c_l * 3.2 / scene.get("numerics.h")))
    return min(limits) if limits else math.inf


def derived_numbers(scene: Scene) -> dict[str, object]:
    length, n, h = (scene.get("domain.box_length"), scene.get("particles.n"),
                    scene.get("numerics.h"))
    dt, steps, evals = _run_steps(scene)
    return {
        "particle spacing L/sqrt(N)": length / math.sqrt(n),
        "h / spacing": h / (length / math.sqrt(n)),
        "neighbours per particle": n * math.pi * h * h / length**2 - 1,
        "viscous spectral radius": viscous_spectral_radius(scene),
        "stable time step": stable_time_step(scene),
        "time step (numerics.dt)": scene.get("numerics.dt"),
        "time step of the run (halved below 0.6 of the viscous limit)": dt,
        "steps": steps,
        "rate evaluations": steps * evals,
        **prediction_lines("drying", workload(scene)),
    }


def _run_steps(scene: Scene) -> tuple[float, int, int]:
    """The step the run takes (numerics.adapt_dt halves it), the step count and the rate
    evaluations per step."""
    from craquelure.scene_rules import drying_run_step

    dt = drying_run_step(scene.data)
    return dt, math.ceil(scene.get("outputs.t_end") / dt), evaluations_per_step(scene, dt)


def workload(scene: Scene) -> dict[str, float]:
    """Rate evaluations, particles and listed neighbours (Verlet radius 1.1 h: 1.21x the
    pairs within h) of a run, for the throughput model."""
    length, n, h = (scene.get("domain.box_length"), scene.get("particles.n"),
                    scene.get("numerics.h"))
    _, steps, evals = _run_steps(scene)
    return {"units": steps * evals, "particles": n,
            "neighbours": 1.21 * (n * math.pi * h * h / length**2 - 1)}


def run(scene: Scene, out, seed: int = 0, init=None, resume: bool = False, **checkpoints):
    from craquelure.drying.run import run as run_drying

    return run_drying(scene, out, seed=seed, init=init, resume=resume, **checkpoints)
