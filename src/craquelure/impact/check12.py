"""Check 12 (impact spec section 10): the source's findings, per seed and per dimension.

The source shows single images, so a criterion on a heterogeneous case applies to the median
specimen over its seeds, and needs at least :data:`MIN_SEEDS` of them in the profile that claims
it: with fewer the finding is ``inconclusive`` (its numbers are still given). The homogeneous
disc and the homogeneous pre-crack discs are deterministic: one run is the whole population.
Every finding carries each seed's values.

Fractional conditions [D]. "The median specimen has property P" is "P holds in at least half
of the specimens": a fraction of seeds against 1/2, decided by the exact binomial interval of
:func:`craquelure.validation.fraction_decision` (95 %, two-sided): true above 1/2, false below,
undecided when it straddles 1/2. Each reports k of n seeds, a percentile bootstrap interval, the
exact interval, and the power at the run's own seed count against P in 9 of 10 specimens and in
1 of 10 (:func:`craquelure.validation.fraction_power`), with the seeds that power 0.8 needs
(8 seeds decide only 8 of 8 or 0 of 8; power 0.8 against 9 in 10 needs 12). κ comparisons
(κ = 0.7 against κ = 1) pair the specimens by seed (the seed alone draws the masses) and count
the seeds where κ = 0.7's value is the larger. They report ε_AS and ℓ_c of every run and
fail that condition by name where they differ (``impact.fixed_across_kappa`` holds them fixed).

Each finding's defining condition decides it (:func:`verdict`); the heterogeneous rows' is the
spec's own median rule (:func:`median_rule`). Reported without a verdict (not findings of the
source): the peak contact force per κ and φ_c(1.5) against φ_c(1).
"""

from __future__ import annotations

import math
import operator

import numpy as np

from craquelure.impact.workflow import SOURCE_KAPPAS, case_key
from craquelure.validation import (
    POWER_NEEDED,
    bootstrap_interval,
    fraction_decision,
    fraction_interval,
    fraction_power,
    samples_for_power,
)

MIN_SEEDS = 8
N_BOOT = 2000
VERTICAL_DEG = 10.0
CENTRE_CELLS = 2.0  # |x| <= 2 Delta at mid-height
COVERAGE = 0.7
TIP_CELLS = 2.0  # "continues from the tips": cracked beyond each tip by >= 2 Delta
MEDIAN_SPECIMEN = 0.5  # "the median specimen has P": P in at least half of the specimens
# The named alternatives of the fractional tests: P in 9 of 10 specimens, P in 1 of 10.
ALTERNATIVES = {"P in 9 of 10 specimens": 0.9, "P in 1 of 10 specimens": 0.1}


def _missing(v) -> bool:
    return v is None or (isinstance(v, float) and math.isnan(v))


def _vals(case: dict | None, q: str) -> list:
    return [v for v in case["per_seed"].get(q, []) if not _missing(v)] if case else []


def _first(case: dict | None, q: str):
    """The first seed's value of ``q`` (None when there is none)."""
    return next(iter(_vals(case, q)), None)


def median_with_interval(values, decide, seed: int = 12) -> dict:
    """Median, 95 % bootstrap interval and bootstrap agreement of ``decide(median)``."""
    v = np.asarray(values, float)
    if v.size == 0:
        return {"median": None, "ci95": None, "agreement": None, "n": 0}
    med = float(np.median(v))
    rng = np.random.default_rng(seed)
    boot = np.median(v[rng.integers(0, v.size, (N_BOOT, v.size))], axis=1)
    agree = float(np.mean([decide(b) == decide(med) for b in boot]))
    return {"median": med, "ci95": bootstrap_interval(boot), "agreement": agree, "n": int(v.size)}


def fraction_test(flags, deterministic: bool = False, seed: int = 12) -> dict:
    """"P holds in at least half of the specimens" over one flag per seed (None: not measurable,
    left out); ``deterministic``: one run is the whole population (its flag decides)."""
    flags = [bool(f) for f in flags if f is not None]
    n, k = len(flags), int(sum(flags))
    out = {"k": k, "n": n, "fraction": k / n if n else None, "threshold": MEDIAN_SPECIMEN}
    if deterministic or n == 0:
        out.update(decided=(flags[0] if n == 1 else None) if deterministic else None,
                   needs="" if n else "at least one run")
        return out
    decided, needs = fraction_decision(k, n, MEDIAN_SPECIMEN)
    boot = np.asarray(flags, float)[np.random.default_rng(seed).integers(0, n, (N_BOOT, n))]
    out.update({
        "decided": decided, "needs": needs,
        "ci95_bootstrap": bootstrap_interval(boot.mean(axis=1)),
        "ci95_exact": list(fraction_interval(k, n)),
        "power": {name: fraction_power(n, p, MEDIAN_SPECIMEN)
                  for name, p in ALTERNATIVES.items()},
        "seeds_for_power": {name: samples_for_power(n, p, MEDIAN_SPECIMEN)
                            for name, p in ALTERNATIVES.items()},
    })
    return out


