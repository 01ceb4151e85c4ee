"""Check 12 as revised 2026-12-02 (craquelure.impact.check12): each finding judged by its
defining condition (failing: "not reproduced" whatever else holds; undecided: "inconclusive";
the other conditions can only make it "partly"), cracks counted by opening, per-seed values,
inconclusive with too few seeds, kappa comparisons that hold eps_AS and l_c fixed, pre-cracks of
heterogeneous discs beyond the source. Synthetic metrics, one or more tests per row."""

from craquelure.impact import check12


def case(seeds, **per_seed):
    return {"seeds": list(seeds), "per_seed": per_seed}


def homogeneous(**kw):
    base = {"n_main_cracks_opening": [1], "main_run_x_mid": [-0.002],
            "main_crack_theta_opening_deg": [2.0], "main_run_share": [0.8],
            "main_run_opening": [1e-3], "main_run_opening_half": [0.95e-3],
            "main_run_opening_growth": [1.05], "crushed_area": [1e-4],
            "main_crack_length_opening": [0.15], "second_crack_length_opening": [0.02],
            "cracked_fraction": [0.1], "spacing": [0.004], "contact_force_peak": [5e6]}
    base.update(kw)
    return case([0], **base)


def heterogeneous(n, n_main, phi, eps=0.15, band=0.008, near=0.5, area=1e-3, force=5e6):
    return case(range(1, n + 1), n_main_cracks_opening=[n_main] * n,
                cracked_fraction=[phi] * n, n_secondary_cracks_opening=[1] * n,
                cracked_fraction_near_main=[near] * n, crushed_area=[area] * n,
                contact_force_peak=[force] * n,
                as_epsilon=[eps] * n, crack_band_width=[band] * n, spacing=[0.004] * n)


def precracked(**kw):
    base = {"precrack_coverage_opening": [0.9], "precrack_largest_opening_on_line": [True],
            "precrack_tip_extension_low": [0.01], "precrack_tip_extension_high": [0.01],
            "main_cracks_elsewhere_opening": [0], "spacing": [0.004]}
    base.update(kw)
    return case([0], **base)


def by_name(findings, start):
    return next(f for f in findings if f["finding"].startswith(start))


def judge(cases, start, *args):
    return by_name(check12.evaluate(cases, "uniform", *args)[0], start)


# --- verdict rule -----------------------------------------------------------------------

def test_verdict_by_the_defining_condition():
    v = check12.verdict
    assert v({"d": True, "o": True}, True, ("d",)) == "reproduced"
    assert v({"d": True, "o": False}, True, ("d",)) == "partly"
    assert v({"d": True, "o": None}, True, ("d",)) == "partly"
    assert v({"d": False, "o": True}, True, ("d",)) == "not reproduced"
    assert v({"d": False, "o": None}, True, ("d",)) == "not reproduced"
    assert v({"d": None, "o": True}, True, ("d",)) == "inconclusive"
    assert v({"d": True, "o": True}, False, ("d",)) == "inconclusive"  # too few seeds
    assert v({"d": False, "o": True}, False, ("d",)) == "not reproduced"


def test_every_finding_names_its_defining_condition_in_the_row():
    cases = {"homogeneous/none/kappa1": homogeneous(),
             "uniform/none/kappa1": heterogeneous(8, 3, 0.3),
             "uniform/none/kappa1.5": heterogeneous(8, 1, 0.2),
             "uniform/none/kappa0.7": heterogeneous(8, 1, 0.4, near=0.7, area=2e-3, force=6e6),
             "homogeneous/pf1/kappa1": precracked()}
    findings = check12.evaluate(cases, "uniform")[0]
    assert len(findings) == 5
    for f in findings:
        assert f["defining"] and set(f["defining"]) <= set(f["conditions"])
        assert f["criterion"].startswith("◆ " + "; ".join(f["defining"]))


# --- homogeneous ----------------------------------------------------------------------------

def test_homogeneous_disc_reproduced_with_enough_heterogeneous_seeds():
    cases = {"homogeneous/none/kappa1": homogeneous(),
             "uniform/none/kappa1": heterogeneous(8, 3, 0.3)}
    assert judge(cases, "homogeneous")["status"] == "reproduced"
    f = judge(cases, "heterogeneous kappa = 1")
    assert f["status"] == "reproduced"
    assert set(f["per_seed"]) == {str(s) for s in range(1, 9)}  # every seed's values


