"""Concrete-impact scene rules a schema cannot state and the memory a run needs; called by
:mod:`craquelure.scene_rules` (``scene_problems``, ``memory_estimate``)."""

import math

from craquelure.errors import SceneError
from craquelure.impact.api import concrete
from craquelure.scene_rules import MAX_STEPS, SceneView, lookup


def scene_problems(data: dict) -> list[str]:
    out = []
    t_end = float(lookup(data, "outputs.t_end"))
    late = [s for s in lookup(data, "outputs.snapshot_times") if s > t_end * (1 + 1e-12)]
    if late:
        out.append(f"outputs.snapshot_times: {late[0]!r} is after outputs.t_end = {t_end!r}; "
                   f"snapshot times must lie in [0, t_end] (the end time is always stored)")
    h_min, h_max = lookup(data, "numerics.h_min"), lookup(data, "numerics.h_max")
    if h_min >= h_max:
        out.append(f"numerics.h_min: {h_min!r} must be below numerics.h_max = {h_max!r}")
    if lookup(data, "domain.dim") == 3:
        if lookup(data, "domain.plane") == "stress":
            out.append("domain.plane: 'stress' is not allowed with domain.dim = 3; allowed "
                       "values: strain (the default; a 3D body has no plane assumption)")
        if lookup(data, "particles.shape") == "rings":
            out.append("particles.shape: 'rings' is not allowed with domain.dim = 3; allowed "
                       "values: disc, rectangle")
    if lookup(data, "particles.shape") == "rings":
        inner, outer = (lookup(data, f"particles.rings.{k}_radius") for k in ("inner", "outer"))
        if inner >= outer:
            out.append(f"particles.rings.inner_radius: {inner!r} must be below "
                       f"particles.rings.outer_radius = {outer!r}")
    precrack, layouts = lookup(data, "particles.precrack"), lookup(data, "precracks")
    if precrack != "none" and precrack not in layouts:
        out.append(f"particles.precrack: {precrack!r} is not allowed; allowed values: none, "
                   f"{', '.join(layouts)} (the layouts under precracks)")
    if "damage" in data["effects"]:
        try:
            concrete(SceneView(data)).validate()
        except ArithmeticError as exc:
            out.append(f"material.f_t, material.G_F: the softening law cannot be computed from "
                       f"these magnitudes ({exc})")
        except SceneError as exc:
            out.append(str(exc))
    series = lookup(data, "outputs.series_dt")
    if t_end / series > MAX_STEPS:
        out.append(f"outputs.series_dt: {series!r} gives {t_end / series:.3g} samples")
    return out


def memory_estimate(data: dict) -> tuple[float, str]:
    d = int(lookup(data, "particles.diameter_cells"))
    n = d * int(lookup(data, "particles.height_cells")) \
        if lookup(data, "particles.shape") == "rectangle" else math.pi / 4 * d * d
    three_d = lookup(data, "domain.dim") == 3
    if three_d:
        n *= int(lookup(data, "particles.thickness_cells"))
    kappa, hf, h_max, skin = (float(lookup(data, f"numerics.{key}"))
                              for key in ("kappa", "h_factor", "h_max", "neighbour_skin"))
    support = 2 * kappa * hf * max(1.0, h_max) * (1 + skin)
    pairs = n * min(n, 4.0 / 3.0 * math.pi * support**3 if three_d else math.pi * support**2)
    samples = float(lookup(data, "outputs.t_end")) / float(lookup(data, "outputs.series_dt")) + 2
    snaps = len(lookup(data, "outputs.snapshot_times")) + 1
    need = n * 8 * 80 + pairs * 32 + samples * 17 * 8 * 2 + snaps * n * 5 * 8
    return need, f"{n:.3g} particles, {pairs:.3g} neighbour pairs, {samples:.3g} series samples"
