# Helpers shared by all model files (config validation, scene paths, target registry).
import shlex
import sys
from pathlib import Path

from snakemake.utils import validate

validate(config, schema="../schemas/config.schema.yaml")

# The CLI of the interpreter running Snakemake (the project's .venv), whatever PATH says.
CRAQUELURE = f"{sys.executable} -m craquelure"

# Each model file registers the final outputs it contributes to `rule all`.
TARGETS = {}


# Each model file also registers the analysis outputs its claims are computed from
# (craquelure.<model>.claims), the inputs of rule validation_report.
CLAIM_SOURCES = {}


# And its final datasets (runs and aggregates) beyond those two registries: rule archive packs
# targets, claim sources and these.
DATASETS = {}


def claim_sources(wildcards):
    return {model: paths for model, paths in CLAIM_SOURCES.items() if paths}


def drying_claim_sources(wildcards):
    """Every drying claim source (rule drying_validation), read when the job is planned, after
    all rules registered theirs."""
    return CLAIM_SOURCES["drying"]


def claim_figures(wildcards):
    """Every figure the models register as targets: the validation summary shows, per claim,
    the one that decides it (craquelure.validation.figure_for)."""
    return [path for path in all_targets() if path.endswith(".png")]


def all_targets():
    return [path for paths in TARGETS.values() for path in paths]


def archive_outputs():
    """What the archive packs from results/ (targets, claim sources, final datasets)."""
    registries = (TARGETS, CLAIM_SOURCES, DATASETS)
    return sorted(
        {path for registry in registries for paths in registry.values() for path in paths}
    )


def archive_reports():
    """The Snakemake report, when it was built before the archive (`make run` builds it
    first): packed with the figures so a reviewer can open both."""
    return [path for path in ("results/report.html",) if Path(path).is_file()]


def archive_configs():
    """Config files, scenes and workflow profiles (what the outputs were made from)."""
    paths = [*Path("config").rglob("*.yaml"), *Path("profiles").glob("*/config.yaml")]
    return sorted(str(path) for path in paths)


def scene_file(model, scene):
    """Scene YAML of a model, e.g. config/scenes/drying/default.yaml."""
    return f"config/scenes/{model}/{scene}.yaml"


def scene_overrides(section):
    """`--set` arguments from a model section's `set` list (profile-level overrides)."""
    return " ".join(f"--set {shlex.quote(item)}" for item in config[section].get("set", []))
