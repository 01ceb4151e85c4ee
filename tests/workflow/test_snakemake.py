"""The Snakemake frame: DAGs of the default and paper profiles, lint, the profiles' shape,
and an end-to-end run of ``rule all`` on the CI profile in a temporary copy of the workflow.

The end-to-end test is generic on purpose: whatever rules the models register, every produced
dataset must open with xarray, every figure must be a non-empty PNG, nothing may be left to do
afterwards, and no temporary file may survive.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
import xarray as xr
import yaml

from craquelure.scene import project_root

ROOT = project_root()
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"
ALLOWED_LINT = "Specify a conda environment or container for each rule."


def workflow_copy(dest: Path) -> Path:
    """Snakefile, workflow/ and config/ copied into ``dest`` (no results, no .snakemake)."""
    shutil.copy2(ROOT / "Snakefile", dest / "Snakefile")
    for folder in ("workflow", "config"):
        shutil.copytree(ROOT / folder, dest / folder,
                        ignore=shutil.ignore_patterns("__pycache__", "*.pyc"))
    return dest


def snakemake(cwd: Path, *args: str, timeout: float = 300) -> subprocess.CompletedProcess:
    """Run the venv's Snakemake (the interpreter running the tests) in ``cwd``."""
    env = dict(os.environ)
    env["PATH"] = f"{Path(sys.executable).parent}{os.pathsep}{env.get('PATH', '')}"
    return subprocess.run([sys.executable, "-m", "snakemake", *args], cwd=cwd, env=env,
                          capture_output=True, text=True, timeout=timeout)


def job_stats(text: str) -> dict[str, int]:
    """The 'Job stats' table of a dry run as {rule: count}."""
    lines = text.splitlines()
    start = next(i for i, line in enumerate(lines) if line.strip() == "Job stats:")
    counts: dict[str, int] = {}
    for line in lines[start + 3:]:
        m = re.fullmatch(r"\s*(\S+)\s+(\d+)\s*", line)
        if not m:
            break
        counts[m.group(1)] = int(m.group(2))
    return counts


def profile(name: str) -> dict:
    return yaml.safe_load((ROOT / "config" / f"{name}.yaml").read_text())


@pytest.fixture(scope="module")
def fresh(tmp_path_factory) -> Path:
    return workflow_copy(tmp_path_factory.mktemp("dag"))


@pytest.mark.parametrize("config", ["config", "paper", "ci"])
def test_dry_run_builds_the_dag(fresh, config):
    proc = snakemake(fresh, "-n", "--configfile", f"config/{config}.yaml")
    assert proc.returncode == 0, proc.stdout + proc.stderr
    counts = job_stats(proc.stdout + proc.stderr)
    assert counts["all"] == 1
    # One mass-consistency job per seed of the profile (paper: Table I with 100 seeds).
    n_seeds = profile(config)["drying"]["n_seeds"]
    assert counts["mass_consistency"] == n_seeds
    if config == "paper":
        assert n_seeds == 100
    assert counts["total"] == sum(v for k, v in counts.items() if k != "total")


def test_profiles_have_the_same_sections():
    # Snakemake merges --configfile into the default config/config.yaml: a section or key
    # missing from a profile would silently take the default profile's value.
    default = profile("config")
    for name in ("ci", "paper"):
        other = profile(name)
        assert set(other) == set(default), name
        for section, body in default.items():
            if isinstance(body, dict):
                assert set(other[section]) == set(body), (name, section)
    assert {profile(n)["profile"] for n in ("config", "ci", "paper")} == {
        "default", "ci", "paper"}


def test_lint_reports_only_conda_and_container(fresh):
    proc = snakemake(fresh, "--lint", "--configfile", "config/ci.yaml")
    text = proc.stdout + proc.stderr
    bullets = [line.strip()[2:] for line in text.splitlines()
               if line.lstrip().startswith("* ")]
    unexpected = [b for b in bullets if b.rstrip(":") != ALLOWED_LINT]
    assert unexpected == [], text
    # Lint exits 1 whenever it reports anything; then it must be only the allowed lint.
    assert proc.returncode == 0 or bullets, text
    headers = [line for line in text.splitlines() if line.startswith("Lints for")]
    assert all(h.startswith("Lints for rule ") for h in headers), headers
    assert "Traceback" not in text


