"""Impact findings for the validation report."""

from __future__ import annotations

import json

import pytest

from craquelure.impact import claims

SUMMARY = {
    "profile": "default", "n_runs": 21, "n_seeds_heterogeneous": 3, "all_runs_finished": True,
    "max_energy_balance_error": 0.0088,
    "material_model": ["cap+compressive_damage"],
    "findings": [
        {"finding": "pf2: failure follows the zero-mass line", "criterion": ">= 70 %",
         "dim": "2D", "values": {"fraction": 0.9625, "angles": [41.0, 29.6]},
         "status": "reproduced", "reproduced": True, "failed": [], "n_seeds": 1,
         "min_seeds": 8},
        {"finding": "pf1: failure follows the zero-mass line", "criterion": ">= 70 %",
         "dim": "2D", "values": {"coverage": {"median": 0.2, "ci95": [0.2, 0.2],
                                              "agreement": 1.0, "n": 1}},
         "status": "not reproduced", "reproduced": False, "failed": ["covers"],
         "n_seeds": 1, "min_seeds": 8},
        {"finding": "kappa = 1: several main cracks", "criterion": "median >= 2", "dim": "2D",
         "values": {}, "status": "inconclusive", "reproduced": None, "failed": [],
         "n_seeds": 3, "min_seeds": 8},
    ],
}

NO = "without rate effects"


def test_findings_keep_their_computed_status(tmp_path):
    path = tmp_path / "summary.json"
    path.write_text(json.dumps(SUMMARY))
    out = [c for c in claims.claims([path]) if not c.claim.startswith("[3D, ")]
    assert [c.verdict for c in out[:2]] == ["reproduced", "not reproduced"]
    assert out[0].measured == "fraction = 0.963; angles = [41, 29.6]"
    assert out[1].measured.startswith("coverage = median 0.2 [95 % 0.2, 0.2], n = 1")
    assert "3 heterogeneous specimens" in out[1].note and "fails: covers" in out[1].note
    assert out[0].claim.startswith(f"[2D, {NO}]")
    # too few seeds: inconclusive, never reproduced
    assert out[2].verdict == "inconclusive" and out[2].note.startswith("inconclusive: 3 seeds")


def test_energy_balance_above_the_tolerance_is_reported():
    bad = dict(SUMMARY, max_energy_balance_error=0.031)
    c = claims.robustness_claim(bad)
    assert c.verdict == "partly" and "energy balance error < 2%" in c.note


def test_too_few_seeds_and_a_missing_case_are_inconclusive():
    few = dict(SUMMARY["findings"][2])
    c = claims.finding_claim(few, "caveat")
    assert c.verdict == "inconclusive" and "3 seeds" in c.note
    missing = {"finding": "homogeneous: one main crack", "criterion": "N_main = 1",
               "values": {}, "reproduced": None}
    assert claims.finding_claim(missing, "caveat").verdict == "inconclusive"


def test_3d_and_2d_verdicts_side_by_side(tmp_path):
    """Each finding's 3D row right before its 2D row; a dimension without runs says so."""
    three = [dict(f, dim="3D", status="reproduced", reproduced=True, n_seeds=8)
             for f in SUMMARY["findings"][:2]]
    path = tmp_path / "summary.json"
    path.write_text(json.dumps(dict(SUMMARY, findings=three + SUMMARY["findings"],
                                    dimensions=["3D", "2D"],
                                    n_seeds_heterogeneous_by_dim={"3D": 8, "2D": 3})))
    out = claims.claims([path])
    rows = [(c.claim, c.verdict) for c in out][:6]
    assert "8 heterogeneous specimens" in out[0].note and "3 heterogeneous" in out[1].note
    assert rows[0] == (f"[3D, {NO}] pf2: failure follows the zero-mass line", "reproduced")
    assert rows[1] == (f"[2D, {NO}] pf2: failure follows the zero-mass line", "reproduced")
    assert rows[2] == (f"[3D, {NO}] pf1: failure follows the zero-mass line", "reproduced")
    assert rows[3] == (f"[2D, {NO}] pf1: failure follows the zero-mass line", "not reproduced")
    assert rows[4] == (f"[3D, {NO}] kappa = 1: several main cracks", "inconclusive")
    missing = claims.claims([path])[4]
    assert missing.note == "not run: profile default has no 3D runs of this case"
    assert rows[5] == (f"[2D, {NO}] kappa = 1: several main cracks", "inconclusive")


