"""``craquelure check SCENE``: validate, print the resolved scene, the effects and derived
numbers (neighbours, stable step, step count, wall-time estimate)."""

from craquelure.commands import add_scene_arguments
from craquelure.models import model_api
from craquelure.registry import known_effects
from craquelure.scene import load_scene

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
        for key, value in api.derived_numbers(scene).items():
            text = f"{value:.6g}" if isinstance(value, float) else str(value)
            print(f"  {key}: {text}")
    return 0
