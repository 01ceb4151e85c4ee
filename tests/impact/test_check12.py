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
