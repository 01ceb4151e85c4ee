"""The drying paper's claims for the validation report (:mod:`craquelure.validation`).

Sources (registered by the drying rules): ``results/drying/summary.json`` (checks 14-16, see
:mod:`craquelure.drying.statistics`; each verdict is recomputed here from the recorded conditions
and what the sample cannot decide) and, when the thickness sweep ran,
``results/drying/<scene>/thickness.nc`` (:mod:`craquelure.drying.thickness`).
"""

from __future__ import annotations

import json
import math
from pathlib import Path

from craquelure.io import open_dataset
from craquelure.validation import Claim, verdict_of

MODEL = "drying"
# Beyond the paper: the thickness exponent passes if within this many standard deviations
# (over the late snapshots) of the dimensional prediction 2.
THICKNESS_SIGMAS = 2.0


def _caveat(summary: dict) -> str:
    pi = summary.get("pi")
    pace = ("" if pi is None else f", Pi = tau/t* = {pi:.3g} (paper "
            f"{summary.get('pi_paper', 0.022):.2g})")
    parts = [f"profile {summary['profile']}: N = {summary['n_particles']}, "
             f"{summary['n_seeds']} seeds, window {summary['window_mode']}{pace}"]
    if pi is not None and abs(pi / summary.get("pi_paper", pi) - 1) > 0.05:
        parts.append("drying speed departs from the paper's regime")
    if not summary["checks"]["sample_size_meets_spec"]:
        parts.append("fewer samples than the spec asks (>= 100 seeds at N = 4e4 or >= 300 at "
                     "N = 1e4)")
    return "; ".join(parts)


def _with(note: str, caveat: str) -> str:
    return f"{note}; {caveat}" if note else caveat


def _interval(ci, spec: str = ".3g", scale: float = 1.0) -> str:
    return "n/a" if not ci or None in ci else (f"{ci[0] * scale:{spec}}-"
                                               f"{ci[1] * scale:{spec}}")


def _verdict(check: dict) -> tuple[str, str]:
    """The check's verdict from its conditions and what its sample cannot decide (recomputed
    here from the recorded conditions, never copied)."""
    return verdict_of(check["conditions"], check.get("undecided"),
                      partial=check.get("partial", False))


def _failed(check: dict) -> list[str]:
    return [name for name, ok in check.get("conditions", {}).items() if not ok]


def _inverse_area_number(c14: dict, verdict: str) -> str:
    """The number check 14's verdict turns on: the first failing condition's, else the power
    when the sample cannot decide, else the x-intercept t0."""
    if "error" in c14:
        return "no test"
    failed = " ".join(_failed(c14))
    if "(a)" in failed:
        return f"chi^2_r = {c14['reduced_chi2']:.2f} (< {c14['reduced_chi2_critical']:.2f})"
    if "(b)" in failed:
        return f"quadratic p = {c14['quadratic_c_p']:.2g} (>= 0.01)"
    if "t0" in failed or not failed and verdict != "inconclusive":
        return f"t0 = {c14['t0_over_t_star']:.2f} t* (0-1 t*)"
    if failed:
        return f"b = {c14['slope_over_b_star']:.2f} b* (0.2-5 b*)"
    return f"power {c14['power']:.2f} (needs 0.8)"


def _collapse_number(c15: dict, verdict: str) -> str:
    if "error" in c15:
        return "no test"
    failed = " ".join(_failed(c15))
    if "KS(S_first" in failed:
        return f"KS(S) = {c15['ks_raw_first_last']:.2f} (>= 0.3)"
    if "CV" in failed:
        return f"CV upper 95 % = {c15['cv_mean_x2_upper95']:.3f} (<= 0.10)"
    if verdict == "inconclusive":
        return f"power {c15['power']:.2f} (needs 0.8)"
    return f"KS(X) upper 95 % = {c15['ks_scaled_first_last_upper95']:.3f} (<= 0.15)"


def _onset_number(c16: dict) -> str:
    def at(key: str) -> str:
        v = c16[key]["over_t_star"]
        return "never" if v is None else f"{v:.2f} t*"

    if any(name.startswith("all") for name in _failed(c16)):
        return f"all broken {at('all_samples_broken')} (<= 0.9 t*)"
    return f"first broken {at('first_sample_broken')} (<= 0.45 t*)"


def inverse_area_claim(summary: dict) -> Claim:
    c14, tstar = summary["checks"]["check14_inverse_mean_area_linear"], summary["t_star"]
    verdict, note = _verdict(c14)
    if "error" in c14:
        measured = f"no test: {c14['error']}"
    else:
        w0, w1 = summary["window"]
        measured = (f"window t = {w0:.3g}-{w1:.3g} ({c14['n_times']} snapshots, "
                    f"{c14['n_samples']} seeds): reduced chi^2 = {c14['reduced_chi2']:.2f} "
                    f"(1 % critical {c14['reduced_chi2_critical']:.2f}); quadratic term "
                    f"p = {c14['quadratic_c_p']:.2g}; b = {c14['slope_b']:.3g} = "
                    f"{c14['slope_over_b_star']:.2f} b* (95 % CI "
                    f"{_interval(c14['slope_b_ci95'], '.2f', 1 / summary['b_star'])} b*); "
                    f"t0 = {c14['t0_over_t_star']:.2f} t* (95 % CI "
                    f"{_interval(c14['t0_ci95'], '.2f', 1 / tstar)} t*); power against "
                    f"{c14['alternative']}: {c14['power']:.2f}; free power law alpha = "
                    f"{c14['alpha_free_power_law']:.2f}")
    return Claim(MODEL, "after the initial stage the average fragment area decreases as 1/t",
                 "paper Fig. 3; drying spec check 14 (revised)",
                 "weighted fit 1/<S>_t = b (t - t0): (a) reduced chi^2 below its 99 % critical "
                 "value, (b) quadratic term not significant at 1 %, (c) 0 < t0 <= t*, "
                 "0.2 b* <= b <= 5 b*; (d) power >= 0.8 against the t^-2 law",
                 measured, verdict, _with(note, _caveat(summary)),
                 deciding=_inverse_area_number(c14, verdict),
                 figure="drying_inverse_mean_area.png")


