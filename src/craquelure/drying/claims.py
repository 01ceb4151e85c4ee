"""The drying paper's claims for the validation report (:mod:`craquelure.validation`), from the
sources the drying rules register: ``results/drying/summary.json`` and the criterion
sensitivity's ``results/drying/<scene>_C<measure>/summary.json`` (checks 14-16 of
:mod:`craquelure.drying.ensemble`, each verdict recomputed here from the recorded conditions and
what the sample cannot decide; a criterion other than the source's is named in every row), a
thickness sweep's ``results/drying/<scene>/thickness.nc`` (:mod:`craquelure.drying.thickness`)
and ``results/drying/transition.nc`` (:mod:`craquelure.drying.transition`: rows against
arXiv:2503.06177, beyond the drying paper)."""

from __future__ import annotations

import json
import math
from dataclasses import replace
from pathlib import Path

import numpy as np

from craquelure.drying.effects.fracture import MEASURE_TEXT, SOURCE_MEASURE, departure_note
from craquelure.drying.transition import ISING, PERCOLATION
from craquelure.io import open_dataset
from craquelure.validation import Claim, verdict_of

MODEL = "drying"
# Beyond the paper: the thickness exponent passes if within this many standard deviations
# (over the late snapshots) of the dimensional prediction 2.
THICKNESS_SIGMAS = 2.0


def _caveat(summary: dict, key: str = "checks") -> str:
    pi = summary.get("pi")
    pace = ("" if pi is None else f", Pi = tau/t* = {pi:.3g} (paper "
            f"{summary.get('pi_paper', 0.022):.2g})")
    parts = [f"profile {summary['profile']}: N = {summary['n_particles']}, "
             f"{summary['n_seeds']} seeds, window {summary['window_mode']}{pace}"]
    if pi is not None and abs(pi / summary.get("pi_paper", pi) - 1) > 0.05:
        parts.append("drying speed departs from the paper's regime")
    criterion = departure_note(summary.get("fracture_stress_measure", SOURCE_MEASURE))
    if criterion:
        parts.append(criterion)
    if not summary[key]["sample_size_meets_spec"]:
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
        return f"CV upper 95 % = {c15['cv_mean_x2_upper95']:.3f} (<= {c15['cv_margin']:.3f})"
    if verdict == "inconclusive":
        rates = {"power": c15["power"], "exact collapse passes": c15["confirmation_rate"]}
        name = min(rates, key=rates.get)
        return f"{name} {rates[name]:.2f} (needs 0.8)"
    return (f"KS(X) upper 95 % = {c15['ks_scaled_first_last_upper95']:.3f} "
            f"(<= {c15['ks_margin']:.3f})")


def _onset_number(c16: dict) -> str:
    def at(key: str) -> str:
        v = c16[key]["over_t_star"]
        return "never" if v is None else f"{v:.2f} t*"

    if any(name.startswith("all") for name in _failed(c16)):
        return f"all broken {at('all_samples_broken')} (<= 0.9 t*)"
    return f"first broken {at('first_sample_broken')} (<= 0.45 t*)"


# Checks 14-16 per fragment labelling: summary key -> what the row says of its labelling.
LABELLING_KEYS = {"checks": "periodic labelling (on the torus)",
                  "checks_open_image": "open-image labelling (no wrap-around)"}


def _labelled(summary: dict, key: str, source: str) -> str:
    """The source column of a row of one labelling, and whether the source most likely used it
    (summaries that judge both labellings say which)."""
    if "checks_open_image" not in summary:
        return source
    likely = summary.get("source_labelling", {})
    used = LABELLING_KEYS[key].startswith(likely.get("labelling", "?"))
    return (f"{source}; {LABELLING_KEYS[key]}"
            + (f", most likely the source's: {likely['why']}" if used else ""))


