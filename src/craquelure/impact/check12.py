"""Check 12 as revised (impact spec section 10, 2026-12): the source's findings, per seed.

The source shows single images, so a criterion on a heterogeneous case applies to the median
over its seeds, and needs at least :data:`MIN_SEEDS` of them in the profile that claims it:
with fewer the finding is ``inconclusive`` (its numbers are still given). The homogeneous disc
and the homogeneous pre-crack discs are deterministic: one run is the whole population.
Every finding carries each seed's values. Medians come with a percentile bootstrap interval
over seeds and the bootstrap agreement (the fraction of resampled seed sets whose median gives
the same decision as the observed one).

Findings are evaluated per dimension (``dim``: "2D" now; a 3D campaign's findings sit beside
them in the same list). Comparisons across κ (κ = 0.7 against κ = 1) hold the artificial-stress
coefficient ε_AS and the crack-band width ℓ_c fixed: where the runs' recorded values differ the
comparison fails that condition by name.

Reported without a verdict (not findings of the source): the peak contact force per κ and
φ_c(1.5) against φ_c(1).
"""

from __future__ import annotations

import math

import numpy as np

MIN_SEEDS = 8
N_BOOT = 2000
VERTICAL_DEG = 10.0
CENTRE_CELLS = 2.0  # |x| <= 2 Delta at mid-height
COVERAGE = 0.7
TIP_CELLS = 2.0  # "continues from the tips": cracked beyond each tip by >= 2 Delta


def _vals(case: dict | None, q: str) -> list:
    if not case:
        return []
    return [v for v in case["per_seed"].get(q, []) if v is not None and not (
        isinstance(v, float) and math.isnan(v))]


def median_with_interval(values, decide, seed: int = 12) -> dict:
    """Median, 95 % percentile-bootstrap interval over seeds and the bootstrap agreement of
    ``decide(median)`` with the observed decision."""
    v = np.asarray(values, float)
    if v.size == 0:
        return {"median": None, "ci95": None, "agreement": None, "n": 0}
    med = float(np.median(v))
    rng = np.random.default_rng(seed)
    boot = np.median(v[rng.integers(0, v.size, (N_BOOT, v.size))], axis=1)
    agree = float(np.mean([decide(b) == decide(med) for b in boot]))
    lo, hi = np.percentile(boot, [2.5, 97.5])
    return {"median": med, "ci95": [float(lo), float(hi)], "agreement": agree, "n": int(v.size)}


def verdict(conditions: dict[str, bool | None], enough: bool) -> str:
    """reproduced / partly / not reproduced / inconclusive. A heterogeneous case with too few
    seeds is inconclusive whatever its medians say (the failing conditions are still named); a
    deterministic case fails on a failed condition even if another cannot be decided yet, and is
    inconclusive only when everything it can decide passes."""
    if not enough:
        return "inconclusive"
    decided = {k: v for k, v in conditions.items() if v is not None}
    failed = [k for k, v in decided.items() if not v]
    if failed:
        return "not reproduced" if len(failed) == len(conditions) else "partly"
    return "reproduced" if len(decided) == len(conditions) else "inconclusive"


def _per_seed(case: dict | None, quantities) -> dict:
    if not case:
        return {}
    return {str(s): {q: case["per_seed"].get(q, [None] * len(case["seeds"]))[i]
                     for q in quantities}
            for i, s in enumerate(case["seeds"])}


def _finding(name, criterion, conditions, values, per_seed, n_seeds, enough, dim):
    status = verdict(conditions, enough)
    failed = [k for k, v in conditions.items() if v is False]
    return {"finding": name, "criterion": criterion, "dim": dim, "values": values,
            "conditions": conditions, "failed": failed, "per_seed": per_seed,
            "n_seeds": n_seeds, "min_seeds": MIN_SEEDS, "status": status,
            "reproduced": True if status == "reproduced" else (
                None if status == "inconclusive" else False)}


def _same(cases, q) -> tuple[bool, dict]:
    """Whether the recorded ``q`` is one value over all runs of ``cases`` (by label)."""
    seen = {label: sorted({round(float(v), 12) for v in _vals(c, q)}) for label, c in
            cases.items() if c}
    flat = {v for vs in seen.values() for v in vs}
    return len(flat) <= 1, seen