MEDIAN_AGREEMENT = 0.95  # the median rule decides when 95 % of bootstrap medians agree


def median_rule(case: dict | None, q: str, decide) -> dict:
    """The spec's median rule as a defining condition: "the median specimen has P" (``decide``
    on the median of ``q`` over the seeds), decided when at least 95 % of the bootstrap medians
    agree; the exact binomial test of :func:`fraction_test` on the per-seed flags beside it."""
    med = median_with_interval(_vals(case, q), decide)
    test = fraction_test(_flags(case, q, decide))
    decided = None
    if med["median"] is not None and med["agreement"] >= MEDIAN_AGREEMENT:
        decided = bool(decide(med["median"]))
    test.update({"rule": "median over the seeds (bootstrap agreement >= "
                         f"{MEDIAN_AGREEMENT:g})", "median": med["median"],
                 "ci95_median": med["ci95"], "agreement": med["agreement"],
                 "binomial_decided": test["decided"], "decided": decided})
    return test


def undecided_note(test: dict) -> str:
    """What an undecided fractional condition would need: its power and seed counts."""
    if not test["n"]:
        return test["needs"]
    lead = (f"median {test['median']:g}, bootstrap agreement {test['agreement']:.2f} < "
            f"{MEDIAN_AGREEMENT:g}; ") if "rule" in test else ""
    if "power" not in test:
        return lead + test.get("needs", "")
    power = ", ".join(f"{p:.2f} against {name}" for name, p in test["power"].items())
    more = set(test["seeds_for_power"].values())
    need = (f"about {max(more)} seeds for power {POWER_NEEDED:g}" if None not in more else
            f"more than 200 seeds for power {POWER_NEEDED:g}")
    lo, hi = test["ci95_exact"]
    return lead + (f"{test['k']} of {test['n']} seeds, exact 95 % interval [{lo:.2f}, "
                   f"{hi:.2f}] contains 1/2; power at {test['n']} seeds {power}; {need}"
                   + (f" ({test['needs']})" if test["needs"] else ""))


def verdict(conditions: dict[str, bool | None], enough: bool,
            defining: tuple[str, ...] = ()) -> str:
    """reproduced / partly / not reproduced / inconclusive, by the finding's defining
    condition (``defining``: the names of its parts, default all; spec check 12): a defining
    part that fails: "not reproduced"; one undecided, or too few seeds (``enough`` False):
    "inconclusive"; else any other condition not met makes it "partly"."""
    defining = tuple(defining) or tuple(conditions)
    core = [conditions[k] for k in defining]
    if any(v is False for v in core):
        return "not reproduced"
    if not enough or any(v is None for v in core):
        return "inconclusive"
    others = [v for k, v in conditions.items() if k not in defining]
    return "reproduced" if all(v is True for v in others) else "partly"


def _per_seed(case: dict | None, quantities) -> dict:
    if not case:
        return {}
    return {str(s): {q: case["per_seed"].get(q, [None] * len(case["seeds"]))[i]
                     for q in quantities}
            for i, s in enumerate(case["seeds"])}


def _finding(name, criterion, conditions, values, per_seed, n_seeds, enough, dim,
             defining: tuple[str, ...] = ()):
    """``conditions``: name -> bool/None, or name -> a :func:`fraction_test` result; ``defining``:
    the defining condition's parts (:func:`verdict`, the criterion's leading "◆ ...")."""
    tests = {k: v for k, v in conditions.items() if isinstance(v, dict)}
    conditions = {k: (v["decided"] if isinstance(v, dict) else v) for k, v in conditions.items()}
    status = verdict(conditions, enough, defining)
    failed = [k for k, v in conditions.items() if v is False]
    undecided = {k: undecided_note(tests[k]) for k, v in conditions.items()
                 if v is None and k in tests}
    defining = list(defining) or list(conditions)
    return {"finding": name, "criterion": "◆ " + "; ".join(defining) + " | also: " + criterion,
            "defining": defining, "dim": dim, "values": values,
            "conditions": conditions, "failed": failed, "undecided": undecided,
            "fraction_tests": tests, "per_seed": per_seed, "n_seeds": n_seeds,
            "min_seeds": MIN_SEEDS, "status": status,
            "reproduced": True if status == "reproduced" else (
                None if status == "inconclusive" else False)}


