"""Check 12 as revised (craquelure.impact.check12): verdicts per seed, inconclusive with too few
seeds, kappa comparisons that hold eps_AS and l_c fixed."""

from craquelure.impact import check12


def case(seeds, **per_seed):
    return {"seeds": list(seeds), "per_seed": per_seed}


def homogeneous(**kw):
    base = {"n_main_cracks_revised": [1], "main_crack_x_mid": [-0.002],
            "main_crack_theta_deg": [2.0], "crushed_area": [1e-4],
            "main_crack_length_revised": [0.15], "second_crack_length": [0.02],
            "cracked_fraction": [0.1], "spacing": [0.004], "contact_force_peak": [5e6]}
    base.update(kw)
    return case([0], **base)


def heterogeneous(n, n_main, phi, eps=0.15, band=0.008, near=0.5, area=1e-3):
    return case(range(1, n + 1), n_main_cracks_revised=[n_main] * n,
                cracked_fraction=[phi] * n, n_secondary_cracks=[1] * n,
                cracked_fraction_near_main=[near] * n, crushed_area=[area] * n,
                as_epsilon=[eps] * n, crack_band_width=[band] * n, spacing=[0.004] * n)


def by_name(findings, start):
    return next(f for f in findings if f["finding"].startswith(start))


def test_homogeneous_disc_reproduced_with_enough_heterogeneous_seeds():
    cases = {"homogeneous/none/kappa1": homogeneous(),
             "uniform/none/kappa1": heterogeneous(8, 3, 0.3)}
    f = by_name(check12.evaluate(cases, "uniform")[0], "homogeneous")
    assert f["status"] == "reproduced"
    f = by_name(check12.evaluate(cases, "uniform")[0], "heterogeneous kappa = 1")
    assert f["status"] == "reproduced"
    assert set(f["per_seed"]) == {str(s) for s in range(1, 9)}  # every seed's values


def test_few_seeds_are_inconclusive_whatever_the_values():
    cases = {"homogeneous/none/kappa1": homogeneous(),
             "uniform/none/kappa1": heterogeneous(3, 3, 0.3)}
    findings = check12.evaluate(cases, "uniform")[0]
    assert by_name(findings, "heterogeneous kappa = 1")["status"] == "inconclusive"
    # the homogeneous disc's comparison with every kappa = 1 specimen cannot be decided either
    assert by_name(findings, "homogeneous")["status"] == "inconclusive"


def test_a_failed_deterministic_condition_is_not_hidden_by_few_seeds():
    cases = {"homogeneous/none/kappa1": homogeneous(n_main_cracks_revised=[3]),
             "uniform/none/kappa1": heterogeneous(3, 3, 0.3)}
    f = by_name(check12.evaluate(cases, "uniform")[0], "homogeneous")
    assert f["status"] == "partly" and "one main crack" in f["failed"]


def test_a_fan_from_the_contact_fails_the_homogeneous_finding():
    cases = {"homogeneous/none/kappa1": homogeneous(n_main_cracks_revised=[3],
                                                    main_crack_x_mid=[0.02]),
             "uniform/none/kappa1": heterogeneous(8, 3, 0.3)}
    f = by_name(check12.evaluate(cases, "uniform")[0], "homogeneous")
    assert f["status"] == "partly"
    assert "one main crack" in f["failed"]


def test_kappa_comparison_fails_when_eps_as_or_l_c_differ():
    cases = {"uniform/none/kappa0.7": heterogeneous(8, 1, 0.4, eps=0.2, near=0.7, area=2e-3),
             "uniform/none/kappa1": heterogeneous(8, 2, 0.3, eps=0.15)}
    f = by_name(check12.evaluate(cases, "uniform")[0], "heterogeneous kappa = 0.7")
    assert f["status"] == "partly"
    assert f["failed"] == ["eps_AS the same at kappa = 0.7 and 1"]
    cases["uniform/none/kappa0.7"] = heterogeneous(8, 1, 0.4, near=0.7, area=2e-3)
    f = by_name(check12.evaluate(cases, "uniform")[0], "heterogeneous kappa = 0.7")
    assert f["status"] == "reproduced"


def test_median_interval_and_bootstrap_agreement():
    out = check12.median_with_interval([1, 1, 1, 1, 2, 2, 3, 3], lambda m: m >= 2)
    assert out["median"] == 1.5 and out["n"] == 8
    assert out["ci95"][0] <= 1.5 <= out["ci95"][1]
    assert 0.0 < out["agreement"] < 1.0  # a median on the edge is not a stable decision


