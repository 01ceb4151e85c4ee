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
