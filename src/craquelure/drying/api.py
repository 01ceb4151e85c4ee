"""Model API of the drying paste for the CLI: initial state and derived numbers."""

from __future__ import annotations

import math

from craquelure.drying.initial_state import build_initial_state
from craquelure.scene import Scene

# Neighbour-pair visits per second per thread of the drying rate function, measured by
# benchmarks/sph_engine.py on the 2-core development machine (2026-11-22, 7.5e7 at N = 4e4);
# used only for wall-time estimates.
PAIR_VISITS_PER_S_PER_THREAD = 7.5e7
RK4_REAL_AXIS, ABM4_REAL_AXIS = 2.785, 1.285
EVALS_PER_STEP = {"rk4": 4, "abm4": 2, "rk2": 2}

__all__ = ["build_initial_state", "derived_numbers", "run"]


def viscous_spectral_radius(scene: Scene) -> float:
    """Estimate 6.7 eta/(rho0 h^2) of the viscous operator (drying spec section 8)."""
    eta = scene.get("material.eta", 0.0) if scene.has("viscosity") else 0.0
    return 6.7 * eta / (scene.get("material.rho0") * scene.get("numerics.h") ** 2)


def stable_time_step(scene: Scene) -> float:
    """Largest stable step of the scene's integrator, from the viscous and acoustic limits."""
    radius = viscous_spectral_radius(scene)
    integrator = scene.get("numerics.integrator")
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
    neighbours = n * math.pi * h * h / length**2 - 1
    dt = scene.get("numerics.dt")
    steps = math.ceil(scene.get("outputs.t_end") / dt)
    evals = EVALS_PER_STEP[scene.get("numerics.integrator")]
    # two pair passes per evaluation over the Verlet list (radius 1.1 h: 1.21x the pairs in h)
    pair_visits = steps * evals * 2 * n * 1.21 * neighbours
    return {
        "particle spacing L/sqrt(N)": length / math.sqrt(n),
        "h / spacing": h / (length / math.sqrt(n)),
        "neighbours per particle": neighbours,
        "viscous spectral radius": viscous_spectral_radius(scene),
        "stable time step": stable_time_step(scene),
        "time step": dt,
        "steps": steps,
        "rate evaluations": steps * evals,
        "estimated wall time, 1 thread [s]": pair_visits / PAIR_VISITS_PER_S_PER_THREAD,
    }


def run(scene: Scene, out, seed: int = 0, init=None, resume: bool = False, **checkpoints):
    from craquelure.drying.run import run as run_drying

    return run_drying(scene, out, seed=seed, init=init, resume=resume, **checkpoints)
