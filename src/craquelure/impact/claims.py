"""The impact paper's findings for the validation report (:mod:`craquelure.validation`).

Source: ``results/impact/summary.json``, whose ``findings`` already carry check 12's criteria
and statuses per dimension (:mod:`.check12`); this module words them as claims, each finding's
3D and 2D rows side by side, and adds the robustness demand (every variant to the end, closed
energy balance).
"""

from __future__ import annotations

import json
import math
from pathlib import Path

from craquelure.validation import VERDICTS, Claim

MODEL = "impact"
# Spec check 9's energy-balance tolerance, applied to every run of the campaign.
ENERGY_BALANCE_MAX = 0.02
DIMENSIONS = ("3D", "2D")  # check 12's rows: the source's 3D runs beside the 2D baseline
SOURCE = "impact spec section 7; check 12 (revised 2026-12)"


def _number(value) -> str:
    if isinstance(value, float):
        return f"{value:.3g}" if math.isfinite(value) else str(value)
    if isinstance(value, dict):
        return "{" + ", ".join(f"{k}: {_number(v)}" for k, v in value.items()) + "}"
    if isinstance(value, list | tuple):
        return "[" + ", ".join(_number(v) for v in value) + "]"
    return str(value)


def _brief(value) -> str:
    """Medians with their interval for the report: {median, ci95, agreement, n}."""
    if isinstance(value, dict) and "median" in value and "ci95" in value:
        if value["median"] is None:
            return "no data"
        lo, hi = value["ci95"]
        return (f"median {_number(value['median'])} [95 % {_number(lo)}, {_number(hi)}], "
                f"n = {value['n']}, bootstrap agreement {value['agreement']:.2f}")
    if isinstance(value, dict):
        return "{" + ", ".join(f"{k}: {_brief(v)}" for k, v in value.items()) + "}"
    return _number(value)


SHORT = {"n_main_cracks_revised": "N", "cracked_fraction": "phi_c", "crushed_area": "A_cr",
         "n_secondary_cracks": "short", "cracked_fraction_near_main": "phi_near",
         "main_crossings_x_mm": "x_mm", "precrack_coverage": "coverage",
         "main_cracks_elsewhere": "elsewhere", "as_epsilon": "eps_AS",
         "crack_band_width": "l_c"}


def per_seed_text(per_seed: dict) -> str:
    """Every seed's values, compact: 'seed 1: N 5, phi_c 0.63, ...' (nested by kappa where a
    finding compares two cases)."""
    def one(values: dict) -> str:
        return ", ".join(f"{SHORT[q]} {_number(v)}" for q, v in values.items() if q in SHORT)

    parts = []
    for key, val in per_seed.items():
        if val and all(isinstance(v, dict) for v in val.values()):
            parts.append(f"kappa {key}: " + "; ".join(f"seed {s}: {one(v)}"
                                                     for s, v in val.items()))
        elif isinstance(val, dict):
            parts.append(f"seed {key}: {one(val)}")
    return " | ".join(parts)


def _fraction_text(name: str, test: dict) -> str:
    """A fractional condition: k of n seeds, bootstrap and exact intervals, power."""
    if "power" not in test:
        return f"{name}: {test['k']} of {test['n']} run(s)"
    lo, hi = test["ci95_bootstrap"]
    power = ", ".join(f"{p:.2f} against {alt}" for alt, p in test["power"].items())
    return (f"{name}: {test['k']} of {test['n']} seeds (fraction {test['fraction']:.2f}, "
            f"bootstrap 95 % [{lo:.2f}, {hi:.2f}], exact 95 % [{test['ci95_exact'][0]:.2f}, "
            f"{test['ci95_exact'][1]:.2f}]; power {power})")


# The report figure that shows each check-12 finding's case (2D: the figures draw the 2D runs).
FIGURES = (("homogeneous:", "impact_damage_homogeneous.png"),
           ("heterogeneous kappa = 1:", "impact_damage_heterogeneous_kappa1.png"),
           ("heterogeneous kappa = ", "impact_damage_heterogeneous_kappa_low_high.png"),
           ("pf", "impact_precracks.png"))


# 3D rows: the pictures of the judged runs (rule impact_judged_figures draws the 3D campaign).
FIGURES_3D = (("pf", "impact_judged_time_sequence.png"), ("", "impact_judged_opening_maps.png"))


def figure_of(finding: dict, rate: bool = False) -> str:
    """The row's picture, of the rate campaign's runs for a row with rate effects
    (``impact_judged_rate_*``, ``impact_rate_*``)."""
    if finding.get("dim", "2D") != "2D":
        name = next(name for prefix, name in FIGURES_3D if finding["finding"].startswith(prefix))
        return name.replace("judged_", "judged_rate_") if rate else name
    name = next((name for prefix, name in FIGURES if finding["finding"].startswith(prefix)), "")
    return name.replace("impact_", "impact_rate_", 1) if rate and name else name


def deciding_number(finding: dict) -> str:
    """The number the verdict turns on: the first failing condition's (else the first
    undecided one's, else the first's): k of n specimens for a fraction, else yes or no."""
    conditions = finding.get("conditions", {})
    tests = finding.get("fraction_tests", {})
    name = next((k for k, v in conditions.items() if v is False),
                next((k for k, v in conditions.items() if v is None), next(iter(conditions), None)))
    test = tests.get(name)
    if test and "k" in test:
        return f"{name.split(' in at least half')[0]}: {test['k']} of {test['n']}"
    return f"{name}: {'yes' if conditions[name] else 'no'}" if name is not None else ""


