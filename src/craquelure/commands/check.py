"""``craquelure check SCENE``: validate, print the resolved scene, the effects and derived
numbers (neighbours, stable step, step count, wall-time estimate)."""

import sys

import numpy as np

from craquelure.commands import add_scene_arguments
from craquelure.models import model_api
from craquelure.registry import known_effects
from craquelure.scene import load_scene
from craquelure.throughput import long_run_warning

NAME = "check"
HELP = "validate a scene and print it resolved, with its effects and derived numbers"


def add_arguments(parser) -> None:
    add_scene_arguments(parser)


def main(args) -> int:
    scene = load_scene(args.scene, args.overrides)
    print(f"# scene {scene.name} (model {scene.model}): valid")
    print(scene.text.rstrip())
    print("\n# effects")
    known = known_effects(scene.model)
    for name in scene.effects:
        print(f"  {name:<16} {known[name].description}")
    api = model_api(scene.model)
    if hasattr(api, "derived_numbers"):
        print("\n# derived numbers")
        for key, value in derived_numbers(api, scene).items():
            print(f"  {key}: {format_number(value)}")
    warn_if_long(api, scene, threads=1)
    return 0


def warn_if_long(api, scene, threads: int) -> None:
    """Print :func:`~craquelure.throughput.long_run_warning` on stderr when the scene's
    predicted wall time exceeds an hour (nothing when it cannot be predicted: the derived
    numbers say why)."""
    if not hasattr(api, "workload"):
        return
    try:
        with np.errstate(all="ignore"):
            message = long_run_warning(scene.model, api.workload(scene), threads)
    except Exception:  # noqa: BLE001 - advisory only; derived_numbers reports the failure
        return
    if message:
        print(message, file=sys.stderr)


def derived_numbers(api, scene) -> dict[str, object]:
    """The model's derived numbers; never raises for a valid scene: numbers that cannot be
    computed (overflow, division by zero, too large to build) are reported as such."""
    try:
        with np.errstate(all="ignore"):
            return dict(api.derived_numbers(scene))
    except (ArithmeticError, ValueError, MemoryError) as exc:
        return {"(all)": Uncomputable(f"{type(exc).__name__}: {exc}")}


class Uncomputable(str):
    """A derived number that cannot be computed, with the reason."""


def format_number(value) -> str:
    if isinstance(value, Uncomputable):
        return f"cannot be computed ({value})"
    if isinstance(value, float | np.floating):
        return f"{value:.6g}" if np.isfinite(value) else f"cannot be computed ({value})"
    if isinstance(value, tuple):
        return "(" + ", ".join(format_number(v) for v in value) + ")"
    return str(value)
