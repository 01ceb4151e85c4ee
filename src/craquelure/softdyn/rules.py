"""Soft Dynamics scene rules a schema cannot state and the memory a run needs; called by
:mod:`craquelure.scene_rules` (``scene_problems``, ``memory_estimate``)."""

import math

from craquelure.errors import SceneError
from craquelure.scene_rules import SceneView, lookup, steps_problem
from craquelure.softdyn import studies
from craquelure.softdyn.initial_state import build


def scene_problems(data: dict) -> list[str]:
    out = []
    view = SceneView(data)
    if not view.has("lubrication_normal"):
        out.append("effects: softdyn needs 'lubrication_normal' (the film carries the normal "
                   "force in series with the elastic response; without it a pair has no normal "
                   "coupling)")
    if view.get("numerics.deflection_rule") == "literal" and not (
            view.has("hertz") and view.has("lubrication_tangential")):
        out.append("numerics.deflection_rule: 'literal' only differs from 'corotating' with "
                   "both 'hertz' and 'lubrication_tangential'")
    t_end = float(lookup(data, "outputs.t_end"))
    dt = view.optional("numerics.dt")  # heun's step
    if dt is not None and dt > t_end:
        out.append(f"numerics.dt: {dt!r} is not allowed; the step must not be longer than "
                   f"outputs.t_end = {t_end!r} (the run would take no step)")
    elif dt is not None and lookup(data, "numerics.integrator") == "heun":
        out += filter(None, [steps_problem("numerics.dt", t_end, dt)])
    window = lookup(data, "study.window")
    if window and window[0] >= window[1]:
        out.append(f"study.window: {window!r} must be increasing")
    try:
        validate_run_setup(view)
    except SceneError as exc:
        out.append(str(exc))
    return out


def validate_run_setup(view: SceneView) -> None:
    """What Soft Dynamics checks while building a run (effects, stop rule, loads, study
    lists), done here so that ``check`` refuses what ``run`` would."""
    kind = view.get("study.kind")
    build(view).stop_function()
    if kind == "sweep":
        studies.sweep_grid(view)
    elif kind == "phase":
        studies.phase_points(view)
    elif kind == "accuracy" and not (view.get("study.rtol") or view.get("study.dt")):
        raise SceneError("study.rtol / study.dt: an accuracy study needs at least one list")


def memory_estimate(data: dict) -> tuple[float, str]:
    samples = int(lookup(data, "outputs.n_samples"))
    grid = math.prod(max(1, len(lookup(data, f"study.{key}")))
                     for key in ("h0", "reduced_force", "fh_over_fv", "rtol", "dt"))
    need = samples * 64 * 8 * grid + 1e6
    return need, f"{samples} samples x {grid} study points"
