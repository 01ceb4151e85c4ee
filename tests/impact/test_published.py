"""Check 12's archive (craquelure.impact.published): the findings are decided again from the
summaries' per-run measurements; a folder is published whole with its manifest, and decided
again from it, row for row."""

from __future__ import annotations

import copy
import json
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import pytest  # noqa: E402

from craquelure.archive import verify  # noqa: E402
from craquelure.errors import CraquelureError  # noqa: E402
from craquelure.impact.published import findings_from_cases, publish, rebuild  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
# The CI profile's summary: 3D (homogeneous disc) and 2D cases, uniform heterogeneous masses.
SUMMARY = json.loads((ROOT / "tests/reference/ci/impact/summary.json").read_text())
HOMOGENEOUS_3D = "3D/homogeneous/none/kappa1"


def test_findings_are_decided_again_from_the_cases():
    assert findings_from_cases(SUMMARY, "uniform") == SUMMARY["findings"]


def test_a_changed_measurement_changes_the_finding():
    """The findings follow the per-run numbers, not a stored verdict: one main crack in the
    homogeneous 3D disc instead of the measured count changes that finding's numbers."""
    changed = copy.deepcopy(SUMMARY)
    per_seed = changed["cases"][HOMOGENEOUS_3D]["per_seed"]
    assert per_seed["n_main_cracks_revised"] != [1]
    per_seed["n_main_cracks_revised"] = [1]
    before = [f for f in SUMMARY["findings"] if f["dim"] == "3D"][0]
    after = [f for f in findings_from_cases(changed, "uniform") if f["dim"] == "3D"][0]
    assert after["values"]["n_main_cracks_revised"] == 1
    assert after["values"] != before["values"]


def _inputs(tmp_path: Path) -> tuple[list[Path], list[Path], dict]:
    """Both summaries (the reference's keys are sorted: its findings are put back in the order
    the analysis writes them, which the rows' wording follows), a figure, a provenance."""
    (tmp_path / "in").mkdir()
    summary = dict(SUMMARY, findings=findings_from_cases(SUMMARY, "uniform"))
    without = tmp_path / "in" / "summary.json"
    without.write_text(json.dumps(summary))
    rate = tmp_path / "in" / "summary_rate.json"
    rate.write_text(json.dumps(dict(summary, scene="ci_rate", material_model_by_dim={
        dim: [f"{m}+rate_effects" for m in models]
        for dim, models in SUMMARY["material_model_by_dim"].items()})))
    figure = tmp_path / "in" / "impact_judged_opening_maps.png"
    fig, ax = plt.subplots(figsize=(2, 2))
    ax.plot([0, 1], [0, 1])
    fig.savefig(figure)
    plt.close(fig)
    provenance = {"profile": "ci", "distribution": "uniform", "run_git_commits": ["abc"],
                  "cpu_hours_total": 0.5}
    return [without, rate], [figure], provenance


def test_published_folder_verifies_and_is_decided_again_row_for_row(tmp_path):
    summaries, figures, provenance = _inputs(tmp_path)
    dest = publish(summaries, figures, provenance, tmp_path / "impact-check12")
    problems, checked = verify(dest)
    assert problems == [] and checked == 6  # 2 summaries, rows, provenance, README, 1 figure
    rows = json.loads((dest / "validation.json").read_text())["claims"]
    labels = {"without rate effects": 0, "with rate effects": 0}
    for row in rows:
        labels["with rate effects" if "with rate effects" in row["claim"]
               else "without rate effects"] += 1
    assert labels["with rate effects"] == labels["without rate effects"] > 0
    readme = (dest / "README.md").read_text()
    assert "- without rate effects: scene ci," in readme
    assert "- with rate effects: scene ci_rate," in readme
    again = rebuild(dest, tmp_path / "again")
    assert json.loads((again / "validation.json").read_text())["claims"] == rows


def test_publish_replaces_the_folder_and_refuses_other_summaries(tmp_path):
    summaries, figures, provenance = _inputs(tmp_path)
    dest = tmp_path / "impact-check12"
    dest.mkdir()
    (dest / "stale.txt").write_text("from an earlier campaign")
    publish(summaries, figures, provenance, dest)
    assert not (dest / "stale.txt").exists() and verify(dest)[0] == []
    with pytest.raises(CraquelureError, match="allowed: summary.json, summary_rate.json"):
        publish([summaries[0], summaries[0]], figures, provenance, tmp_path / "other")
