"""Drying-paste scene rules a schema cannot state, the memory a run needs, and what an
``--init`` state must match; called by :mod:`craquelure.scene_rules` (``scene_problems``,
``memory_estimate``) and by the drying API (``initial_state_problems``)."""

import math

from craquelure.drying.integrators import REAL_AXIS_LIMIT
from craquelure.scene_rules import SceneView, lookup, steps_problem

# Snapshots of a run whose scene gives no outputs.times: this many, equally spaced up to t_end.
SNAPSHOTS_WITHOUT_TIMES = 10


def viscous_spectral_radius(scene) -> float:
    """Estimate 6.7 eta/(rho0 h^2) of the viscous operator (drying spec section 8); 0 without
    the viscosity effect (which requires eta)."""
    return (6.7 * scene.get("material.eta") / (scene.get("material.rho0")
                                               * scene.get("numerics.h") ** 2)
            if scene.has("viscosity") else 0.0)


def run_step(data: dict) -> float:
    """The step a drying run takes: ``numerics.dt`` halved while above 0.6 of the viscous
    stability limit (``numerics.adapt_dt``, drying spec section 8); as the engine does, with the
    spec's estimate 6.7 eta/(rho0 h^2) of the viscous spectral radius. rkc2 with adapt_dt:
    ``step_control.dt_max``, the step between removal events."""
    dt = float(lookup(data, "numerics.dt"))
    if not lookup(data, "numerics.adapt_dt"):
        return dt
    if lookup(data, "numerics.integrator") == "rkc2":
        return float(lookup(data, "numerics.step_control.dt_max"))
    radius = viscous_spectral_radius(SceneView(data))
    if not radius > 0:
        return dt
    limit = REAL_AXIS_LIMIT[lookup(data, "numerics.integrator")] / radius
    while dt > 0.6 * limit and dt > 0:
        dt *= 0.5
    return dt


def scene_problems(data: dict) -> list[str]:
    out = []
    t_end = float(lookup(data, "outputs.t_end"))
    times = SceneView(data).optional("outputs.times")  # absent: equally spaced up to t_end
    late = [] if times is None else [t for t in times if t > t_end * (1 + 1e-12)]
    if late:
        out.append(f"outputs.times: {late[0]!r} is after outputs.t_end = {t_end!r}; snapshot "
                   f"times must lie in [0, t_end]")
    dt = float(lookup(data, "numerics.dt"))
    if dt > t_end:
        out.append(f"numerics.dt: {dt!r} is not allowed; the step must not be longer than "
                   f"outputs.t_end = {t_end!r} (the run would take no step)")
    elif problem := steps_problem("numerics.dt", t_end, run_step(data)):
        out.append(problem)
    h, length = float(lookup(data, "numerics.h")), float(lookup(data, "domain.box_length"))
    radius = h * (1 + float(lookup(data, "numerics.neighbour_skin")))
    if lookup(data, "domain.periodic") and length < 2 * radius:
        out.append(f"domain.box_length: {length!r} is not allowed; the periodic box must be at "
                   f"least twice the neighbour search radius numerics.h x (1 + "
                   f"numerics.neighbour_skin) = {radius:g}")
    for k, band in enumerate(lookup(data, "particles.excluded_bands")):
        if band["lo"] >= band["hi"]:
            out.append(f"particles.excluded_bands[{k}]: lo = {band['lo']!r} must be below "
                       f"hi = {band['hi']!r}")
    return out


def memory_estimate(data: dict) -> tuple[float, str]:
    n = int(lookup(data, "particles.n"))
    length, h = float(lookup(data, "domain.box_length")), float(lookup(data, "numerics.h"))
    skin = float(lookup(data, "numerics.neighbour_skin"))
    pairs = n * min(n, n * math.pi * (h * (1 + skin)) ** 2 / length**2 + 1)
    shepard = float(lookup(data, "numerics.mass_solve.shepard_spacing")) * h
    mesh = (length / shepard) ** 2
    times = SceneView(data).optional("outputs.times")
    snaps = (SNAPSHOTS_WITHOUT_TIMES if times is None else len(times)) + 1
    rsa = 0.0
    if lookup(data, "particles.placement") == "rsa":  # cell grid of side min-separation / sqrt 2
        rsa = 2 * n / float(lookup(data, "particles.rsa_min_separation")) ** 2
        mesh = max(mesh, rsa)
    # state (9 vars) x (4 ABM4 history + 4 stages + working copies) + 30 per-particle arrays;
    # pair list and kernel values (3 x 8 bytes); mesh field and its labels; snapshots
    need = n * 8 * (9 * 12 + 30) + pairs * 24 + mesh * 8 * 3 + snaps * n * 8 * 8
    what = "RSA grid" if rsa >= mesh and rsa > 0 else "Shepard mesh"
    return need, f"{n} particles, {pairs:.3g} neighbour pairs, a {mesh:.3g}-cell {what}"


def initial_state_problems(scene, ds, path) -> list[str]:
    """An ``--init`` state (of the drying model: :func:`craquelure.io.read_dataset` checks) must
    hold the scene's particles in the scene's box (else its provenance describes another run)."""
    out = []
    n, length = int(scene.get("particles.n")), float(scene.get("domain.box_length"))
    n_file = int(ds.sizes.get("particle", 0))
    if n_file != n:
        out.append(f"{path}: holds {n_file} particles; the scene's particles.n is {n}")
    box = ds.attrs.get("box_length")
    if box is not None and not math.isclose(float(box), length, rel_tol=1e-12):
        out.append(f"{path}: box length {float(box):g}; the scene's domain.box_length is "
                   f"{length:g}")
    return out
