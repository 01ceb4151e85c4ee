"""``craquelure check SCENE``: validate, print the resolved scene, the effects and derived
numbers (neighbours, stable step, step count, wall-time estimate)."""

import numpy as np

from craquelure import api
from craquelure.commands import add_scene_arguments
from craquelure.registry import known_effects

NAME = "check"
HELP = "validate a scene and print it resolved, with its effects and derived numbers"


def add_arguments(parser) -> None:
    add_scene_arguments(parser)


def main(args) -> int:
    scene = api.load_scene(args.scene, args.overrides)
    print(f"# scene {scene.name} (model {scene.model}): valid")
    print(scene.text.rstrip())
    print("\n# effects")
    known = known_effects(scene.model)
    for name in scene.effects:
        print(f"  {name:<16} {known[name].description}")
    numbers = api.check(scene)
    if numbers:
        print("\n# derived numbers")
        for key, value in numbers.items():
            print(f"  {key}: {format_number(value)}")
    api.warn_if_long(scene, threads=1)
    return 0


def format_number(value) -> str:
    if isinstance(value, api.Uncomputable):
        return f"cannot be computed ({value})"
    if isinstance(value, float | np.floating):
        return f"{value:.6g}" if np.isfinite(value) else f"cannot be computed ({value})"
    if isinstance(value, tuple):
        return "(" + ", ".join(format_number(v) for v in value) + ")"
    return str(value)
