"""Snakemake catalog conventions: config/README.md documents every config key and profile,
results/README.md is committed while generated results are not, the catalog file, LICENSE,
snakefmt-clean rules, and local rules for aggregation, figures and reports."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import yaml

from craquelure.scene import project_root
from tests.workflow.test_snakemake import snakemake, workflow_copy

ROOT = project_root()
# Rules that only aggregate, draw or report (seconds each): never queued on a cluster.
LOCAL_RULES = {
    "all", "archive", "validation_report",
    "drying_campaign", "drying_summary", "drying_figures", "drying_accuracy_figure",
    "drying_thickness", "drying_thickness_figure", "drying_speed", "drying_speed_figure",
    "drying_speed_study", "drying_speed_scene",
    "drying_onset_study", "drying_criterion_study", "drying_criterion_summary",
    "drying_validation", "drying_transition", "drying_transition_figure",
    "drying_transition_study", "drying_kappa_figure",
    "drying_published", "drying_published_companions", "drying_publish_tables", "published",
    "impact_summary", "impact_figures", "impact_judged_figures", "impact_published",
    "lattice_glen_figure", "lattice_scene_figure",
    "softdyn_sweep", "softdyn_fig4", "softdyn_fig3", "softdyn_pair_figure", "softdyn_summary",
}


def schema_keys(node: dict, prefix: str = "") -> set[str]:
    """Dotted names of every property in the config schema (with $ref'd definitions)."""
    keys = set()
    for name, sub in node.get("properties", {}).items():
        keys.add(f"{prefix}{name}")
        keys |= schema_keys(sub, f"{prefix}{name}.")
    return keys


def test_config_readme_names_every_key_and_profile():
    schema = yaml.safe_load((ROOT / "workflow/schemas/config.schema.yaml").read_text())
    campaign = schema["definitions"]["campaign"]
    keys = schema_keys(schema)
    for section in ("drying", "impact"):
        keys |= {f"{section}.{k}" for k in campaign["properties"]}
    text = (ROOT / "config/README.md").read_text()
    documented = set(re.findall(r"`([a-z_.]+)`", text))
    missing = []
    for key in sorted(keys):
        leaf = key.split(".", 1)[1] if "." in key else key
        # documented as the full dotted key, as its name in the section's table, or (nested)
        # as parent.leaf
        tail = ".".join(key.split(".")[-2:])
        parent = any(d.startswith(f"{leaf}.") for d in documented)  # e.g. `thickness.values`
        if not {key, leaf, tail} & documented and not parent:
            missing.append(key)
    assert missing == [], missing
    for config in (ROOT / "config").glob("*.yaml"):
        assert f"`{config.name}`" in text, config.name
    for profile in (ROOT / "profiles").iterdir():
        assert f"`profiles/{profile.name}/`" in text, profile.name


def test_results_readme_is_committed_and_results_are_not():
    tracked = subprocess.run(["git", "ls-files", "results"], cwd=ROOT, capture_output=True,
                             text=True, check=True).stdout.split()
    # results/published/ holds the archived results of long campaigns, and only those
    assert [p for p in tracked if not p.startswith("results/published/")] == ["results/README.md"]
    ignored = subprocess.run(["git", "check-ignore", "-q", "results/drying/ci/run/seed1.nc"],
                             cwd=ROOT)
    assert ignored.returncode == 0
    text = (ROOT / "results/README.md").read_text()
    for folder in ("mass/", "drying/", "impact/", "lattice/", "softdyn/", "archive/",
                   "published/"):
        assert f"`{folder}" in text, folder


def test_catalog_file_and_license():
    catalog = yaml.safe_load((ROOT / ".snakemake-workflow-catalog.yml").read_text())
    usage = catalog["usage"]
    assert usage["report"] is True
    assert set(usage["software-stack-deployment"]) == {"conda", "apptainer", "apptainer+conda"}
    assert "--workflow-profile profiles/slurm" in usage["mandatory-flags"]["desc"]
    assert (ROOT / "LICENSE").read_text().startswith("MIT License")


def test_rules_are_snakefmt_clean():
    files = [ROOT / "Snakefile", *sorted((ROOT / "workflow/rules").glob("*.smk"))]
    proc = subprocess.run([sys.executable, "-m", "snakefmt", "--check", *map(str, files)],
                          cwd=ROOT, capture_output=True, text=True)
    assert proc.returncode == 0, proc.stdout + proc.stderr


def declared_local_rules() -> set[str]:
    names = set()
    for path in [ROOT / "Snakefile", *(ROOT / "workflow/rules").glob("*.smk")]:
        text = path.read_text()
        for block in re.findall(r"^localrules:\n((?:    \w+,?\n)+)", text, re.M):
            names |= set(re.findall(r"\w+", block))
        names |= set(re.findall(r"^rule (\w+):\n    localrule: True", text, re.M))
    return names


def test_aggregation_figure_and_report_rules_are_local(tmp_path):
    """Declared local (Snakemake itself rejects a local rule that does not exist), and the
    rest of the rules are what a cluster should run: simulations and per-run analysis."""
    assert declared_local_rules() == LOCAL_RULES
    work = workflow_copy(tmp_path)
    proc = snakemake(work, "--list-rules")
    assert proc.returncode == 0, proc.stderr[-3000:]
    rules = set(proc.stdout.split())
    assert LOCAL_RULES <= rules
    queued = rules - LOCAL_RULES
    assert {"drying_run", "mass_consistency", "impact_run", "lattice_run", "softdyn_run",
            "drying_fragments", "lattice_glen_point", "softdyn_sweep_batch"} <= queued
    assert not {r for r in queued if r.endswith(("_figure", "_figures", "_summary"))}


def test_workflow_copy_has_what_a_clone_has(tmp_path):
    work = workflow_copy(tmp_path)
    assert (work / "profiles/default/config.yaml").is_file()
    assert Path(work / "Snakefile").read_text().count("include:") >= 8
