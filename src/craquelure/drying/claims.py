"""The drying paper's claims for the validation report (:mod:`craquelure.validation`).

Sources (registered by the drying rules): ``results/drying/summary.json`` (checks 14 and 15, see
:mod:`craquelure.drying.statistics`) and, when the thickness sweep ran,
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


def _num(value, spec: str) -> str:
    """A summary number, or n/a where the statistic could not be computed (None)."""
    return "n/a" if value is None else format(value, spec)


def _caveat(summary: dict) -> str:
    parts = [f"profile {summary['profile']}: N = {summary['n_particles']}, "
             f"{summary['n_seeds']} seeds, window {summary['window_mode']}"]
    if not summary["checks"]["sample_size_meets_spec"]:
        parts.append("fewer samples than the spec asks (>= 100 seeds at N = 4e4 or >= 300 at "
                     "N = 1e4): indicative only")
    return "; ".join(parts)


def _with(note: str, caveat: str) -> str:
    return f"{note}; {caveat}" if note else caveat


def inverse_area_claim(summary: dict) -> Claim:
    fit, c14 = summary["fit"], summary["checks"]["check14_inverse_mean_area_linear"]
    tstar = summary["t_star"]
    lo, hi = c14["x_intercept_range"]
    verdict, note = verdict_of({k: c14[k] for k in (
        "r2_at_least_0.95", "slope_positive", "quadratic_change_below_20_percent",
        "x_intercept_in_range")})
    if "error" in fit:  # too few usable snapshots (e.g. the CI profile's short runs)
        measured = f"no fit: {fit['error']}"
    else:
        w0, w1 = summary["window"]
        alpha_lo, alpha_hi = fit["alpha_ci95"]
        measured = (f"window t = {w0:.3g}-{w1:.3g}: R^2 = {fit['r2']:.3f}, slope b = "
                    f"{fit['slope_b']:.3g} = {summary['slope_over_b_star']:.2f} b*, quadratic "
                    f"term {fit['quadratic_departure_fraction']:.1%} of the rise, x-intercept "
                    f"{fit['x_intercept']:.3g} = {fit['x_intercept'] / tstar:.2f} t* (range "
                    f"{lo / tstar:.2f}-{hi / tstar:.2f} t*); alpha = {fit['alpha']:.2f} (95 % "
                    f"CI {alpha_lo:.2f}-{alpha_hi:.2f})")
    return Claim(MODEL, "after the initial stage the average fragment area decreases as 1/t",
                 "paper Fig. 3; drying spec check 14",
                 "1/<S>_t linear in t: R^2 >= 0.95, slope > 0, a quadratic term changes the fit "
                 "by < 20 % of the rise, x-intercept in the paper's range rescaled by t*",
                 measured, verdict, _with(note, _caveat(summary)))


def collapse_claim(summary: dict) -> Claim:
    col, c15 = summary["collapse"], summary["checks"]["check15_scaling_collapse"]
    rows = col["per_time"]
    below = sum(bool(r["below_critical"]) for r in rows)
    verdict, note = verdict_of({k: c15[k] for k in (
        "ks_test_can_reject_at_all_t_k", "ks_below_critical_at_all_t_k",
        "cv_mean_x2_at_most_0.10", "raw_ks_first_last_at_least_0.3")})
    counts = [int(r["n"]) for r in rows]
    if not rows:
        measured = "no collapse times: no snapshot window with every sample broken"
    else:
        measured = (f"KS(X(t_k), pooled X) below the 1 % critical value at {below}/{len(rows)} "
                    f"t_k ({min(counts)}-{max(counts)} fragments each); CV of <X^2>_t = "
                    f"{_num(col['cv_mean_x2'], '.3f')}; raw KS(S) first/last = "
                    f"{_num(col['raw_ks_first_last'], '.2f')}; mean pairwise KS of scaled "
                    f"distributions {_num(col['mean_pairwise_ks_before'], '.2f')} before the "
                    f"window, {_num(col['mean_pairwise_ks_after'], '.2f')} inside it")
    return Claim(MODEL, "the fragment-size distributions collapse when scaled by their mean",
                 "paper Figs. 5-6; drying spec check 15",
                 "KS test can reject and does not at every t_k, CV of <X^2>_t <= 0.10, raw "
                 "KS(S) first/last >= 0.3 (the collapse is not trivial)",
                 measured, verdict, _with(note, _caveat(summary)))


def thickness_claim(path: Path) -> Claim:
    ds = open_dataset(path)
    beta = float(ds.attrs["exponent_late_mean"])
    spread = float(ds.attrs["exponent_late_std"])
    predicted = float(ds.attrs["predicted_exponent"])
    n = int(ds.attrs["n_late_times"])
    ok = n > 0 and math.isfinite(beta) and abs(beta - predicted) <= THICKNESS_SIGMAS * spread
    verdict, note = verdict_of({f"|beta - {predicted:g}| <= {THICKNESS_SIGMAS:g} s.d.": ok})
    values = ", ".join(f"{h:g}" for h in ds["thickness"].values)
    measured = (f"beta = {beta:.2f} +- {spread:.2f} (s.d. over {n} late snapshots), "
                f"H = {values}, {int(ds['n_seeds'].values.min())} seed(s) per H")
    return Claim(MODEL, "fragment area at a given time scales as H^2 (beyond the paper: "
                 "dimensional analysis, drying-layer experiments)",
                 "issue #4 part 6", f"exponent of <S> ~ H^beta within {THICKNESS_SIGMAS:g} "
                 f"standard deviations of {predicted:g}", measured, verdict, note)


def claims(sources: list[Path]) -> list[Claim]:
    out: list[Claim] = []
    for path in sources:
        if path.name == "summary.json":
            summary = json.loads(path.read_text())
            out += [inverse_area_claim(summary), collapse_claim(summary)]
        elif path.name == "thickness.nc":
            out.append(thickness_claim(path))
        else:
            raise ValueError(f"drying claims: unexpected source {path} (summary.json or "
                             f"thickness.nc)")
    return out
