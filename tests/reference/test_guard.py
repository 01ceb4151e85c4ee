"""The CI reference guard (tests/reference/guard.py): what it compares, what it leaves out,
that it names a moved number, and that the committed reference comes with its CHANGELOG.md
line. The comparison with a real CI run is tests/workflow/test_snakemake.py
(test_ci_numbers_match_the_reference), on the run the suite already makes."""

from __future__ import annotations

import json
import math

import pytest

from tests.reference import guard, regenerate


def run_folder(tmp_path, summary: dict, claims: list[dict]):
    """A minimal finished run: one summary.json and validation.json under results/."""
    (tmp_path / "results" / "lattice" / "glen").mkdir(parents=True)
    (tmp_path / "results" / "lattice" / "glen" / "summary.json").write_text(json.dumps(summary))
    (tmp_path / "results" / "validation.json").write_text(json.dumps({
        "profile": "ci", "tally": {}, "claims": claims, "benchmarked": [],
        "provenance": {"git_commit": "abc", "sources": {}}}))
    return tmp_path


CLAIM = {"model": "lattice", "claim": "Glen's law", "source": "check 8", "criterion": "c",
         "measured": "slope -2.01", "verdict": "reproduced", "note": ""}


@pytest.mark.parametrize("key", ["wall_time_s", "total_wall_s", "cpu_s", "cpu_seconds",
                                 "run_wall_time_s_by_dim", "reference_wall_time_s",
                                 "bond_updates_per_s", "heun_wall_time_s"])
def test_timings_are_left_out(key):
    assert guard.left_out(key) == "timing"


@pytest.mark.parametrize("key", ["git_commit", "campaign_git_commit", "start_time", "host",
                                 "version_numpy", "provenance"])
def test_provenance_is_left_out(key):
    assert guard.left_out(key) == "provenance"


@pytest.mark.parametrize("key", ["t_star", "h_star", "relative_error", "fragments", "time",
                                 "duration", "steps", "predicted", "check8_glen_slope_pass",
                                 "times_over_t_star", "onset_time", "walls"])
def test_physical_quantities_are_compared(key):
    assert guard.left_out(key) is None


def test_a_moved_number_is_named_and_timings_are_not(tmp_path):
    summary = {"viscosity_slope": -2.0125, "wall_time_s": 1.5, "nested": {"n": [1, 2, 3]},
               "undefined": math.nan}
    ref = guard.snapshot(run_folder(tmp_path / "a", summary, [CLAIM]))
    # timing and provenance moved, NaN stays NaN: no difference
    same = dict(summary, wall_time_s=99.0, git_commit="def")
    assert guard.differences(ref, guard.snapshot(run_folder(tmp_path / "b", same, [CLAIM]))) == []
    # one ulp on a float, an int that became a float, a verdict, a list that grew
    moved = dict(summary, viscosity_slope=math.nextafter(-2.0125, 0.0),
                 nested={"n": [1, 2.0, 3, 4]})
    claim = dict(CLAIM, verdict="partly", note="fails: x")
    diffs = guard.differences(ref, guard.snapshot(run_folder(tmp_path / "c", moved, [claim])))
    text = "\n".join(diffs)
    assert "results/lattice/glen/summary.json: viscosity_slope: -2.0125 -> -2.0124999" in text
    assert "nested.n[1]: 2 -> 2.0" in text and "nested.n[len]: 3 -> 4" in text
    assert "nested.n[3]: (new) -> 4" in text
    # claims are named by their text, not by their position
    assert "results/validation.json: claims.lattice: Glen's law.verdict: 'reproduced' -> " \
           "'partly'" in text
    assert "make reference" in guard.report(diffs)


def test_a_missing_or_new_source_is_named(tmp_path):
    ref = guard.snapshot(run_folder(tmp_path / "a", {"x": 1}, [CLAIM]))
    now = {k: v for k, v in ref.items() if k == guard.VALIDATION}
    assert guard.differences(ref, now) == [
        "results/lattice/glen/summary.json: missing from this run (in the reference)"]
    assert guard.differences(now, ref) == [
        "results/lattice/glen/summary.json: new in this run (not in the reference)"]


def test_regenerate_writes_the_reference_and_its_changelog_line(tmp_path, monkeypatch):
    folder = run_folder(tmp_path / "run", {"x": 0.1, "wall_time_s": 3.0}, [CLAIM])
    monkeypatch.setattr(guard, "REFERENCE", tmp_path / "ref")
    monkeypatch.setattr(guard, "CHANGELOG", tmp_path / "CHANGELOG.md")
    (tmp_path / "CHANGELOG.md").write_text("# Changelog\n\nintro\n\n## 2026-01-01\n\n- old\n")
    assert regenerate.main(["--reason", "kernel round-off", "--from", str(folder)]) == 0
    snap, meta = guard.load_reference(tmp_path / "ref")
    assert snap == guard.snapshot(folder) and "wall_time_s" not in json.dumps(snap)
    assert meta["reason"] == "kernel round-off"
    assert meta["digest"] == guard.reference_digest(tmp_path / "ref")
    text = (tmp_path / "CHANGELOG.md").read_text()
    assert guard.changelog_has(meta["digest"], tmp_path / "CHANGELOG.md")
    # newest on top, under its date, before the older entries
    assert text.index("kernel round-off") < text.index("## 2026-01-01") < text.index("- old")
    with pytest.raises(SystemExit):
        regenerate.main(["--reason", " ", "--from", str(folder)])


def test_committed_reference_is_whole_and_in_the_changelog():
    """The files of tests/reference/ci/ are the ones REFERENCE.json's digest names, and
    CHANGELOG.md carries the line of that digest: a reference changed by hand, or regenerated
    without saying why in CHANGELOG.md, fails here."""
    snap, meta = guard.load_reference()
    assert guard.VALIDATION in snap and len(snap) > 1
    files_digest = guard.reference_digest()
    assert meta["digest"] == files_digest, (
        "tests/reference/ci/ differs from the files its REFERENCE.json names; regenerate it "
        "with `make reference REASON=...`")
    assert guard.changelog_has(files_digest), (
        f"CHANGELOG.md has no line for the CI reference of digest {files_digest}; add "
        f"{guard.changelog_line(files_digest, meta['reason'])!r} (make reference does)")
