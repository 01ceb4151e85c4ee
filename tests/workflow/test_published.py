"""Archived ensembles (results/published/<name>/): every committed folder matches its manifest
and its figures, summary and validation rows are rebuilt from its committed tables by target
`published` without a simulation; and the publishing steps, end to end on the CI run's drying
ensemble."""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from craquelure.archive import verify
from craquelure.drying.published import publish
from tests.workflow.test_snakemake import snakemake, workflow_copy

ROOT = Path(__file__).resolve().parents[2]
PUBLISHED = sorted(p.parent for p in (ROOT / "results/published").glob("*/MANIFEST.sha256"))


def _judged(summary: dict) -> dict:
    """What a summary decides: its checks for both labellings and the sizing, no provenance."""
    return {key: summary.get(key) for key in ("n_seeds", "box_length", "n_particles", "t_star",
                                              "fracture_stress_measure", "checks",
                                              "checks_open_image", "campaign_sizing")}


@pytest.mark.parametrize("folder", PUBLISHED, ids=[p.name for p in PUBLISHED])
def test_committed_folder_matches_its_manifest(folder):
    problems, checked = verify(folder)
    assert problems == [] and checked > 0


@pytest.mark.slow
@pytest.mark.parametrize("folder", PUBLISHED, ids=[p.name for p in PUBLISHED])
def test_rebuilt_from_the_committed_tables(tmp_path, folder):
    """The figures, summary and rows rebuilt by target `published` from the committed tables
    decide as the committed ones do, number for number."""
    work = workflow_copy(tmp_path)
    shutil.copytree(folder, work / "results/published" / folder.name)
    proc = snakemake(work, "published", "--cores", "1", timeout=1800)
    assert proc.returncode == 0, proc.stderr[-3000:]
    rebuilt = work / "results/drying_published" / folder.name
    summary = json.loads((rebuilt / "summary.json").read_text())
    assert _judged(summary) == _judged(json.loads((folder / "summary.json").read_text()))
    rows = json.loads((rebuilt / "validation.json").read_text())["claims"]
    assert rows == json.loads((folder / "validation.json").read_text())["claims"]
    for png in (folder / "figures").glob("*.png"):
        assert (rebuilt / "figures" / png.name).stat().st_size > 10_000


@pytest.mark.slow
def test_publish_end_to_end_on_the_ci_ensemble(ci_run, tmp_path):
    """Tables of the CI run's drying ensemble, installed, rebuilt, verified: both labellings
    judged, and a changed file is caught by `craquelure verify`. (In a copy of the run's
    drying outputs: the CI run's own folder stays as the workflow wrote it.)"""
    ci_work, proc = ci_run
    assert proc.returncode == 0, proc.stderr[-3000:]
    work = workflow_copy(tmp_path)
    for sub in ("results/drying/ci", "results/mass/ci",
                *(f"benchmarks/results/{kind}/ci" for kind in
                  ("mass_consistency", "drying_run", "drying_fragments"))):
        shutil.copytree(ci_work / sub, work / sub)
    tables = work / "results/drying/ci/published"
    run = snakemake(work, str(tables.relative_to(work)), "--cores", "1", "--configfile",
                    "config/ci.yaml")
    assert run.returncode == 0, run.stderr[-3000:]
    dest = work / "results/published/ci-test"
    publish(tables, None, dest)
    rebuild = snakemake(work, "published", "--cores", "1")
    assert rebuild.returncode == 0, rebuild.stderr[-3000:]
    publish(tables, work / "results/drying_published/ci-test", dest)
    summary = json.loads((dest / "summary.json").read_text())
    assert summary["checks"]["labelling"] == "periodic"
    assert summary["checks_open_image"]["labelling"] == "open"
    assert summary["source_labelling"]["labelling"] == "open"
    claims = json.loads((dest / "validation.json").read_text())["claims"]
    assert sum("open-image labelling" in c["source"] for c in claims) == 3
    provenance = json.loads((dest / "provenance.json").read_text())
    assert provenance["seeds"] == [1, 2] and provenance["cpu_hours_total"] > 0
    cli = [sys.executable, "-m", "craquelure", "verify", str(dest)]
    assert subprocess.run(cli, capture_output=True).returncode == 0
    (dest / "tables/seed1_fragments.csv").write_text("time,labelling,area\n")
    proc = subprocess.run(cli, capture_output=True, text=True)
    assert proc.returncode == 1 and "changed: tables/seed1_fragments.csv" in proc.stdout