def evaluate(cases: dict, dist: str, dim: str = "2D") -> tuple[list[dict], dict]:
    """(findings, reported-without-verdict) of one campaign's cases."""
    out = []
    homo = cases.get("homogeneous/none/kappa1")
    het = {k: cases.get(f"{dist}/none/kappa{k:g}") for k in (0.7, 1.0, 1.5)}
    spacing = None
    for c in cases.values():
        sp = _vals(c, "spacing")
        if sp:
            spacing = sp[0]
            break
    phi_het1 = _vals(het[1.0], "cracked_fraction")
    if homo:
        g = {q: (_vals(homo, q) or [None])[0] for q in (
            "n_main_cracks_revised", "main_crack_x_mid", "main_crack_theta_deg",
            "crushed_area", "main_crack_length_revised", "second_crack_length",
            "cracked_fraction")}
        n_het1 = len(phi_het1)
        conditions = {
            "one main crack": g["n_main_cracks_revised"] == 1,
            "along the vertical diameter (|x| <= 2 Delta at mid-height, theta within 10 deg)":
                (g["main_crack_x_mid"] is not None and spacing is not None
                 and abs(g["main_crack_x_mid"]) <= CENTRE_CELLS * spacing * (1 + 1e-9)
                 and abs(g["main_crack_theta_deg"]) <= VERTICAL_DEG),
            "crushed zone at the contact": (g["crushed_area"] or 0) > 0,
            "no second crack longer than half the main one":
                (g["second_crack_length"] or 0) <= 0.5 * (g["main_crack_length_revised"] or 0)
                if g["n_main_cracks_revised"] else False,
            "cracked fraction below every heterogeneous kappa = 1 specimen's":
                (g["cracked_fraction"] < min(phi_het1)) if n_het1 >= MIN_SEEDS else None,
        }
        out.append(_finding(
            "homogeneous: one main crack along the vertical diameter, crushed contact zone, "
            "very high resistance to complete failure",
            "N_main = 1 (cracked cluster from the contact zone reaching >= 0.5 D), |x_mid| <= "
            "2 Delta, |theta| <= 10 deg, A_cr > 0, second crack <= half the main one, phi_c < "
            "every heterogeneous kappa = 1 specimen's (needs >= 8 seeds)",
            conditions, {**g, "phi_c_heterogeneous_kappa1": phi_het1},
            {"0": g}, 1, True, dim))
    keys = ("n_main_cracks_revised", "cracked_fraction", "n_secondary_cracks",
            "cracked_fraction_near_main", "crushed_area", "main_crossings_x_mm",
            "as_epsilon", "crack_band_width")
    if het[1.0]:
        n = len(het[1.0]["seeds"])
        phi_h = (_vals(homo, "cracked_fraction") or [None])[0]
        nm = median_with_interval(_vals(het[1.0], "n_main_cracks_revised"), lambda m: m >= 2)
        ph = median_with_interval(phi_het1, lambda m: phi_h is not None and m > phi_h)
        out.append(_finding(
            "heterogeneous kappa = 1: multiple main cracks developing simultaneously, more "
            "damage than the homogeneous disc",
            "median N_main >= 2 and median phi_c above the homogeneous disc's (>= 8 seeds)",
            {"median N_main >= 2": nm["median"] is not None and nm["median"] >= 2,
             "median phi_c above homogeneous": (ph["median"] is not None and phi_h is not None
                                                and ph["median"] > phi_h)},
            {"N_main": nm, "phi_c": ph, "phi_c_homogeneous": phi_h},
            _per_seed(het[1.0], keys), n, n >= MIN_SEEDS, dim))
    if het[1.5]:
        n = len(het[1.5]["seeds"])
        nm = median_with_interval(_vals(het[1.5], "n_main_cracks_revised"), lambda m: m == 1)
        ns = median_with_interval(_vals(het[1.5], "n_secondary_cracks"), lambda m: m >= 1)
        out.append(_finding(
            "heterogeneous kappa = 1.5: heterogeneity smoothed, one main crack with shorter "
            "cracks beside it",
            "median N_main = 1 and median number of shorter (non-main, > 2 Delta) cracks >= 1 "
            "(>= 8 seeds)",
            {"median N_main = 1": nm["median"] == 1,
             "shorter cracks beside it": ns["median"] is not None and ns["median"] >= 1},
            {"N_main": nm, "n_secondary_cracks": ns}, _per_seed(het[1.5], keys), n,
            n >= MIN_SEEDS, dim))
    if het[0.7] and het[1.0]:
        n = min(len(het[0.7]["seeds"]), len(het[1.0]["seeds"]))
        nm = median_with_interval(_vals(het[0.7], "n_main_cracks_revised"), lambda m: m == 1)
        near = {k: median_with_interval(_vals(het[k], "cracked_fraction_near_main"),
                                        lambda m: True) for k in (0.7, 1.0)}
        area = {k: median_with_interval(_vals(het[k], "crushed_area"), lambda m: True)
                for k in (0.7, 1.0)}
        same_eps, eps = _same({"0.7": het[0.7], "1.0": het[1.0]}, "as_epsilon")
        same_band, band = _same({"0.7": het[0.7], "1.0": het[1.0]}, "crack_band_width")

        def larger(d):
            a, b = d[0.7]["median"], d[1.0]["median"]
            return a is not None and b is not None and a > b

        out.append(_finding(
            "heterogeneous kappa = 0.7: one main crack, larger failure along it and at the "
            "contact than at kappa = 1",
            "median N_main = 1; median cracked fraction within 3 Delta of the main crack and "
            "median A_cr above kappa = 1's; eps_AS and l_c the same at both kappa (>= 8 seeds)",
            {"median N_main = 1": nm["median"] == 1,
             "cracked fraction near the main crack above kappa = 1": larger(near),
             "crushed area above kappa = 1": larger(area),
             "eps_AS the same at kappa = 0.7 and 1": same_eps,
             "l_c the same at kappa = 0.7 and 1": same_band},
            {"N_main": nm, "cracked_fraction_near_main": {str(k): v for k, v in near.items()},
             "crushed_area": {str(k): v for k, v in area.items()}, "as_epsilon": eps,
             "crack_band_width": band},
            {"0.7": _per_seed(het[0.7], keys), "1.0": _per_seed(het[1.0], keys)}, n,
            n >= MIN_SEEDS, dim))
    pkeys = ("precrack_coverage", "precrack_tip_extension_low", "precrack_tip_extension_high",
             "main_cracks_elsewhere", "n_main_cracks_revised", "main_crossings_x_mm")
    for key in sorted(k for k in cases if k.endswith("/kappa1") and "/pf" in k):
        masses, layout, _ = key.split("/")
        c = cases[key]
        n = len(c["seeds"])
        deterministic = masses == "homogeneous"
        cov = median_with_interval(_vals(c, "precrack_coverage"), lambda m: m >= COVERAGE)
        tips = median_with_interval(
            [min(a, b) for a, b in zip(_vals(c, "precrack_tip_extension_low"),
                                       _vals(c, "precrack_tip_extension_high"), strict=False)],
            lambda m: spacing is not None and m >= TIP_CELLS * spacing)
        other = median_with_interval(_vals(c, "main_cracks_elsewhere"), lambda m: m == 0)
        out.append(_finding(
            f"{layout} ({masses}): the main crack follows the zero-mass line, with few cracks "
            "elsewhere",
            "cracked particles within Delta of the line over >= 70 % of its length, the crack "
            "continues >= 2 Delta beyond both tips, no main crack crossing the centre row more "
            "than 3 Delta from the line" + ("" if deterministic else " (medians, >= 8 seeds)"),
            {"covers >= 70 % of the line": cov["median"] is not None
             and cov["median"] >= COVERAGE,
             "continues from both tips": tips["median"] is not None and spacing is not None
             and tips["median"] >= TIP_CELLS * spacing,
             "no main crack elsewhere": other["median"] == 0},
            {"coverage": cov, "tip_extension_min_m": tips, "main_cracks_elsewhere": other},
            _per_seed(c, pkeys), n, deterministic or n >= MIN_SEEDS, dim))
    force = {f"{k:g}": (_vals(cases.get(f"homogeneous/none/kappa{k:g}"),
                               "contact_force_peak") or [None])[0] for k in (0.7, 1.0, 1.5)}
    phi = {f"{k:g}": median_with_interval(_vals(het[k], "cracked_fraction"), lambda m: True)
           for k in (1.0, 1.5) if het[k]}
    reported = {"dim": dim, "peak_contact_force_homogeneous_N_per_m": force,
                "phi_c_heterogeneous_kappa_1_and_1.5": phi}
    return out, reported
