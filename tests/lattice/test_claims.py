"""Lattice claims for the validation report."""

from __future__ import annotations

import json

import pytest

from craquelure.lattice import claims


def test_weak_scaling_is_judged_by_its_benchmark_not_by_the_report(tmp_path):
    """Spec check 12's only measurement is a timing: the report refuses the scaling table as a
    claim source and names the benchmark that judges it, which exists."""
    from craquelure import validation
    from craquelure.scene import project_root

    path = tmp_path / "scaling" / "scaling.tsv"
    path.parent.mkdir()
    path.write_text("particles\ttime_per_step_per_particle_s\n1000\t1.0e-7\n")
    with pytest.raises(ValueError, match="benchmarks/lattice_scaling.py"):
        claims.claims([path])
    (entry,) = [b for b in validation.benchmarked() if b["model"] == "lattice"]
    assert "check 12" in entry["claim"]
    assert (project_root() / entry["judged_by"]).is_file()


def test_calving_passes_on_likelihood_but_not_on_the_binned_slope(tmp_path):
    folder = tmp_path / "calving"
    folder.mkdir()
    (folder / "summary.json").write_text(json.dumps({
        "fragments": 77, "ml_exponent": 1.67, "ml_cutoff": 20.2, "slope": -1.95,
        "decades": 1.15, "check11_slope_pass": True, "binned_slope_in_band": False}))
    (c,) = claims.claims([folder / "summary.json"])
    assert c.verdict == "partly" and "log-binned" in c.note


def test_fretting_without_platelets_is_partly():
    c = claims.fretting_claim({"broken": 173, "cycles": [{"platelets": 0}, {"platelets": 0}]})
    assert c.verdict == "partly" and c.note == "fails: platelets detach"


def test_calving_with_too_few_fragments_is_inconclusive(tmp_path):
    folder = tmp_path / "calving"
    folder.mkdir()
    (folder / "summary.json").write_text(json.dumps({
        "fragments": 12, "ml_exponent": 1.5, "ml_cutoff": 20.2, "slope": -1.5,
        "decades": 1.15, "check11_slope_pass": False, "binned_slope_in_band": True}))
    (c,) = claims.claims([folder / "summary.json"])
    assert c.verdict == "inconclusive" and "needs >= 20 fragments" in c.note
