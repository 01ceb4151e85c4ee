"""Archived ensembles (results/published/<name>/): every committed folder matches its manifest
and its figures, summary and validation rows are rebuilt from its committed tables (check 12:
decided again from its summaries) by target `published` without a simulation; and the
publishing steps, end to end on the CI run's drying ensemble and on check 12's summaries."""

from __future__ import annotations

import csv
import json
import runpy
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from craquelure.archive import verify
from craquelure.drying.figures import COMPARISON
from craquelure.drying.figures import FIGURES as DRYING_FIGURES
from craquelure.drying.published import publish
from craquelure.impact.published import publish as publish_check12
from tests.impact.test_published import _inputs as check12_inputs
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


@pytest.mark.parametrize("folder", PUBLISHED, ids=[p.name for p in PUBLISHED])
def test_only_a_criterion_variant_goes_without_verdicts(folder):
    """Runs that override their scene's criterion with one departing from the source's
    (results/drying/<scene>_C<measure>/) are a variant the source never ran: their rows keep
    their numbers and carry no verdict. Every other archived ensemble is judged."""
    from craquelure.drying.claims import criterion_variant

    provenance = json.loads((folder / "provenance.json").read_text())
    doc = json.loads((folder / "validation.json").read_text())
    if criterion_variant(provenance):
        assert doc["claims"] == [] and [c["name"] for c in doc["companions"]] == [folder.name]
        assert {r["verdict"] for r in doc["companions"][0]["claims"]} == {None}
    else:
        assert doc["claims"] and all(c["verdict"] for c in doc["claims"])


@pytest.mark.slow
@pytest.mark.parametrize("folder", PUBLISHED, ids=[p.name for p in PUBLISHED])
def test_rebuilt_from_the_committed_tables(tmp_path, folder):
    """The figures, summary and rows rebuilt by target `published` from the committed tables
    decide as the committed ones do, number for number; with the companions the folder names
    (committed beside it), so that the figures comparing them are rebuilt too. Check 12's
    folder is decided again from its summaries' per-run measurements, row for row."""
    work = workflow_copy(tmp_path)
    companions = json.loads((folder / "provenance.json").read_text()).get("companions", [])
    for name in [folder.name, *companions]:
        if (folder.parent / name).is_dir():
            shutil.copytree(folder.parent / name, work / "results/published" / name)
    proc = snakemake(work, "published", "--cores", "1", timeout=1800)
    assert proc.returncode == 0, proc.stderr[-3000:]
    if (folder / "summary_rate.json").is_file():  # check 12 of the impact campaign
        rebuilt = work / "results/impact_published" / folder.name
        rows = json.loads((rebuilt / "validation.json").read_text())["claims"]
        assert rows == json.loads((folder / "validation.json").read_text())["claims"]
        return
    rebuilt = work / "results/drying_published" / folder.name
    summary = json.loads((rebuilt / "summary.json").read_text())
    assert _judged(summary) == _judged(json.loads((folder / "summary.json").read_text()))
    rows = json.loads((rebuilt / "validation.json").read_text())["claims"]
    assert rows == json.loads((folder / "validation.json").read_text())["claims"]
    for png in (folder / "figures").glob("*.png"):
        assert (rebuilt / "figures" / png.name).stat().st_size > 10_000


def test_check12_folder_decided_again_by_target_published(tmp_path):
    """A check-12 folder installed in the workflow is decided again by target `published`
    (rule impact_published), row for row, beside no drying archive."""
    work = workflow_copy(tmp_path)
    dest = publish_check12(*check12_inputs(tmp_path), work / "results/published/check12-ci")
    proc = snakemake(work, "published", "--cores", "1")
    assert proc.returncode == 0, proc.stderr[-3000:]
    rebuilt = work / "results/impact_published/check12-ci/validation.json"
    assert (json.loads(rebuilt.read_text())["claims"]
            == json.loads((dest / "validation.json").read_text())["claims"])


@pytest.fixture(scope="module")
def ci_tables(ci_run, tmp_path_factory) -> Path:
    """The tables of the CI run's drying ensemble (rule drying_publish_tables), made in a copy
    of its drying outputs: the CI run's own folder stays as the workflow wrote it."""
    ci_work, proc = ci_run
    assert proc.returncode == 0, proc.stderr[-3000:]
    work = workflow_copy(tmp_path_factory.mktemp("tables"))
    for sub in ("results/drying/ci", "results/mass/ci",
                *(f"benchmarks/results/{kind}/ci" for kind in
                  ("mass_consistency", "drying_run", "drying_fragments"))):
        shutil.copytree(ci_work / sub, work / sub)
    tables = work / "results/drying/ci/published"
    run = snakemake(work, str(tables.relative_to(work)), "--cores", "1", "--configfile",
                    "config/ci.yaml")
    assert run.returncode == 0, run.stderr[-3000:]
    return tables