def test_a_fan_of_cracks_is_not_reproduced_whatever_else_holds():
    """Six opened runs (the reviewer's 3D disc): N_main = 6 fails the defining condition; the
    crushed zone and the rest cannot rescue the row."""
    cases = {"homogeneous/none/kappa1": homogeneous(n_main_cracks_opening=[6],
                                                    main_run_share=[0.28]),
             "uniform/none/kappa1": heterogeneous(8, 3, 0.3)}
    f = judge(cases, "homogeneous")
    assert f["status"] == "not reproduced"
    assert f["failed"][:2] == ["one main crack (N_main = 1, by opening)",
                               "it carries most (> 1/2) of the centre row's opening"]


def test_a_crack_that_keeps_opening_is_not_reproduced():
    cases = {"homogeneous/none/kappa1": homogeneous(main_run_opening_growth=[1.6]),
             "uniform/none/kappa1": heterogeneous(8, 3, 0.3)}
    f = judge(cases, "homogeneous")
    assert f["status"] == "not reproduced"
    assert f["failed"] == ["it does not open further between 0.5 and 1 ms (opening at 1 ms "
                           "<= 1.2 x at 0.5 ms)"]


def test_an_off_centre_or_inclined_main_crack_is_not_reproduced():
    for kw in ({"main_run_x_mid": [0.012]}, {"main_crack_theta_opening_deg": [25.0]}):
        cases = {"homogeneous/none/kappa1": homogeneous(**kw),
                 "uniform/none/kappa1": heterogeneous(8, 3, 0.3)}
        assert judge(cases, "homogeneous")["status"] == "not reproduced"


def test_a_failed_secondary_condition_makes_the_homogeneous_row_partly():
    cases = {"homogeneous/none/kappa1": homogeneous(crushed_area=[0.0]),
             "uniform/none/kappa1": heterogeneous(8, 3, 0.3)}
    f = judge(cases, "homogeneous")
    assert f["status"] == "partly" and f["failed"] == ["crushed zone at the contact"]


def test_few_heterogeneous_seeds_leave_the_homogeneous_row_partly_not_inconclusive():
    """The comparison with every kappa = 1 specimen cannot be decided with 3 seeds; the defining
    condition is decided (one deterministic run), so the row is "partly", not "inconclusive"."""
    cases = {"homogeneous/none/kappa1": homogeneous(),
             "uniform/none/kappa1": heterogeneous(3, 3, 0.3)}
    assert judge(cases, "homogeneous")["status"] == "partly"
    assert judge(cases, "heterogeneous kappa = 1")["status"] == "inconclusive"


# --- heterogeneous kappa = 1 ----------------------------------------------------------------

def test_fractional_condition_reports_statistic_intervals_and_power():
    """N_main >= 2 in 10 of 10 specimens: decided (exact 95 % interval [0.69, 1] above 1/2),
    with its bootstrap interval over seeds and the simulated power at 10 seeds against the
    named alternatives (P in 9 of 10 specimens: the test decides when k >= 9, binomial
    probability 0.74; P in 1 of 10: symmetric)."""
    cases = {"homogeneous/none/kappa1": homogeneous(),
             "uniform/none/kappa1": heterogeneous(10, 3, 0.3)}
    f = judge(cases, "heterogeneous kappa = 1")
    t = f["fraction_tests"]["N_main >= 2 in the median specimen"]
    assert (t["k"], t["n"], t["decided"]) == (10, 10, True)
    assert t["ci95_bootstrap"] == [1.0, 1.0]
    assert abs(t["ci95_exact"][0] - 0.025 ** 0.1) < 1e-9 and t["ci95_exact"][1] == 1.0
    assert abs(t["power"]["P in 9 of 10 specimens"] - 0.736) < 0.03  # exact: 0.7361
    assert abs(t["power"]["P in 1 of 10 specimens"] - 0.736) < 0.03
    assert t["seeds_for_power"]["P in 9 of 10 specimens"] == 12
    assert f["status"] == "reproduced"