def test_fractional_condition_reports_statistic_intervals_and_power():
    """N_main >= 2 in 10 of 10 specimens: decided (exact 95 % interval [0.69, 1] above 1/2),
    with its bootstrap interval over seeds and the simulated power at 10 seeds against the
    named alternatives (P in 9 of 10 specimens: the test decides when k >= 9, binomial
    probability 0.74; P in 1 of 10: symmetric)."""
    cases = {"homogeneous/none/kappa1": homogeneous(),
             "uniform/none/kappa1": heterogeneous(10, 3, 0.3)}
    f = by_name(check12.evaluate(cases, "uniform")[0], "heterogeneous kappa = 1")
    t = f["fraction_tests"]["N_main >= 2 in at least half of the specimens"]
    assert (t["k"], t["n"], t["decided"]) == (10, 10, True)
    assert t["ci95_bootstrap"] == [1.0, 1.0]
    assert abs(t["ci95_exact"][0] - 0.025 ** 0.1) < 1e-9 and t["ci95_exact"][1] == 1.0
    assert abs(t["power"]["P in 9 of 10 specimens"] - 0.736) < 0.03  # exact: 0.7361
    assert abs(t["power"]["P in 1 of 10 specimens"] - 0.736) < 0.03
    assert t["seeds_for_power"]["P in 9 of 10 specimens"] == 12
    assert f["status"] == "reproduced"


def test_low_power_is_inconclusive_even_with_eight_seeds():
    """6 of 8 specimens with two or more main cracks: the exact interval [0.35, 0.97] contains
    1/2, the test has power 0.43 against 'P in 9 of 10 specimens' at 8 seeds: inconclusive,
    naming the power and the seeds it would need, never reproduced."""
    het = heterogeneous(8, 3, 0.3)
    het["per_seed"]["n_main_cracks_revised"] = [3, 2, 1, 4, 1, 2, 3, 2]
    cases = {"homogeneous/none/kappa1": homogeneous(), "uniform/none/kappa1": het}
    f = by_name(check12.evaluate(cases, "uniform")[0], "heterogeneous kappa = 1")
    assert f["status"] == "inconclusive" and f["failed"] == []
    note = f["undecided"]["N_main >= 2 in at least half of the specimens"]
    assert "6 of 8 seeds" in note and "power at 8 seeds 0.4" in note
    assert "about 12 seeds for power 0.8" in note


def test_clear_effect_at_eight_seeds_is_decided_both_ways():
    """8 of 8 specimens: reproduced; 0 of 8 (one main crack everywhere): decided false, the
    finding fails that condition by name."""
    cases = {"homogeneous/none/kappa1": homogeneous(),
             "uniform/none/kappa1": heterogeneous(8, 3, 0.3)}
    assert by_name(check12.evaluate(cases, "uniform")[0],
                   "heterogeneous kappa = 1")["status"] == "reproduced"
    cases["uniform/none/kappa1"] = heterogeneous(8, 1, 0.3)
    f = by_name(check12.evaluate(cases, "uniform")[0], "heterogeneous kappa = 1")
    assert f["status"] == "partly"
    assert f["failed"] == ["N_main >= 2 in at least half of the specimens"]


def test_kappa_comparison_pairs_specimens_by_seed_and_states_what_was_held_fixed():
    """kappa = 0.7 against kappa = 1: the same seeds (the same masses) compared pairwise; the
    verdict says whether eps_AS and l_c were held fixed by the config."""
    low = heterogeneous(8, 1, 0.4, near=0.7, area=2e-3)
    low["per_seed"]["crushed_area"] = [2e-3, 2e-3, 5e-4, 5e-4, 5e-4, 5e-4, 5e-4, 5e-4]
    cases = {"uniform/none/kappa0.7": low, "uniform/none/kappa1": heterogeneous(8, 2, 0.3)}
    f = by_name(check12.evaluate(cases, "uniform", "2D", {"as_epsilon": 0.15})[0],
                "heterogeneous kappa = 0.7")
    t = f["fraction_tests"]["crushed area above kappa = 1 in at least half of the specimens"]
    assert (t["k"], t["n"], t["decided"]) == (2, 8, None)  # [0.03, 0.65]: undecided
    assert f["status"] == "inconclusive"
    assert f["values"]["eps_AS and l_c"].startswith("held fixed across kappa by the config "
                                                    "(as_epsilon = 0.15)")
    f = by_name(check12.evaluate(cases, "uniform")[0], "heterogeneous kappa = 0.7")
    assert f["values"]["eps_AS and l_c"].startswith("each kappa's own")


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