@pytest.mark.slow
def test_publish_end_to_end_on_the_ci_ensemble(ci_tables, tmp_path):
    """Tables of the CI run's drying ensemble, installed, rebuilt, verified: both labellings
    judged, the provenance names scene, criterion and box, and a changed file is caught by
    `craquelure verify`."""
    tables = ci_tables
    work = workflow_copy(tmp_path)
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
    assert (provenance["scene"], provenance["fracture_stress_measure"],
            provenance["box_length"]) == ("ci", summary["fracture_stress_measure"], 2.0)
    assert "companions" not in provenance and "companions" not in json.loads(
        (dest / "validation.json").read_text())
    assert not list((dest / "figures").glob("drying_companions*"))
    cli = [sys.executable, "-m", "craquelure", "verify", str(dest)]
    assert subprocess.run(cli, capture_output=True).returncode == 0
    (dest / "tables/seed1_fragments.csv").write_text("time,labelling,area\n")
    proc = subprocess.run(cli, capture_output=True, text=True)
    assert proc.returncode == 1 and "changed: tables/seed1_fragments.csv" in proc.stdout


def _inverse_mean_area(folder: Path, labelling: str) -> np.ndarray:
    """1/<S>_t of an archived ensemble straight from its tables: the fragment areas summed
    over seeds per snapshot, over the fragments counted per snapshot."""
    with open(folder / "tables/seeds.csv", newline="") as fh:
        seeds = [int(float(row["seed"])) for row in csv.DictReader(fh)]
    total = count = 0.0
    for seed in seeds:
        snaps = np.genfromtxt(folder / f"tables/seed{seed}_snapshots.csv", delimiter=",",
                              names=True)
        with open(folder / f"tables/seed{seed}_fragments.csv", newline="") as fh:
            rows = [r for r in csv.DictReader(fh) if r["labelling"] == labelling]
        k = np.searchsorted(snaps["time"], [float(r["time"]) for r in rows])
        total = total + np.bincount(k, [float(r["area"]) for r in rows], snaps.size)
        count = count + snaps["n_fragments" if labelling == "periodic" else "n_fragments_open"]
    with np.errstate(divide="ignore", invalid="ignore"):
        return count / total


@pytest.mark.slow
def test_companions_drawn_beside_the_headline(ci_run, tmp_path):
    """Three archived ensembles of the CI run: a headline whose provenance names two companions
    (one archived: the first seed alone; one not), the companion, and the headline's tables
    without companions. Target `published` draws the comparison of the headline and the
    archived companion only, with the companion's 1/<S>_t as its committed tables give it,
    adds the companion's rows beside the headline's, and leaves the headline's own summary,
    rows and figures as they are without companions."""
    ci_work, proc = ci_run
    assert proc.returncode == 0, proc.stderr[-3000:]
    script = runpy.run_path(str(ROOT / "workflow/scripts/drying_publish_tables.py"))
    fragments = sorted(str(p) for p in (ci_work / "results/drying/ci/fragments").glob("*.nc"))
    run = str(ci_work / "results/drying/ci/run/seed1.nc")
    work = workflow_copy(tmp_path)
    for name, frags, companions in (("ci-head", fragments, ["ci-comp", "ci-missing"]),
                                    ("ci-alone", fragments, []),
                                    ("ci-comp", fragments[:1], [])):
        tables = tmp_path / name / "results/drying/ci/published"
        script["main"](str(tables), run, frags, {}, "ci", companions)
        publish(tables, None, work / "results/published" / name)
    proc = snakemake(work, "published", "--cores", "1")
    assert proc.returncode == 0, proc.stderr[-3000:]
    out = work / "results/drying_published"
    assert sorted(p.name for p in out.glob("*/figures/drying_companions_*.png")) == [
        f"drying_companions_{name}.png" for name in COMPARISON]  # the headline's only
    drawn = json.loads((out / "ci-head/figures/drying_companions.json").read_text())
    assert [e["name"] for e in drawn["ensembles"]] == ["ci-head", "ci-comp"]
    t_star = json.loads((out / "ci-comp/summary.json").read_text())["t_star"]
    comp = drawn["ensembles"][1]
    assert "L = 2," in comp["setting"] and comp["setting"].endswith("1 seed")
    for labelling in ("periodic", "open"):
        d = comp["labellings"][labelling]
        direct = _inverse_mean_area(work / "results/published/ci-comp", labelling)
        assert np.isfinite(direct).sum() >= 2
        np.testing.assert_allclose(np.array(d["inverse_mean_area"], float), direct,
                                   rtol=1e-12)
        times = np.genfromtxt(work / "results/published/ci-comp/tables/seed1_snapshots.csv",
                              delimiter=",", names=True)["time"]
        np.testing.assert_allclose(d["t_over_t_star"], times / t_star, rtol=1e-12)
    head, alone = (json.loads((out / name / "validation.json").read_text())
                   for name in ("ci-head", "ci-alone"))
    assert head["claims"] == alone["claims"] and "companions" not in alone
    assert [c["name"] for c in head["companions"]] == ["ci-comp"]
    rows = head["companions"][0]["claims"]
    assert len(rows) == len(head["claims"]) and all("ensemble ci-comp" in r["note"]
                                                     for r in rows)
    assert "Beside it: ci-comp" in (out / "ci-head/validation.html").read_text()
    assert _judged(json.loads((out / "ci-head/summary.json").read_text())) == _judged(
        json.loads((out / "ci-alone/summary.json").read_text()))
    for name in DRYING_FIGURES:
        png = f"figures/drying_{name}.png"
        assert (out / "ci-head" / png).read_bytes() == (out / "ci-alone" / png).read_bytes()
