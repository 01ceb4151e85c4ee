"""Validation report frame: verdicts from conditions, the model registry, the HTML table."""

from __future__ import annotations

import json

import pytest

from craquelure import validation
from craquelure.validation import Claim, verdict_of


def test_verdict_from_conditions_names_the_failures():
    assert verdict_of({"a": True, "b": True}) == ("reproduced", "")
    assert verdict_of({"a": True, "b": False}) == ("partly", "fails: b")
    assert verdict_of({"a": False, "b": False}) == ("not reproduced", "fails: a, b")
    assert verdict_of({"a": True, "b": False}, partial=False) == ("not reproduced", "fails: b")
    with pytest.raises(ValueError, match="at least one condition"):
        verdict_of({})


def test_a_sample_that_cannot_decide_gives_inconclusive_never_reproduced():
    verdict, note = verdict_of({"a": True}, {"power 0.3 < 0.8": "about 40 seeds"})
    assert verdict == "inconclusive"
    assert note == "sample cannot decide: power 0.3 < 0.8 (needs about 40 seeds)"
    # A failure still decides, and the note keeps what could not be decided.
    verdict, note = verdict_of({"a": False}, {"b": "100 samples"})
    assert verdict == "not reproduced" and "fails: a" in note and "needs 100 samples" in note
    assert verdict_of({}, {"no fragments": "a longer run"})[0] == "inconclusive"


def test_fraction_decision_is_exact_binomial():
    from craquelure.validation import fraction_decision

    # 3 of 3 seeds: the 95 % interval [0.29, 1] straddles 0.6: undecided, and the note
    # names the sample at the same fraction that would decide (8 of 8: lower bound 0.63).
    decided, need = fraction_decision(3, 3, 0.6)
    assert decided is None and "about 8 samples" in need
    assert fraction_decision(20, 20, 0.6) == (True, "")
    assert fraction_decision(0, 20, 0.6) == (False, "")


def test_claim_rejects_an_unknown_verdict():
    with pytest.raises(ValueError, match="allowed values: reproduced, partly, not reproduced, "
                                         "inconclusive"):
        Claim("drying", "c", "s", "k", "m", "maybe")


def test_collect_rejects_an_unknown_model():
    with pytest.raises(ValueError, match="unknown model.*allowed values: drying, impact"):
        validation.collect({"fluid": ["x.json"]})


def test_outputs_count_and_escape(tmp_path):
    claims = [Claim("impact", "a < b & c", "s", "k", "1", "reproduced"),
              Claim("impact", "d", "s", "k", "2", "partly", "fails: x"),
              Claim("softdyn", "e", "s", "k", "3", "not reproduced", "fails: y"),
              Claim("drying", "f", "s", "k", "4", "inconclusive", "sample cannot decide: z")]
    validation.write_json(claims, tmp_path / "v.json", "ci")
    doc = json.loads((tmp_path / "v.json").read_text())
    assert doc["tally"]["all"] == {"reproduced": 1, "partly": 1, "not reproduced": 1,
                                   "inconclusive": 1}
    assert doc["tally"]["impact"]["partly"] == 1 and len(doc["claims"]) == 4
    assert "git_commit" in doc["provenance"] and "version_numpy" in doc["provenance"]
    html = validation.render_html(claims, "ci")
    assert "a &lt; b &amp; c" in html and "a < b" not in html
    assert "impact: 1 reproduced, 1 partly, 0 not reproduced, 0 inconclusive" in html
    assert html.count('class="inconclusive"') == 1
    assert html.count('class="not-reproduced"') == 1


def test_fraction_power_by_simulation_matches_the_binomial():
    """Power of the exact-interval test of 'fraction >= 1/2' at n samples against a true
    fraction 0.9: it decides when the interval's lower bound clears 1/2 (k = n at n = 8,
    k >= 9 at n = 10), so the power is P(k = 8) = 0.430 and P(k >= 9) = 0.736 within the
    simulation's noise (4000 draws: sd 0.008); 3 samples never decide."""
    from craquelure.validation import fraction_power, samples_for_power

    assert abs(fraction_power(8, 0.9, 0.5) - 0.9**8) < 0.03
    assert abs(fraction_power(10, 0.9, 0.5) - (0.9**10 + 10 * 0.9**9 * 0.1)) < 0.03
    assert fraction_power(3, 0.9, 0.5) == 0.0
    assert samples_for_power(3, 0.9, 0.5) == 12
