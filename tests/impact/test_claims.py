"""Impact findings for the validation report."""

from __future__ import annotations

import json

from craquelure.impact import claims

SUMMARY = {
    "profile": "default", "n_runs": 21, "n_seeds_heterogeneous": 3, "all_runs_finished": True,
    "max_energy_balance_error": 0.0088,
    "findings": [
        {"finding": "pf2: failure follows the zero-mass line", "criterion": ">= 80 %",
         "values": {"fraction": 0.9625, "angles": [41.0, 29.6]}, "reproduced": True},
        {"finding": "pf1: failure follows the zero-mass line", "criterion": ">= 80 %",
         "values": {"fraction": 0.2045}, "reproduced": False},
    ],
}


def test_findings_keep_their_computed_flags(tmp_path):
    path = tmp_path / "summary.json"
    path.write_text(json.dumps(SUMMARY))
    out = claims.claims([path])
    assert [c.verdict for c in out] == ["reproduced", "not reproduced", "reproduced"]
    assert "fraction = 0.963; angles = [41, 29.6]" == out[0].measured
    assert "3 heterogeneous specimens" in out[1].note


def test_energy_balance_above_the_tolerance_is_reported():
    bad = dict(SUMMARY, max_energy_balance_error=0.031)
    c = claims.robustness_claim(bad)
    assert c.verdict == "partly" and "energy balance error < 2%" in c.note


def test_a_fraction_of_three_seeds_is_inconclusive_and_a_missing_case_too():
    kappa15 = {"finding": "kappa = 1.5: heterogeneity smoothed, one main crack",
               "criterion": "N_mc = 1 in >= 60 % of seeds and median phi_c(1.5) < phi_c(1.0)",
               "values": {"fraction_N_mc_1": 2 / 3}, "reproduced": True}
    c = claims.finding_claim(kappa15, "caveat", n_seeds=3)
    # 2 of 3: the exact 95 % interval [0.09, 0.99] straddles 60 %.
    assert c.verdict == "inconclusive" and "samples at the observed fraction 0.67" in c.note
    # 20 of 30 still straddles it ([0.47, 0.83]); 27 of 30 ([0.73, 0.98]) decides.
    assert claims.finding_claim(kappa15, "caveat", n_seeds=30).verdict == "inconclusive"
    kappa15["values"]["fraction_N_mc_1"] = 0.9
    assert claims.finding_claim(kappa15, "caveat", n_seeds=30).verdict == "reproduced"
    missing = {"finding": "homogeneous: one main crack", "criterion": "N_mc = 1", "values": {},
               "reproduced": None}
    assert claims.finding_claim(missing, "caveat", n_seeds=3).verdict == "inconclusive"