def _same(cases, q) -> tuple[bool, dict]:
    """Whether the recorded ``q`` is one value over all runs of ``cases`` (by label)."""
    seen = {label: sorted({round(float(v), 12) for v in _vals(c, q)}) for label, c in
            cases.items() if c}
    flat = {v for vs in seen.values() for v in vs}
    return len(flat) <= 1, seen


def _flags(case: dict | None, q: str, test) -> list:
    """One flag per seed of ``case``: ``test(value)``, None where the value is missing."""
    return [None if _missing(v) else bool(test(v))
            for v in case["per_seed"].get(q, [])] if case else []


def _by_seed(a: dict | None, b: dict | None, q: str, compare) -> list:
    """Per seed common to both cases: ``compare(a's q, b's q)``, None if either is missing."""
    if not a or not b:
        return []
    va = dict(zip(a["seeds"], a["per_seed"].get(q, []), strict=False))
    vb = dict(zip(b["seeds"], b["per_seed"].get(q, []), strict=False))
    return [None if _missing(va[s]) or _missing(vb[s]) else compare(va[s], vb[s])
            for s in sorted(set(va) & set(vb))]


GROWTH_MAX = 1.2  # "does not open further": opening at 1 ms <= 1.2 x at 0.5 ms [D]
FORCE_DIFFERENCE = 0.05  # "contact forces differ": |F(0.7) - F(1)| > 5 % of F(1) [D]
MOST = 0.5  # "carries most of the centre row's opening": share > 1/2


