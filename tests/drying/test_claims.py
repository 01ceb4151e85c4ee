"""Drying claims for the validation report: verdicts follow the summary's check conditions."""

from __future__ import annotations

import copy

import numpy as np
import xarray as xr

from craquelure.drying import claims

SUMMARY = {
    "profile": "medium", "n_particles": 10000, "n_seeds": 8, "window_mode": "all_broken",
    "t_star": 7.5, "window": [19.5, 45.0], "slope_over_b_star": 0.35,
    "fit": {"r2": 0.991, "slope_b": 0.0387, "quadratic_departure_fraction": 0.009,
            "x_intercept": 15.4, "alpha": 2.33, "alpha_ci95": [2.12, 2.61]},
    "collapse": {"per_time": [{"n": 22, "below_critical": True}, {"n": 169,
                                                                  "below_critical": True}],
                 "cv_mean_x2": 0.133, "raw_ks_first_last": 0.83,
                 "mean_pairwise_ks_before": 0.37, "mean_pairwise_ks_after": 0.13},
    "checks": {
        "sample_size_meets_spec": False,
        "check14_inverse_mean_area_linear": {
            "r2_at_least_0.95": True, "slope_positive": True,
            "quadratic_change_below_20_percent": True, "x_intercept_in_range": False,
            "x_intercept_range": [1.67, 7.67]},
        "check15_scaling_collapse": {
            "ks_test_can_reject_at_all_t_k": True, "ks_below_critical_at_all_t_k": True,
            "cv_mean_x2_at_most_0.10": False, "raw_ks_first_last_at_least_0.3": True},
    },
}


def test_check14_misses_on_the_intercept_only_is_partly():
    c = claims.inverse_area_claim(SUMMARY)
    assert c.verdict == "partly"
    assert "fails: x_intercept_in_range" in c.note and "indicative only" in c.note
    assert "R^2 = 0.991" in c.measured and "2.05 t*" in c.measured


def test_check15_verdicts_follow_the_conditions():
    assert claims.collapse_claim(SUMMARY).verdict == "partly"
    good = copy.deepcopy(SUMMARY)
    good["checks"]["check15_scaling_collapse"]["cv_mean_x2_at_most_0.10"] = True
    good["checks"]["sample_size_meets_spec"] = True
    c = claims.collapse_claim(good)
    assert c.verdict == "reproduced" and "indicative" not in c.note
    assert "2/2 t_k (22-169 fragments each)" in c.measured


def test_thickness_exponent_within_two_standard_deviations(tmp_path):
    def write(beta, std):
        ds = xr.Dataset({"n_seeds": ("thickness", np.array([1, 1]))},
                        coords={"thickness": [0.2, 0.316]},
                        attrs={"exponent_late_mean": beta, "exponent_late_std": std,
                               "predicted_exponent": 2.0, "n_late_times": 7})
        path = tmp_path / f"thickness_{beta}.nc"
        ds.to_netcdf(path)
        return path

    assert claims.thickness_claim(write(1.62, 0.24)).verdict == "reproduced"
    assert claims.thickness_claim(write(1.2, 0.24)).verdict == "not reproduced"


def test_a_campaign_without_a_window_is_not_reproduced_with_its_reason():
    # Short runs (the CI profile) never break every sample: no fit, no collapse times.
    empty = copy.deepcopy(SUMMARY)
    empty["fit"] = {"window_times": [], "mean_area": [],
                    "error": "fewer than 3 usable snapshots in the window"}
    empty["slope_over_b_star"] = None
    empty["collapse"] = {"per_time": [], "cv_mean_x2": None, "raw_ks_first_last": None,
                         "mean_pairwise_ks_before": 0.5, "mean_pairwise_ks_after": None}
    for group in ("check14_inverse_mean_area_linear", "check15_scaling_collapse"):
        for key, value in empty["checks"][group].items():
            if isinstance(value, bool):
                empty["checks"][group][key] = False
    inverse, collapse = claims.inverse_area_claim(empty), claims.collapse_claim(empty)
    assert inverse.verdict == collapse.verdict == "not reproduced"
    assert inverse.measured == "no fit: fewer than 3 usable snapshots in the window"
    assert collapse.measured.startswith("no collapse times")