def inverse_area_claim(summary: dict, key: str = "checks") -> Claim:
    c14, tstar = summary[key]["check14_inverse_mean_area_linear"], summary["t_star"]
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
                    f"{_interval(c14['t0_ci95'], '.2f', 1 / tstar)} t*; "
                    f"{c14.get('t0_bound_note', 't0 bound applied to the whole window')}); "
                    f"power against "
                    f"{c14['alternative']}: {c14['power']:.2f}; free power law alpha = "
                    f"{c14['alpha_free_power_law']:.2f}")
    return Claim(MODEL, "after the initial stage the average fragment area decreases as 1/t",
                 _labelled(summary, key, "paper Fig. 3; drying spec check 14 (revised)"),
                 "weighted fit 1/<S>_t = b (t - t0): (a) reduced chi^2 below its 99 % critical "
                 "value, (b) quadratic term not significant at 1 %, (c) 0 < t0 <= t* (only "
                 "over snapshots where every sample has several fragments), "
                 "0.2 b* <= b <= 5 b*; (d) power >= 0.8 against the t^-2 law",
                 measured, verdict, _with(note, _caveat(summary, key)),
                 deciding=_inverse_area_number(c14, verdict),
                 figure="drying_inverse_mean_area.png")


def collapse_claim(summary: dict, key: str = "checks") -> Claim:
    c15 = summary[key]["check15_scaling_collapse"]
    verdict, note = _verdict(c15)
    if "error" in c15:
        measured = f"no test: {c15['error']}"
    else:
        measured = (f"{c15['n_first']} and {c15['n_last']} fragments at the window's ends: "
                    f"KS(X_first, X_last) = {c15['ks_scaled_first_last']:.3f} (upper 95 % "
                    f"{c15['ks_scaled_first_last_upper95']:.3f}, margin "
                    f"{c15['ks_margin']:.3f}); CV of <X^2>_t = "
                    f"{c15['cv_mean_x2']:.3f} (upper 95 % {c15['cv_mean_x2_upper95']:.3f}, "
                    f"margin {c15['cv_margin']:.3f}); "
                    f"KS(S_first, S_last) = {c15['ks_raw_first_last']:.2f}; power against "
                    f"{c15['alternative']}: {c15['power']:.2f}; an exact collapse passes in "
                    f"{c15['confirmation_rate']:.0%} of simulated samples")
    return Claim(MODEL, "the fragment-size distributions collapse when scaled by their mean",
                 _labelled(summary, key, "paper Figs. 5-6; drying spec check 15 (revised)"),
                 "upper 95 % bootstrap bounds of KS(X_first, X_last) and of the CV of <X^2>_t "
                 "within half what a 25 % width drift does to the first snapshot's sizes; "
                 "KS(S_first, S_last) >= 0.3; an exact collapse passes and the drift fails "
                 "in >= 80 % of simulated samples of the measured counts",
                 measured, verdict, _with(note, _caveat(summary, key)),
                 deciding=_collapse_number(c15, verdict), figure="drying_scaled_distribution.png")


def onset_claim(summary: dict, key: str = "checks") -> Claim:
    c16 = {**summary[key]["check16_onset"], "partial": True}
    verdict, note = _verdict(c16)

    def item(key: str) -> str:
        v = c16[key]
        if v["over_t_star"] is None:
            return "never"
        return f"{v['over_t_star']:.2f} t* (95 % CI {_interval(v['ci95_over_t_star'], '.2f')})"

    ci = c16["unbroken_at_end_ci95"]
    measured = (f"first removal: earliest {item('first_removal_earliest')}, median "
                f"{item('first_removal_median')}; samples broken (>= 2 fragments): first "
                f"{item('first_sample_broken')}, half {item('half_samples_broken')}, all "
                f"{item('all_samples_broken')}; {c16['unbroken_at_end']} of "
                f"{c16['n_samples']} unbroken at the end (exact 95 % interval {ci[0]:.2f}-"
                f"{ci[1]:.2f}); at {c16['rates_at_samples']} samples drawn from these, both "
                f"conditions hold in {c16['confirmation_rate']:.0%}; power against "
                f"{c16['alternative']}: {c16['power']:.2f}")
    return Claim(MODEL, "fragments appear early: the first sample breaks by 0.40 t*, all are "
                 "broken before 0.8 t* (100 samples)",
                 _labelled(summary, key, "paper Figs. 4-6 (t = 90, 150, 180); drying spec "
                           "check 16"),
                 "first sample broken by 0.45 t*, all broken by 0.9 t*",
                 measured, verdict, _with(note, _caveat(summary, key)),
                 deciding=_onset_number(c16), figure="drying_snapshots.png")