def collapse_claim(summary: dict) -> Claim:
    c15 = summary["checks"]["check15_scaling_collapse"]
    verdict, note = _verdict(c15)
    if "error" in c15:
        measured = f"no test: {c15['error']}"
    else:
        measured = (f"{c15['n_first']} and {c15['n_last']} fragments at the window's ends: "
                    f"KS(X_first, X_last) = {c15['ks_scaled_first_last']:.3f} (upper 95 % "
                    f"{c15['ks_scaled_first_last_upper95']:.3f}); CV of <X^2>_t = "
                    f"{c15['cv_mean_x2']:.3f} (upper 95 % {c15['cv_mean_x2_upper95']:.3f}); "
                    f"KS(S_first, S_last) = {c15['ks_raw_first_last']:.2f}; power against "
                    f"{c15['alternative']}: {c15['power']:.2f}; an exact collapse passes in "
                    f"{c15['confirmation_rate']:.0%} of simulated samples")
    return Claim(MODEL, "the fragment-size distributions collapse when scaled by their mean",
                 "paper Figs. 5-6; drying spec check 15 (revised)",
                 "upper 95 % bootstrap bounds KS(X_first, X_last) <= 0.15 and CV of <X^2>_t "
                 "<= 0.10; KS(S_first, S_last) >= 0.3; power >= 0.8 against a 25 % width "
                 "drift", measured, verdict, _with(note, _caveat(summary)),
                 deciding=_collapse_number(c15, verdict), figure="drying_scaled_distribution.png")


def onset_claim(summary: dict) -> Claim:
    c16 = summary["checks"]["check16_onset"]
    c16 = {**c16, "partial": True}
    verdict, note = _verdict(c16)

    def item(key: str) -> str:
        v = c16[key]
        if v["over_t_star"] is None:
            return "never"
        return f"{v['over_t_star']:.2f} t* (95 % CI {_interval(v['ci95_over_t_star'], '.2f')})"

    measured = (f"first removal: earliest {item('first_removal_earliest')}, median "
                f"{item('first_removal_median')}; samples broken (>= 2 fragments): first "
                f"{item('first_sample_broken')}, half {item('half_samples_broken')}, all "
                f"{item('all_samples_broken')}; {c16['unbroken_at_end']} of "
                f"{c16['n_samples']} unbroken at the end")
    return Claim(MODEL, "fragments appear early: the first sample breaks by 0.40 t*, all are "
                 "broken before 0.8 t* (100 samples)",
                 "paper Figs. 4-6 (t = 90, 150, 180); drying spec check 16",
                 "first sample broken by 0.45 t*, all broken by 0.9 t*",
                 measured, verdict, _with(note, _caveat(summary)),
                 deciding=_onset_number(c16), figure="drying_snapshots.png")


def thickness_claim(path: Path) -> Claim:
    ds = open_dataset(path)
    beta = float(ds.attrs["exponent_late_mean"])
    spread = float(ds.attrs["exponent_late_std"])
    predicted = float(ds.attrs["predicted_exponent"])
    n = int(ds.attrs["n_late_times"])
    name = f"|beta - {predicted:g}| <= {THICKNESS_SIGMAS:g} s.d."
    if n > 0 and math.isfinite(beta):
        verdict, note = verdict_of({name: abs(beta - predicted) <= THICKNESS_SIGMAS * spread})
    else:  # no late snapshot with every sample of every H broken: nothing to decide on
        verdict, note = verdict_of({}, {f"{name}: no late snapshot with every sample broken":
                                        "longer runs or larger boxes"})
    values = ", ".join(f"{h:g}" for h in ds["thickness"].values)
    measured = (f"beta = {beta:.2f} +- {spread:.2f} (s.d. over {n} late snapshots), "
                f"H = {values}, {int(ds['n_seeds'].values.min())} seed(s) per H")
    return Claim(MODEL, "fragment area at a given time scales as H^2 (beyond the paper: "
                 "dimensional analysis, drying-layer experiments)",
                 "issue #4 part 6", f"exponent of <S> ~ H^beta within {THICKNESS_SIGMAS:g} "
                 f"standard deviations of {predicted:g}", measured, verdict, note,
                 deciding=(f"beta = {beta:.2f} +- {spread:.2f} ({predicted:g})" if n > 0
                           and math.isfinite(beta) else "no late snapshot all broken"),
                 figure=f"{path.parent.name}_thickness.png")


def claims(sources: list[Path]) -> list[Claim]:
    out: list[Claim] = []
    for path in sources:
        if path.name == "summary.json":
            summary = json.loads(path.read_text())
            out += [inverse_area_claim(summary), collapse_claim(summary)]
            if "check16_onset" in summary["checks"]:
                out.append(onset_claim(summary))
        elif path.name == "thickness.nc":
            out.append(thickness_claim(path))
        else:
            raise ValueError(f"drying claims: unexpected source {path} (summary.json or "
                             f"thickness.nc)")
    return out