def test_low_power_on_the_defining_condition_is_inconclusive():
    """6 of 8 specimens with two or more main cracks: the exact interval [0.35, 0.97] contains
    1/2, the test has power 0.43 against 'P in 9 of 10 specimens' at 8 seeds: the defining
    condition cannot be decided, inconclusive, naming the power and the seeds it would need."""
    het = heterogeneous(8, 3, 0.3)
    het["per_seed"]["n_main_cracks_opening"] = [3, 2, 1, 4, 1, 2, 3, 2]
    cases = {"homogeneous/none/kappa1": homogeneous(), "uniform/none/kappa1": het}
    f = judge(cases, "heterogeneous kappa = 1")
    assert f["status"] == "inconclusive" and f["failed"] == []
    note = f["undecided"]["N_main >= 2 in the median specimen"]
    assert "6 of 8 seeds" in note and "power at 8 seeds 0.4" in note
    assert "about 12 seeds for power 0.8" in note


def test_one_main_crack_everywhere_is_not_reproduced_at_kappa_1():
    cases = {"homogeneous/none/kappa1": homogeneous(),
             "uniform/none/kappa1": heterogeneous(8, 1, 0.3)}
    f = judge(cases, "heterogeneous kappa = 1")
    assert f["status"] == "not reproduced"  # more damage holds, but cannot rescue the row
    assert f["failed"] == ["N_main >= 2 in the median specimen"]


def test_few_seeds_are_inconclusive_whatever_the_values():
    cases = {"homogeneous/none/kappa1": homogeneous(),
             "uniform/none/kappa1": heterogeneous(3, 3, 0.3)}
    assert judge(cases, "heterogeneous kappa = 1")["status"] == "inconclusive"


# --- kappa = 1.5 ----------------------------------------------------------------------------

def test_kappa_1_5_median_rule_failing_is_not_reproduced():
    """N = 1 in 2 of 10 specimens (the reviewer's 3D campaign): the exact interval lies below
    1/2, the defining condition fails: "not reproduced" (no longer "inconclusive")."""
    het = heterogeneous(10, 2, 0.2)
    het["per_seed"]["n_main_cracks_opening"] = [1, 2, 2, 3, 1, 2, 4, 2, 3, 2]
    cases = {"uniform/none/kappa1.5": het}
    f = judge(cases, "heterogeneous kappa = 1.5")
    assert f["status"] == "not reproduced"
    assert "N_main = 1 in the median specimen" in f["failed"]


def test_kappa_1_5_one_crack_without_short_ones_is_partly():
    het = heterogeneous(8, 1, 0.2)
    het["per_seed"]["n_secondary_cracks_opening"] = [0] * 8
    f = judge({"uniform/none/kappa1.5": het}, "heterogeneous kappa = 1.5")
    assert f["status"] == "partly"


# --- kappa = 0.7 ----------------------------------------------------------------------------

def test_kappa_0_7_with_five_cracks_everywhere_is_not_reproduced():
    """kappa = 0.7 with N = 5 in 10 of 10 specimens and the near-crack condition passing: the
    defining condition (one main crack) fails: "not reproduced"."""
    cases = {"uniform/none/kappa0.7": heterogeneous(10, 5, 0.4, near=0.7, area=2e-3,
                                                    force=6e6),
             "uniform/none/kappa1": heterogeneous(10, 2, 0.3)}
    f = judge(cases, "heterogeneous kappa = 0.7")
    assert f["conditions"]["cracked fraction near the main crack above kappa = 1 in at least "
                           "half of the specimens"] is True
    assert f["status"] == "not reproduced"


def test_kappa_0_7_contact_forces_must_differ():
    base = {"uniform/none/kappa1": heterogeneous(8, 2, 0.3)}
    same = base | {"uniform/none/kappa0.7": heterogeneous(8, 1, 0.4, near=0.7, area=2e-3,
                                                          force=5.1e6)}
    f = judge(same, "heterogeneous kappa = 0.7")
    assert f["status"] == "partly"
    assert f["failed"] == ["peak contact force differs from kappa = 1 in at least half of the "
                           "specimens"]
    differ = base | {"uniform/none/kappa0.7": heterogeneous(8, 1, 0.4, near=0.7, area=2e-3,
                                                            force=6e6)}
    assert judge(differ, "heterogeneous kappa = 0.7")["status"] == "reproduced"


def test_kappa_comparison_fails_when_eps_as_or_l_c_differ():
    cases = {"uniform/none/kappa0.7": heterogeneous(8, 1, 0.4, eps=0.2, near=0.7, area=2e-3,
                                                    force=6e6),
             "uniform/none/kappa1": heterogeneous(8, 2, 0.3, eps=0.15)}
    f = judge(cases, "heterogeneous kappa = 0.7")
    assert f["status"] == "partly"
    assert f["failed"] == ["eps_AS the same at kappa = 0.7 and 1"]