def thickness_claim(path: Path) -> Claim:
    ds = open_dataset(path)
    beta, spread, predicted = (float(ds.attrs[key]) for key in (
        "exponent_late_mean", "exponent_late_std", "predicted_exponent"))
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


TRANSITION_SOURCE = ("Szatmari, Nakahara, Kitsunezaki & Kun, arXiv:2503.06177 (abstract, "
                     "https://arxiv.org/html/2503.06177v2); beyond the drying paper")
MIN_SIZES = 3  # finite-size scaling tests its form only with >= 3 sizes


def transition_claims(path: Path) -> list[Claim]:
    """Rows against arXiv:2503.06177: the two phases, and d_c with the exponents."""
    ds = open_dataset(path)
    a = ds.attrs
    sizes = ", ".join(f"L = {s:g} x {int(n)}" for s, n in
                      zip(ds["size"].values, ds["n_seeds"].values, strict=True))
    criterion = departure_note(str(a.get("fracture_stress_measure", SOURCE_MEASURE)))
    setup = (f"runs '{a.get('variant', '')}' of {a.get('scenes', '?')} ({sizes} seeds), "
             f"v_r = {float(a['drying_rate']):.3g} (paper 2.2e-05)"
             + (f"; {criterion}" if criterion else ""))
    first, last = [], []  # m_max at the lowest damage with cracks and at the highest, per size
    for n, m, d in zip(ds["n"].values, ds["m_max"].values, ds["damage"].values, strict=True):
        m, cracked = m[n > 0], d[n > 0] > 0
        first.append(float(m[cracked][0]) if cracked.any() else math.nan)
        last.append(float(m[-1]) if m.size else math.nan)
    below = float(a.get("fragmented_below", 0.5))
    name_damage = f"cracked but m_max >= {below:g} at the lowest damage, every size"
    name_frag = f"m_max < {below:g} at the highest damage, every size"
    conditions = {name_damage: all(v >= below for v in first)}
    undecided = {}
    if all(v < below for v in last):
        conditions[name_frag] = True
    else:
        undecided[f"{name_frag}: not reached in the runs"] = "longer drying (higher damage)"
    verdict, note = verdict_of(conditions, undecided)
    measured = ("m_max at the lowest / highest damage bin: "
                + "; ".join(f"L = {s:g}: {f:.2f} / {la:.2f} (d up to "
                            f"{float(np.nanmax(ds['damage'].values[k])):.3f})"
                            for k, (s, f, la) in enumerate(zip(ds["size"].values, first, last,
                                                               strict=True))))
    phases = Claim(MODEL, "shrinking layers on a substrate: a damage phase (cracked, one "
                   "dominant piece) precedes a fragmentation phase", TRANSITION_SOURCE,
                   f"{name_damage}; {name_frag}", measured, verdict, _with(note, setup),
                   deciding="m_max " + ", ".join(f"{v:.2f}" for v in last) + f" (< {below:g})",
                   figure="drying_transition.png")

    def est(key: str, spec: str = ".3g") -> str:
        ci = a.get(f"{key}_ci95", [math.nan, math.nan])
        return f"{float(a[key]):{spec}} (95 % CI {_interval(list(ci), spec)})"

    n_sizes = int(ds.sizes["size"])
    measured = (f"d_c = {est('d_c')}; beta/nu = {est('beta_over_nu')}, gamma/nu = "
                f"{est('gamma_over_nu')}, 1/nu = {est('one_over_nu')}; the paper's fitted "
                f"d_c and exponents are not in the sources available to us (its abstract: "
                f"they agree to a reasonable accuracy with the 2D Ising model's, beta/nu = "
                f"0.125, gamma/nu = 1.75, 1/nu = 1)")
    conditions, undecided = {}, {}
    if n_sizes < MIN_SIZES:
        undecided[f"finite-size scaling from {n_sizes} sizes: each exponent rests on "
                  f"{n_sizes} points, the scaling form is not tested"] = (
            f">= {MIN_SIZES} box sizes (the L = 10 ensembles)")
    elif not math.isfinite(float(a["d_c"])):
        undecided["no crossing of P(m_max < 1/2) between the sizes"] = "higher damage"
    else:
        resolving = []
        for key, value in ISING.items():
            lo, hi = a.get(f"{key}_ci95", [math.nan, math.nan])
            conditions[f"2D Ising {key.replace('_over_', '/')} = {value:g} inside the "
                       f"95 % interval"] = bool(lo <= value <= hi)
            # an interval wider than the Ising-percolation gap cannot tell the two apart,
            # whichever side of it the percolation value happens to fall
            resolving.append(bool(hi - lo < abs(value - PERCOLATION[key])))
        if all(conditions.values()) and not any(resolving):
            undecided["every exponent's interval is wider than its gap to the 2D percolation "
                      "value (beta/nu 5/48, gamma/nu 43/24, 1/nu 3/4): Ising cannot be told "
                      "from percolation"] = "larger boxes or more seeds (narrower intervals)"
    # the exponents' agreement is one statement of the source: any one outside fails it
    verdict, note = verdict_of(conditions, undecided, partial=False)
    scaling = Claim(MODEL, "the damage-to-fragmentation transition is continuous, with "
                    "finite-size scaling of the largest and the average fragment at a "
                    "critical damage d_c; exponents close to the 2D Ising model's",
                    TRANSITION_SOURCE, "d_c from the crossing of P(m_max < 1/2) between "
                    "sizes; at d_c the exponents' 95 % bootstrap intervals contain the 2D "
                    "Ising values (defining), one of them narrower than its gap to the 2D "
                    "percolation value (else undecided); >= 3 sizes", measured, verdict,
                    _with(note, setup),
                    deciding=f"{n_sizes} sizes (>= {MIN_SIZES}); d_c = {float(a['d_c']):.3g}",
                    figure="drying_transition.png")
    return [phases, scaling]