# --- end to end on the CI profile ---------------------------------------------------------


@pytest.fixture(scope="module")
def ci_run(tmp_path_factory) -> tuple[Path, subprocess.CompletedProcess]:
    work = workflow_copy(tmp_path_factory.mktemp("e2e"))
    proc = snakemake(work, "--cores", "2", "--configfile", "config/ci.yaml", timeout=1500)
    return work, proc


def test_ci_workflow_runs(ci_run):
    work, proc = ci_run
    assert proc.returncode == 0, proc.stdout[-5000:] + proc.stderr[-5000:]
    # Nothing left to do: every target of `rule all` exists and is up to date.
    again = snakemake(work, "-n", "--configfile", "config/ci.yaml")
    assert again.returncode == 0
    assert "Nothing to be done" in again.stdout + again.stderr, again.stdout + again.stderr


def test_ci_outputs_are_valid(ci_run):
    work, proc = ci_run
    assert proc.returncode == 0
    results = work / "results"
    files = [p for p in results.rglob("*") if p.is_file()]
    datasets = [p for p in files if p.suffix == ".nc"]
    figures = [p for p in files if p.suffix == ".png"]
    assert any(p.parts[-3:-1] == ("mass", "ci") for p in datasets)
    for path in datasets:
        with xr.open_dataset(path) as ds:
            # Provenance (craquelure.provenance) on every dataset, whichever model wrote it.
            for key in ("git_commit", "scene", "version_numpy", "start_time", "wall_time_s"):
                assert key in ds.attrs, (path, key)
            assert ds.sizes, path
    for path in figures:
        data = path.read_bytes()
        assert data[:8] == PNG_MAGIC and len(data) > 1000, path
    # No temporary file survives (io.write_dataset names them .<name>.tmp-<pid>).
    assert [p for p in files if ".tmp" in p.name] == []
    # Everything is written under results/, logs/ and benchmarks/ (plus Snakemake's state).
    allowed = {"Snakefile", "workflow", "config", "results", "logs", "benchmarks", ".snakemake"}
    assert {p.name for p in work.iterdir()} <= allowed
    # The mass-consistency datasets carry what the issue asks for.
    for path in (results / "mass" / "ci").glob("seed*.nc"):
        with xr.open_dataset(path) as ds:
            for key in ("h", "rho0", "box_length", "cg_iterations", "cg_residual"):
                assert key in ds.attrs, (path, key)
            assert ds.attrs["cg_residual"] <= 3e-3
            assert ds.attrs["seed"] == int(path.stem.removeprefix("seed"))
            for name in ("x", "y", "mass"):
                assert ds[name].dims == ("particle",)


def test_ci_validation_report_covers_every_model(ci_run):
    """results/validation.json: claims of all four models, each with a computed verdict."""
    work, proc = ci_run
    assert proc.returncode == 0
    doc = json.loads((work / "results" / "validation.json").read_text())
    assert doc["profile"] == "ci"
    assert {c["model"] for c in doc["claims"]} == {"drying", "impact", "lattice", "softdyn"}
    assert all(c["verdict"] in ("reproduced", "partly", "not reproduced", "inconclusive")
               for c in doc["claims"])
    assert sum(doc["tally"]["all"].values()) == len(doc["claims"])
    html = (work / "results" / "validation.html").read_text()
    assert html.count("<tr>") == len(doc["claims"]) + 1 + len(doc["tally"]) - 1


def test_ci_report_builds(ci_run):
    work, proc = ci_run
    assert proc.returncode == 0
    report = snakemake(work, "--cores", "1", "--configfile", "config/ci.yaml",
                       "--report", "results/report.html")
    assert report.returncode == 0, report.stdout[-3000:] + report.stderr[-3000:]
    html = (work / "results" / "report.html").read_bytes()
    assert len(html) > 10_000 and b"<html" in html[:2000].lower()
