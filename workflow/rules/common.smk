# Helpers shared by all model files (config validation, scene paths, target registry).
import shlex
import sys

from snakemake.utils import validate


validate(config, schema="../schemas/config.schema.yaml")

# The CLI of the interpreter running Snakemake (the project's .venv), whatever PATH says.
CRAQUELURE = f"{sys.executable} -m craquelure"

# Each model file registers the final outputs it contributes to `rule all`.
TARGETS = {}


def all_targets():
    return [path for paths in TARGETS.values() for path in paths]


def scene_file(model, scene):
    """Scene YAML of a model, e.g. config/scenes/drying/default.yaml."""
    return f"config/scenes/{model}/{scene}.yaml"


def scene_overrides(section):
    """`--set` arguments from a model section's `set` list (profile-level overrides)."""
    return " ".join(f"--set {shlex.quote(item)}" for item in config[section].get("set", []))


def seeds(section):
    first = config[section]["first_seed"]
    return list(range(first, first + config[section]["n_seeds"]))


def drying_scene(wildcards):
    return scene_file("drying", wildcards.scene)