def summary_claims(summary: dict) -> list[Claim]:
    """Checks 14-16 of a summary, for each labelling it judges."""
    return [claim(summary, key) for key in LABELLING_KEYS if key in summary
            for claim in (inverse_area_claim, collapse_claim, onset_claim)]


def setting(summary: dict) -> str:
    """An ensemble in the paper's terms: scene, criterion (and how it departs from the
    source's), L, N and seeds."""
    measure = summary.get("fracture_stress_measure", SOURCE_MEASURE)
    how = ("the source's" if measure == SOURCE_MEASURE else "a factor 2 from the source's"
           if measure == "trace" else "departs from the source's")
    return (f"scene {summary['scene']}: {MEASURE_TEXT[measure]} > sigma_Y ({how}), "
            f"L = {summary['box_length']:g}, N = {summary['n_particles']}, "
            f"{summary['n_seeds']} seed{'s' * (summary['n_seeds'] != 1)}")


def criterion_variant(provenance: dict) -> bool:
    """Whether an archived ensemble's runs override their scene's criterion with one that
    departs from the source's (results/drying/<scene>_C<measure>/): a variant the source never
    ran, whose rows carry no verdict (not a scene's declared departure, as the headline's)."""
    return (provenance.get("scene") != provenance.get("scene_name")
            and provenance.get("fracture_stress_measure", SOURCE_MEASURE) != SOURCE_MEASURE)


def companion(name: str, summary: dict) -> dict:
    """The rows of a companion ensemble (archived as ``name``) shown beside the headline's
    (``companions`` of :func:`craquelure.validation.write_json`), each naming its setting;
    judged with the source's criterion, without a verdict (a variant the source never ran)
    with a criterion that departs, since only the headline carries the declared departure."""
    judged = summary.get("fracture_stress_measure", SOURCE_MEASURE) == SOURCE_MEASURE
    label = setting(summary)
    return {"name": name, "setting": label, "judged": judged,
            "why": "" if judged else ("its criterion departs from the source's and only the "
                                      "headline carries the declared departure: a variant the "
                                      "source never ran, shown for context"),
            "claims": [replace(c, note=_with(c.note, f"ensemble {name}, {label}"))
                       for c in summary_claims(summary)]}


def claims(sources: list[Path]) -> list[Claim]:
    out: list[Claim] = []
    for path in sources:
        if path.name == "summary.json":
            out += summary_claims(json.loads(path.read_text()))
        elif path.name == "thickness.nc":
            out.append(thickness_claim(path))
        elif path.name == "transition.nc":
            out += transition_claims(path)
        else:
            raise ValueError(f"drying claims: unexpected source {path} (summary.json, "
                             f"thickness.nc or transition.nc)")
    return out
