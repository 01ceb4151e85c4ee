"""Drying claims for the validation report: verdicts follow the summary's check conditions and
what its sample cannot decide."""

from __future__ import annotations

import copy
import re

import numpy as np
import xarray as xr

from craquelure.drying import claims

C14 = {
    "n_times": 13, "n_samples": 8, "reduced_chi2": 0.9, "reduced_chi2_critical": 2.3,
    "quadratic_c_p": 0.4, "slope_b": 0.0387, "slope_over_b_star": 0.35,
    "slope_b_ci95": [0.03, 0.045], "t0_over_t_star": 2.05, "t0_ci95": [14.0, 16.5],
    "alternative": "1/<S>_t = A + B t^2 (t^-2 law) through the measured end points",
    "power": 0.31, "alpha_free_power_law": 2.33,
    "conditions": {"(a) reduced chi^2 below its 99 % critical value": True,
                   "(b) quadratic term not significant at 1 %": True,
                   "(c) 0 < t0 <= t*": True, "(c) b > 0": True,
                   "(c) 0.2 b* <= b <= 5 b*": True},
    "undecided": {"(d) power 0.31 < 0.8 against 1/<S>_t = A + B t^2": "about 45 seeds"},
}
C15 = {
    "n_first": 22, "n_last": 169, "ks_scaled_first_last": 0.12,
    "ks_scaled_first_last_upper95": 0.31, "cv_mean_x2": 0.13, "cv_mean_x2_upper95": 0.2,
    "ks_raw_first_last": 0.83, "alternative": "scaled width drifting by 25% across the window",
    "power": 1.0, "confirmation_rate": 0.9, "ks_margin": 0.15, "cv_margin": 0.1,
    "conditions": {"KS(S_first, S_last) >= 0.3 (non-trivial)": True,
                   "KS(X_first, X_last) upper 95 % bound <= 0.15": False,
                   "CV of <X^2>_t upper 95 % bound <= 0.1": False},
    "undecided": {},
}
ITEM = {"time": 20.0, "over_t_star": 2.6, "ci95_over_t_star": [2.4, 2.9]}
C16 = {
    "n_samples": 8, "unbroken_at_end": 0, "unbroken_at_end_ci95": [0.0, 0.37],
    "rates_at_samples": 100, "confirmation_rate": 0.0, "power": 1.0,
    "alternative": "every break 25% later", **{k: ITEM for k in (
        "first_removal_earliest", "first_removal_median", "first_sample_broken",
        "half_samples_broken", "all_samples_broken")},
    "conditions": {"first sample broken by 0.45 t*": False,
                   "all samples broken by 0.9 t*": False},
    "undecided": {},
}
SUMMARY = {
    "profile": "medium", "n_particles": 10000, "n_seeds": 8, "window_mode": "all_broken",
    "t_star": 7.5, "b_star": 0.11, "window": [19.5, 45.0], "pi": 0.66, "pi_paper": 0.022,
    "checks": {"sample_size_meets_spec": False, "check14_inverse_mean_area_linear": C14,
               "check15_scaling_collapse": C15, "check16_onset": C16},
}


def test_check14_without_power_is_inconclusive_and_names_the_sample():
    c = claims.inverse_area_claim(SUMMARY)
    assert c.verdict == "inconclusive"
    assert "power 0.31" in c.note and "needs about 45 seeds" in c.note
    assert "Pi = tau/t* = 0.66" in c.note and "departs from the paper's regime" in c.note
    assert "t0 = 2.05 t*" in c.measured and "power against" in c.measured
    failed = copy.deepcopy(SUMMARY)
    failed["checks"]["check14_inverse_mean_area_linear"]["conditions"]["(c) 0 < t0 <= t*"] = False
    c = claims.inverse_area_claim(failed)
    # A failing condition decides whatever the power; the spec states one test.
    assert c.verdict == "not reproduced" and "fails: (c) 0 < t0 <= t*" in c.note


def test_check15_verdict_is_recomputed_from_the_conditions():
    assert claims.collapse_claim(SUMMARY).verdict == "not reproduced"
    good = copy.deepcopy(SUMMARY)
    for key in good["checks"]["check15_scaling_collapse"]["conditions"]:
        good["checks"]["check15_scaling_collapse"]["conditions"][key] = True
    good["pi"] = 0.022
    c = claims.collapse_claim(good)
    assert c.verdict == "reproduced" and "departs" not in c.note
    assert "22 and 169 fragments" in c.measured


def test_check16_names_pi_and_the_onset_in_t_star():
    c = claims.onset_claim(SUMMARY)
    assert c.verdict == "not reproduced"
    assert "all 2.60 t* (95 % CI 2.40-2.90)" in c.measured and "Pi = tau/t* = 0.66" in c.note