def test_kappa_comparison_pairs_specimens_by_seed_and_states_what_was_held_fixed():
    """kappa = 0.7 against kappa = 1: the same seeds (the same masses) compared pairwise; an
    undecided secondary condition makes the row "partly" (never "inconclusive": the defining
    condition is decided); the row says whether eps_AS and l_c were held fixed."""
    low = heterogeneous(8, 1, 0.4, near=0.7, area=2e-3, force=6e6)
    low["per_seed"]["crushed_area"] = [2e-3, 2e-3, 5e-4, 5e-4, 5e-4, 5e-4, 5e-4, 5e-4]
    cases = {"uniform/none/kappa0.7": low, "uniform/none/kappa1": heterogeneous(8, 2, 0.3)}
    f = by_name(check12.evaluate(cases, "uniform", "2D", {"as_epsilon": 0.15})[0],
                "heterogeneous kappa = 0.7")
    t = f["fraction_tests"]["crushed area above kappa = 1 in at least half of the specimens"]
    assert (t["k"], t["n"], t["decided"]) == (2, 8, None)  # [0.03, 0.65]: undecided
    assert f["status"] == "partly"
    assert f["values"]["eps_AS and l_c"].startswith("held fixed across kappa by the config "
                                                    "(as_epsilon = 0.15)")
    assert judge(cases, "heterogeneous kappa = 0.7")["values"]["eps_AS and l_c"].startswith(
        "each kappa's own")


# --- pre-cracks -----------------------------------------------------------------------------

def test_precrack_reproduced_partly_and_not():
    assert judge({"homogeneous/pf1/kappa1": precracked()}, "pf1")["status"] == "reproduced"
    f = judge({"homogeneous/pf1/kappa1": precracked(main_cracks_elsewhere_opening=[2])}, "pf1")
    assert f["status"] == "partly"
    # a line that opened by 2-3 mm but softened nothing: the opening measure covers it
    low = precracked(precrack_coverage_opening=[0.05])
    assert judge({"homogeneous/pf1/kappa1": low}, "pf1")["status"] == "not reproduced"
    off = precracked(precrack_largest_opening_on_line=[False])
    assert judge({"homogeneous/pf1/kappa1": off}, "pf1")["status"] == "not reproduced"


def test_heterogeneous_precracks_are_beyond_the_source_without_a_verdict():
    cases = {"uniform/pf1/kappa1": case(range(1, 9), **{
        k: v * 8 for k, v in precracked()["per_seed"].items()})}
    findings, reported = check12.evaluate(cases, "uniform")
    assert findings == []
    assert reported["beyond_the_source"][0]["case"] == "uniform/pf1/kappa1"
    assert "without a verdict" in reported["beyond_the_source"][0]["note"]


# --- bookkeeping ----------------------------------------------------------------------------

def test_median_interval_and_bootstrap_agreement():
    out = check12.median_with_interval([1, 1, 1, 1, 2, 2, 3, 3], lambda m: m >= 2)
    assert out["median"] == 1.5 and out["n"] == 8
    assert out["ci95"][0] <= 1.5 <= out["ci95"][1]
    assert 0.0 < out["agreement"] < 1.0  # a median on the edge is not a stable decision


def test_findings_carry_their_dimension():
    cases = {"homogeneous/none/kappa1": homogeneous(),
             "uniform/none/kappa1": heterogeneous(8, 3, 0.3)}
    findings, reported = check12.evaluate(cases, "uniform", "3D")
    assert {f["dim"] for f in findings} == {"3D"} and reported["dim"] == "3D"


def test_reported_peak_contact_force_carries_the_unit_of_its_dimension():
    """A plane slice's contact force is per unit thickness (N/m), the 3D disc's a force (N)."""
    cases = {"homogeneous/none/kappa1": homogeneous()}
    assert check12.evaluate(cases, "uniform", "2D")[1][
        "peak_contact_force_homogeneous_N_per_m"]["1"] == 5e6
    reported = check12.evaluate(cases, "uniform", "3D")[1]
    assert reported["peak_contact_force_homogeneous_N"]["1"] == 5e6
    assert "peak_contact_force_homogeneous_N_per_m" not in reported