def test_fractional_condition_shows_statistic_intervals_and_power():
    test = {"k": 6, "n": 8, "fraction": 0.75, "threshold": 0.5, "decided": None,
            "ci95_bootstrap": [0.5, 1.0], "ci95_exact": [0.35, 0.97],
            "power": {"P in 9 of 10 specimens": 0.43, "P in 1 of 10 specimens": 0.42},
            "seeds_for_power": {"P in 9 of 10 specimens": 12, "P in 1 of 10 specimens": 12}}
    finding = dict(SUMMARY["findings"][2], n_seeds=8, fraction_tests={"N_main >= 2": test},
                   undecided={"N_main >= 2": "power 0.43"})
    c = claims.finding_claim(finding, "caveat")
    assert ("N_main >= 2: 6 of 8 seeds (fraction 0.75, bootstrap 95 % [0.50, 1.00], exact 95 % "
            "[0.35, 0.97]; power 0.43 against P in 9 of 10 specimens") in c.measured
    assert c.verdict == "inconclusive" and c.note.startswith("cannot decide: N_main >= 2")


def test_rows_off_the_source_configuration_say_they_are_sensitivities():
    """3D with the cap (CSCM-like) concrete is the source's configuration; the 2D slice and a
    Drucker-Prager 3D disc are labelled sensitivities with what departs."""
    from craquelure.impact.claims import caveat_of

    summary = {"profile": "paper", "n_seeds_heterogeneous": 10,
               "material_model_by_dim": {"3D": ["cap+compressive_damage+rate_effects"],
                                         "2D": ["drucker_prager"]}}
    assert "the source's configuration" in caveat_of(summary, "3D")
    two = caveat_of(summary, "2D")
    assert "sensitivity" in two and "2D plane-strain slice" in two and "drucker_prager" in two
    summary["material_model_by_dim"]["3D"] = ["drucker_prager"]
    three = caveat_of(summary, "3D")
    assert "sensitivity" in three and "slice" not in three


def test_rows_with_rate_effects_say_so_and_show_their_pictures(tmp_path):
    """summary_rate.json (runs with CSCM's rate effects): every row says 'with rate effects'
    and points at the rate campaign's pictures, never at those of the runs without them."""
    three = [dict(f, dim="3D") for f in SUMMARY["findings"]]
    path = tmp_path / "summary_rate.json"
    path.write_text(json.dumps(dict(SUMMARY, findings=three, material_model_by_dim={
        "3D": ["cap+compressive_damage+rate_effects"]})))
    out = claims.claims([path])
    assert all(c.claim.startswith(("[3D, with rate effects]", "[2D, with rate effects]",
                                   "[with rate effects]")) for c in out)
    assert {c.figure for c in out if c.claim.startswith("[3D")} <= {
        "impact_judged_rate_opening_maps.png", "impact_judged_rate_time_sequence.png"}
    two = [dict(f, dim="2D") for f in SUMMARY["findings"]]
    path.write_text(json.dumps(dict(SUMMARY, findings=two, material_model_by_dim={
        "2D": ["cap+rate_effects"]})))
    rate_figures = {c.figure for c in claims.claims([path])}
    assert rate_figures - {""} and all(f.startswith("impact_rate_") for f in rate_figures - {""})
    path.with_name("summary.json").write_text(json.dumps(dict(SUMMARY, findings=two)))
    plain = {c.figure for c in claims.claims([path.with_name("summary.json")])}
    assert rate_figures == {f.replace("impact_", "impact_rate_", 1) for f in plain}
    with pytest.raises(ValueError, match="unexpected source"):
        claims.claims([tmp_path / "other.json"])