def test_thickness_exponent_within_two_standard_deviations(tmp_path):
    def write(beta, std, n_late=7):
        ds = xr.Dataset({"n_seeds": ("thickness", np.array([1, 1]))},
                        coords={"thickness": [0.2, 0.316]},
                        attrs={"exponent_late_mean": beta, "exponent_late_std": std,
                               "predicted_exponent": 2.0, "n_late_times": n_late})
        path = tmp_path / f"thickness_{beta}_{n_late}.nc"
        ds.to_netcdf(path)
        return path

    assert claims.thickness_claim(write(1.62, 0.24)).verdict == "reproduced"
    assert claims.thickness_claim(write(1.2, 0.24)).verdict == "not reproduced"
    assert claims.thickness_claim(write(float("nan"), 0.0, 0)).verdict == "inconclusive"


def test_a_campaign_without_a_window_is_inconclusive_with_its_reason():
    # Short runs (the CI profile) never break every sample: nothing to test.
    empty = copy.deepcopy(SUMMARY)
    for key in ("check14_inverse_mean_area_linear", "check15_scaling_collapse"):
        error = "needs >= 4 snapshots in the window"
        empty["checks"][key] = {"error": error, "conditions": {},
                                "undecided": {error: "a longer or larger run"}}
    inverse, collapse = claims.inverse_area_claim(empty), claims.collapse_claim(empty)
    assert inverse.verdict == collapse.verdict == "inconclusive"
    assert inverse.measured == "no test: needs >= 4 snapshots in the window"
    assert "needs a longer or larger run" in collapse.note


def test_companion_rows_name_their_setting_and_a_departing_variant_has_no_verdict(tmp_path):
    """Beside the headline: a companion with the source's criterion is judged as its own
    summary is; one whose criterion departs (tr(sigma) at L = 5) keeps its numbers and loses
    its verdicts, in the JSON (null, no tally) and on the page ("not judged")."""
    import json

    from craquelure import validation

    base = {**SUMMARY, "scene": "paper_speed", "box_length": 5.0}
    source = claims.companion("drying-l5-source", {**base, "fracture_stress_measure":
                                                   "half_trace"})
    variant = claims.companion("drying-l5-trace", {**base, "fracture_stress_measure": "trace"})
    assert source["judged"] and not variant["judged"] and "never ran" in variant["why"]
    assert source["setting"] == ("scene paper_speed: tr(sigma)/2 > sigma_Y (the source's), "
                                 "L = 5, N = 10000, 8 seeds")
    assert "a factor 2 from the source's" in variant["setting"]
    own = claims.summary_claims(base)
    assert [c.verdict for c in source["claims"]] == [c.verdict for c in own]
    for c in source["claims"] + variant["claims"]:
        assert c.note.endswith("L = 5, N = 10000, 8 seeds") and "ensemble drying-l5-" in c.note
    headline = claims.summary_claims({**base, "fracture_stress_measure": "trace"})
    path = validation.write_json(headline, tmp_path / "v.json", "table1", None,
                                 [source, variant])
    doc = json.loads(path.read_text())
    assert doc["tally"] == validation.tally(headline)  # companions stay out of the tally
    judged, context = doc["companions"]
    assert judged["tally"] == validation.tally(own) and context["tally"] is None
    assert {r["verdict"] for r in context["claims"]} == {None}
    assert [r["measured"] for r in context["claims"]] == [c.measured for c in own]
    page = validation.render_html(headline, "table1", (), [source, variant])
    assert page.count("Beside it: drying-l5-") == 2
    assert page.count('class="cq-badge not-judged"') == len(own)
    context_page = page.split("Beside it: drying-l5-trace")[1]  # no verdict, no tally there
    assert 'data-verdict=""' in context_page and not re.search(
        r'data-verdict="[a-z]|\d+ (reproduced|partly|not reproduced|inconclusive)', context_page)
    plain = validation.render_html(headline, "table1")
    assert "Beside it" not in plain and page.startswith(plain.removesuffix("</body></html>\n"))


def test_a_criterion_variant_is_an_overridden_departing_criterion():
    """Only runs that override their scene's criterion with a departing one are a variant; a
    scene that declares the departure (the headline) and the source's criterion are judged."""
    assert claims.criterion_variant({"scene": "paper_speed_Ctrace", "scene_name": "paper_speed",
                                     "fracture_stress_measure": "trace"})
    assert not claims.criterion_variant({"scene": "table1_trace", "scene_name": "table1_trace",
                                         "fracture_stress_measure": "trace"})
    assert not claims.criterion_variant({"scene": "paper_speed_Chalf_trace",
                                         "scene_name": "paper_speed",
                                         "fracture_stress_measure": "half_trace"})
