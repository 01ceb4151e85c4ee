"""Lattice claims for the validation report."""

from __future__ import annotations

import json

from craquelure.lattice import claims


def test_weak_scaling_spread(tmp_path):
    path = tmp_path / "scaling.tsv"
    path.write_text("particles\ttime_per_step_per_particle_s\n1000\t1.0e-7\n100000\t1.25e-7\n")
    c = claims.scaling_claim(path)
    assert c.verdict == "reproduced" and "spread 25%" in c.measured
    path.write_text("particles\ttime_per_step_per_particle_s\n1000\t1.0e-7\n100000\t1.5e-7\n")
    assert claims.scaling_claim(path).verdict == "not reproduced"


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