def finding_claim(finding: dict, caveat: str, rate: bool = False) -> Claim:
    """A check-12 finding (status computed by :mod:`.check12`), with every seed's values and
    each fractional condition's statistic, intervals and power."""
    measured = "; ".join(f"{k} = {_brief(v)}" for k, v in finding["values"].items())
    tests = finding.get("fraction_tests", {})
    if tests:
        measured += "; " + "; ".join(_fraction_text(k, t) for k, t in tests.items())
    seeds = per_seed_text(finding.get("per_seed", {}))
    if seeds and finding.get("n_seeds", 1) > 1:
        measured += f"; per seed: {seeds}"
    status = finding.get("status")
    dim = finding.get("dim", "2D")
    notes = [f"{dim}; {caveat}"]
    if finding.get("undecided"):
        notes.insert(0, "cannot decide: " + "; ".join(
            f"{k} ({v})" for k, v in finding["undecided"].items()))
    if finding.get("failed"):
        notes.insert(0, "fails: " + ", ".join(finding["failed"]))
    if status == "inconclusive" and finding.get("n_seeds", 0) < finding.get("min_seeds", 0):
        notes.insert(0, f"inconclusive: {finding['n_seeds']} seeds, the profile needs >= "
                        f"{finding['min_seeds']} per heterogeneous case to decide")
    elif status not in VERDICTS:  # a finding whose case did not run
        status = "inconclusive"
        notes.insert(0, "not run")
    return Claim(MODEL, f"[{dim}, {rate_label(rate)}] {finding['finding']}", SOURCE,
                 finding["criterion"], measured, status, "; ".join(notes),
                 deciding=deciding_number(finding), figure=figure_of(finding, rate))


def rate_label(rate: bool) -> str:
    return "with rate effects" if rate else "without rate effects"


def with_rate(summary: dict) -> bool:
    """Did the summary's runs use CSCM's rate effects (their material model says so)?"""
    models = [m for ms in summary.get("material_model_by_dim", {}).values() for m in ms]
    models += summary.get("material_model", [])
    return any("rate_effects" in m.split("+") for m in models)


def not_run_claim(finding: dict, dim: str, profile: str, rate: bool = False) -> Claim:
    """The row of a dimension the profile did not run, beside the other dimension's."""
    return Claim(MODEL, f"[{dim}, {rate_label(rate)}] {finding['finding']}", SOURCE,
                 finding["criterion"], f"no {dim} runs", "inconclusive",
                 f"not run: profile {profile} has no {dim} runs of this case",
                 deciding=f"no {dim} runs")


# the source ran its 3D disc with LS-DYNA's CSCM concrete; ours is "cap" (+ its extras)
SOURCE_MODEL = "cap"


def caveat_of(summary: dict, dim: str) -> str:
    """The row's profile, sample and configuration; a row whose runs depart from the source's
    configuration (3D, CSCM-like concrete) says it is a sensitivity and why."""
    seeds = summary.get("n_seeds_heterogeneous_by_dim", {}).get(
        dim, summary["n_seeds_heterogeneous"])
    models = summary.get("material_model_by_dim", {}).get(
        dim, summary.get("material_model", ["drucker_prager"]))
    cscm = all(m.split("+")[0] == SOURCE_MODEL for m in models)
    departs = ([] if dim == "3D" else ["a 2D plane-strain slice"]) + (
        [] if cscm else [f"concrete model {', '.join(models)}"])
    label = (f"sensitivity ({' and '.join(departs)}; the source ran the 3D disc with CSCM)"
             if departs else "the source's configuration (3D, CSCM-like concrete)")
    return (f"profile {summary['profile']}, {seeds} heterogeneous specimens per kappa, "
            f"concrete model {', '.join(models)}; {label}")


def check12_claims(summary: dict) -> list[Claim]:
    """Check 12's findings, each finding's 3D row (the source's runs) before its 2D row; a dimension
    the profile did not run gets a 'not run' row."""
    rate = with_rate(summary)
    names: dict[str, dict] = {}
    for f in summary["findings"]:
        names.setdefault(f["finding"], {})[f.get("dim", "2D")] = f
    return [finding_claim(by_dim[dim], caveat_of(summary, dim), rate) if dim in by_dim
            else not_run_claim(next(iter(by_dim.values())), dim, summary["profile"], rate)
            for by_dim in names.values() for dim in DIMENSIONS]


def robustness_claim(summary: dict) -> Claim:
    err = float(summary["max_energy_balance_error"])
    return Claim.judged(MODEL, f"[{rate_label(with_rate(summary))}] every variant (zero-mass "
                        "pre-cracks and kappa = 0.7 included) runs to the end time with no NaN "
                        "and a closed energy balance",
                        "issue #5 acceptance; impact spec check 9 tolerance",
                        f"all runs finished; max energy-balance error < {ENERGY_BALANCE_MAX:.0%}",
                        f"{summary['n_runs']} runs, all finished: {summary['all_runs_finished']};"
                        f" max energy-balance error {err:.2%}",
                        {"all runs finished": bool(summary["all_runs_finished"]),
                         f"energy balance error < {ENERGY_BALANCE_MAX:.0%}":
                         err < ENERGY_BALANCE_MAX},
                        deciding=f"max energy error {err:.2%} (< {ENERGY_BALANCE_MAX:.0%})",
                        figure=("impact_rate_contact_force.png" if with_rate(summary)
                                else "impact_contact_force.png"))


def claims(sources: list[Path]) -> list[Claim]:
    out: list[Claim] = []
    for path in sources:
        if path.name not in ("summary.json", "summary_rate.json"):
            raise ValueError(f"impact claims: unexpected source {path} (summary.json, "
                             "summary_rate.json)")
        summary = json.loads(path.read_text())
        out += check12_claims(summary)
        out.append(robustness_claim(summary))
    return out
