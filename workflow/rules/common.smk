# Helpers shared by all model files (config validation, scene paths, target registry).
import shlex
import sys
from pathlib import Path

from snakemake.utils import validate

from craquelure.scene import load_scene

validate(config, schema="../schemas/config.schema.yaml")
_speed = config["drying"]["speed"]
if isinstance(_speed["t_end_over_t_star"], list) and len(_speed["t_end_over_t_star"]) != len(
    _speed["pis"]
):
    raise ValueError(
        f"config drying.speed.t_end_over_t_star: one number or one value per entry of "
        f"drying.speed.pis ({len(_speed['pis'])}), got {_speed['t_end_over_t_star']}"
    )

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


def all_targets():
    return [path for paths in TARGETS.values() for path in paths]


def archive_outputs():
    """What the archive packs from results/ (targets, claim sources, final datasets)."""
    registries = (TARGETS, CLAIM_SOURCES, DATASETS)
    return sorted(
        {path for registry in registries for paths in registry.values() for path in paths}
    )


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


def seeds(section):
    first = config[section]["first_seed"]
    return list(range(first, first + config[section]["n_seeds"]))


def drying_scene(wildcards):
    return scene_file("drying", wildcards.scene)


def thickness_label(value):
    """H as a wildcard value (scene wildcards have no dots): 0.25 -> 0p25."""
    return f"{value:g}".replace(".", "p")


def thickness_value(wildcards):
    return wildcards.thickness.replace("p", ".")


def thickness_fragments(wildcards):
    """Fragment datasets of the sweep, grouped by H; the scene's own H reuses its runs."""
    sweep = config["drying"]["thickness"]
    own = float(load_scene(scene_file("drying", wildcards.scene)).get("material.thickness"))
    sweep_seeds = seeds("drying")[: sweep["n_seeds"]]
    files = {}
    for value in sweep["values"]:
        label = thickness_label(value)
        folder = wildcards.scene if abs(value - own) < 1e-12 else f"{wildcards.scene}_H{label}"
        files[f"H{label}"] = [
            f"results/drying/{folder}/fragments/seed{seed}.nc" for seed in sweep_seeds
        ]
    return files


def speed_label(pi):
    """Pi = tau/t* as a wildcard value (scene wildcards have no dots): 0.022 -> 0p022."""
    return f"{pi:g}".replace(".", "p")


def speed_end_over_t_star(study, pi):
    """End of the speed run at Pi in units of t*: one number for every speed, or one per
    entry of `pis` (slow drying is expensive per t*, fast drying breaks late in t*)."""
    ends = study["t_end_over_t_star"]
    if not isinstance(ends, list):
        return float(ends)
    by_pi = {speed_label(p): float(e) for p, e in zip(study["pis"], ends, strict=True)}
    return by_pi[speed_label(pi)]


def speed_run_settings(wildcards):
    """`--set` arguments of a drying-speed run: v_r = Pi sigma_Y/tau, tau = eta/(2 mu), the end
    time and the snapshots at the configured fractions of t* = sigma_Y/v_r (those up to the
    run's end)."""
    study = config["drying"]["speed"]
    scene = load_scene(scene_file("drying", wildcards.scene))
    pi = float(wildcards.pi.replace("p", "."))
    tau = scene.get("material.eta") / (2.0 * scene.get("material.lame_mu"))
    sigma_y = scene.get("material.yield_stress")
    t_star = tau / pi
    end = speed_end_over_t_star(study, pi)
    times = ", ".join(
        f"{f * t_star:.6g}" for f in study["times_over_t_star"] if f <= end * (1 + 1e-9)
    )
    items = [
        f"material.drying_rate={pi * sigma_y / tau:.6g}",
        f"outputs.t_end={end * t_star:.6g}",
        f"outputs.times=[{times}]",
        *study.get("set", []),
    ]
    return " ".join(f"--set {shlex.quote(item)}" for item in items)


def speed_fragments(wildcards):
    """Fragment datasets of the drying-speed study, grouped by Pi (inputs P<label>)."""
    study = config["drying"]["speed"]
    study_seeds = seeds("drying")[: study["n_seeds"]]
    return {
        f"P{speed_label(pi)}": [
            f"results/drying/{wildcards.scene}_Pi{speed_label(pi)}/fragments/seed{seed}.nc"
            for seed in study_seeds
        ]
        for pi in study["pis"]
    }