def evaluate(cases: dict, dist: str, dim: str = "2D",
             fixed_across_kappa: dict | None = None) -> tuple[list[dict], dict]:
    """(findings, reported-without-verdict) of one dimension's cases (keys
    ``<masses>/<pre-crack>/kappa<k>``). Cracks are counted by opening
    (:func:`craquelure.impact.measure.opening_cracks`); the softening-based counts stay in the
    per-seed values as secondary numbers. Each finding names its defining condition (◆, spec
    check 12, worded in the conditions below): the homogeneous disc's one vertical main crack
    that stops opening; the heterogeneous discs' main-crack count in the median specimen
    (:func:`median_rule`: N_main >= 2 at kappa = 1, N_main = 1 at 0.7 and 1.5); the homogeneous
    pre-crack discs' opening along the zero-mass line. Heterogeneous pre-crack variants are
    beyond the source: their numbers go to ``reported["beyond_the_source"]``, no verdict.

    ``fixed_across_kappa``: the config's values of eps_AS and l_c held fixed across kappa
    (empty: each kappa's own), stated in the kappa comparison."""
    out = []
    homo = cases.get(case_key("homogeneous", "none", 1.0))
    het = {k: cases.get(case_key(dist, "none", k)) for k in SOURCE_KAPPAS}
    spacing = next((_first(c, "spacing") for c in cases.values() if _vals(c, "spacing")), None)
    phi_het1 = _vals(het[1.0], "cracked_fraction")
    if homo:
        g = {q: _first(homo, q) for q in (
            "n_main_cracks_opening", "main_run_x_mid", "main_crack_theta_opening_deg",
            "main_run_share", "main_run_opening", "main_run_opening_half",
            "main_run_opening_growth", "crushed_area", "main_crack_length_opening",
            "second_crack_length_opening", "cracked_fraction", "row_runs_x_mm",
            "row_runs_opening_mm", "n_main_cracks_revised")}
        one = "one main crack (N_main = 1, by opening)"
        most = "it carries most (> 1/2) of the centre row's opening"
        along = "along the vertical diameter (|x| <= 2 Delta at mid-height, theta within 10 deg)"
        still = ("it does not open further between 0.5 and 1 ms (opening at 1 ms <= "
                 f"{GROWTH_MAX:g} x at 0.5 ms)")
        growth = g["main_run_opening_growth"]
        conditions = {
            one: g["n_main_cracks_opening"] == 1 if g["n_main_cracks_opening"] is not None
            else None,
            most: (g["main_run_share"] > MOST) if g["main_run_share"] is not None else False,
            along: (g["main_run_x_mid"] is not None and spacing is not None
                    and abs(g["main_run_x_mid"]) <= CENTRE_CELLS * spacing * (1 + 1e-9)
                    and g["main_crack_theta_opening_deg"] is not None
                    and abs(g["main_crack_theta_opening_deg"]) <= VERTICAL_DEG),
            still: (None if growth is None and g["main_run_opening"] else
                    bool(growth is not None and growth <= GROWTH_MAX)),
            "crushed zone at the contact": (g["crushed_area"] or 0) > 0,
            "no second crack longer than half the main one":
                (g["second_crack_length_opening"] or 0)
                <= 0.5 * (g["main_crack_length_opening"] or 0)
                if g["n_main_cracks_opening"] else False,
            "cracked fraction below every heterogeneous kappa = 1 specimen's":
                (g["cracked_fraction"] < min(phi_het1)) if len(phi_het1) >= MIN_SEEDS else None,
        }
        out.append(_finding(
            "homogeneous: one main crack along the vertical diameter, crushed contact zone, "
            "very high resistance to complete failure",
            "A_cr > 0, second crack <= half the main one, phi_c < every heterogeneous kappa = 1"
            " specimen's (needs >= 8 seeds)",
            conditions, {**g, "phi_c_heterogeneous_kappa1": phi_het1},
            {"0": g}, 1, True, dim, defining=(one, most, along, still)))
    keys = ("n_main_cracks_opening", "row_runs_x_mm", "row_runs_opening_mm",
            "main_run_share", "cracked_fraction", "n_secondary_cracks_opening",
            "cracked_fraction_near_main", "crushed_area", "contact_force_peak",
            "n_main_cracks_revised", "as_epsilon", "crack_band_width")

    def hetero(kappa, name, criterion, key, decide, others, values, per_seed=None, n=None):
        """A heterogeneous finding defined by ``key``: ``decide`` on the median N_main."""
        case = het[kappa]
        n = len(case["seeds"]) if n is None else n
        nm = median_with_interval(_vals(case, "n_main_cracks_opening"), decide)
        out.append(_finding(
            name, criterion, {key: median_rule(case, "n_main_cracks_opening", decide), **others},
            {"N_main": nm, **values}, per_seed or _per_seed(case, keys), n, n >= MIN_SEEDS, dim,
            defining=(key,)))

    if het[1.0]:
        phi_h = _first(homo, "cracked_fraction")
        hetero(
            1.0, "heterogeneous kappa = 1: multiple main cracks developing simultaneously, more "
            "damage than the homogeneous disc",
            "phi_c above the homogeneous disc's in at least half of the specimens (>= 8 seeds,"
            " exact binomial interval above 1/2)",
            "N_main >= 2 in the median specimen", lambda m: m >= 2,
            {"phi_c above homogeneous in at least half of the specimens":
                fraction_test(_flags(het[1.0], "cracked_fraction", lambda m: m > phi_h)
                              if phi_h is not None else [])},
            {"phi_c": median_with_interval(phi_het1, lambda m: phi_h is not None and m > phi_h),
             "phi_c_homogeneous": phi_h})
    if het[1.5]:
        hetero(
            1.5, "heterogeneous kappa = 1.5: heterogeneity smoothed, one main crack with shorter "
            "cracks beside it",
            ">= 1 shorter (non-main, > 2 Delta) crack in at least half of the specimens "
            "(>= 8 seeds, exact binomial interval above 1/2)",
            "N_main = 1 in the median specimen", lambda m: m == 1,
            {"shorter cracks beside it in at least half of the specimens":
                fraction_test(_flags(het[1.5], "n_secondary_cracks_opening", lambda m: m >= 1))},
            {"n_secondary_cracks": median_with_interval(
                _vals(het[1.5], "n_secondary_cracks_opening"), lambda m: m >= 1)})
    if het[0.7] and het[1.0]:
        spread = {q: {str(k): median_with_interval(_vals(het[k], q), lambda _: True)
                      for k in (0.7, 1.0)}
                  for q in ("cracked_fraction_near_main", "crushed_area", "contact_force_peak")}
        same_eps, eps = _same({"0.7": het[0.7], "1.0": het[1.0]}, "as_epsilon")
        same_band, band = _same({"0.7": het[0.7], "1.0": het[1.0]}, "crack_band_width")
        fixed = dict(fixed_across_kappa or {})
        held = ("held fixed across kappa by the config (" + ", ".join(
            f"{k} = {v:g}" for k, v in sorted(fixed.items())) + ")") if fixed else (
            "each kappa's own (not held fixed by the config)")

        def paired(q, compare=operator.gt):
            return fraction_test(_by_seed(het[0.7], het[1.0], q, compare))

        hetero(
            0.7, "heterogeneous kappa = 0.7: one main crack, larger failure along it and at the "
            "contact than at kappa = 1, contact forces differ between kappa values",
            "in at least half of the specimens (>= 8 seeds, exact binomial interval above "
            "1/2), the same specimen (seed) compared at kappa = 0.7 and 1: a larger cracked "
            "fraction within 3 Delta of the main crack, a larger A_cr, a peak contact force "
            f"differing by more than {FORCE_DIFFERENCE:.0%}; eps_AS and l_c the same at both "
            "kappa",
            "N_main = 1 in the median specimen", lambda m: m == 1,
            {"cracked fraction near the main crack above kappa = 1 in at least half of the "
             "specimens": paired("cracked_fraction_near_main"),
             "crushed area above kappa = 1 in at least half of the specimens":
                paired("crushed_area"),
             "peak contact force differs from kappa = 1 in at least half of the specimens":
                paired("contact_force_peak",
                       lambda a, b: abs(a - b) > FORCE_DIFFERENCE * abs(b)),
             "eps_AS the same at kappa = 0.7 and 1": same_eps,
             "l_c the same at kappa = 0.7 and 1": same_band},
            {**spread, "as_epsilon": eps, "crack_band_width": band, "eps_AS and l_c": held},
            {"0.7": _per_seed(het[0.7], keys), "1.0": _per_seed(het[1.0], keys)},
            min(len(het[0.7]["seeds"]), len(het[1.0]["seeds"])))
    pkeys = ("precrack_coverage_opening", "precrack_largest_opening_on_line",
             "precrack_line_max_opening", "max_opening", "precrack_tip_extension_low",
             "precrack_tip_extension_high", "main_cracks_elsewhere_opening",
             "n_main_cracks_opening", "row_runs_x_mm", "precrack_coverage")
    beyond = []
    for key in sorted(k for k in cases if "/pf" in k and k == case_key(*k.split("/")[:2], 1.0)):
        masses, layout, _ = key.split("/")
        c = cases[key]
        if masses != "homogeneous":  # the source's pre-crack discs are homogeneous
            beyond.append({"case": key, "n_seeds": len(c["seeds"]),
                           "per_seed": _per_seed(c, pkeys),
                           "note": "beyond the source (its pre-crack figures are of "
                                   "homogeneous discs): reported without a verdict"})
            continue
        v = {q: _first(c, q) for q in pkeys}
        ends = (v["precrack_tip_extension_low"], v["precrack_tip_extension_high"])
        tips = None if None in ends else min(ends)
        largest = f"the largest opening lies on the {layout} line"
        covers = f"the line opens over >= {COVERAGE:.0%} of its length (by opening)"
        out.append(_finding(
            f"{layout} ({masses}): the main crack follows the zero-mass line, with few cracks "
            "elsewhere",
            f"the crack continues >= {TIP_CELLS:g} Delta beyond both tips (softening, "
            "secondary), no main crack crossing the centre row more than 3 Delta from the line",
            {largest: v["precrack_largest_opening_on_line"],
             covers: (v["precrack_coverage_opening"] >= COVERAGE
                      if v["precrack_coverage_opening"] is not None else None),
             "continues from both tips": (None if tips is None or spacing is None
                                          else tips >= TIP_CELLS * spacing),
             "no main crack elsewhere": (v["main_cracks_elsewhere_opening"] == 0
                                         if v["main_cracks_elsewhere_opening"] is not None
                                         else None)},
            {**v, "tip_extension_min_m": tips}, {"0": v}, 1, True, dim, defining=(largest, covers)))
    force = {f"{k:g}": _first(cases.get(case_key("homogeneous", "none", k)), "contact_force_peak")
             for k in SOURCE_KAPPAS}
    phi = {f"{k:g}": median_with_interval(_vals(het[k], "cracked_fraction"), lambda m: True)
           for k in (1.0, 1.5) if het[k]}
    # the contact force of a plane slice is per unit thickness, the 3D disc's a force
    unit = "N" if dim == "3D" else "N_per_m"
    reported = {"dim": dim, f"peak_contact_force_homogeneous_{unit}": force,
                "phi_c_heterogeneous_kappa_1_and_1.5": phi, "beyond_the_source": beyond}
    return out, reported
