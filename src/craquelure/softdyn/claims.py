"""Soft Dynamics claims for the validation report (:mod:`craquelure.validation`), judged on the
numbers of ``results/softdyn/summary.json`` (:mod:`craquelure.softdyn.analysis`), never on runs.
"""

import json
import math
from pathlib import Path

import numpy as np

from craquelure.validation import Claim, verdict_of

MODEL = "softdyn"
# Fig. 3 points this close to the line F_h/F_v = 1/sqrt(3) are judged apart (phase_claim).
NEAR_LINE = 0.05


def sweep_claims(n: dict) -> list[Claim]:
    """Fig. 5: T decreases with h0 at every force (check 12) and, in the Hertz regime, as
    (h*/h0)^2 (check 11: local slope in [-2.2, -1.5] next to h0/h* = 0.1)."""
    monotone, slopes, span = n["monotone"], n["slopes"], n["span_decades"]
    out = [Claim.judged(
        MODEL, "the T1 duration falls with the initial gap h0, steeply once the spheres touch "
        "elastically (h0 < h*)", "paper 2 Fig. 5; softdyn spec check 12",
        "T/tau decreasing in h0 at every reduced force; span >= 2 decades over the grid",
        f"{n['finished']} finished runs at {n['forces']} forces; decreasing at "
        f"{sum(monotone)}/{len(monotone)} forces; span {span:.2f} decades",
        {"decreasing at every force": bool(monotone) and all(monotone),
         "span >= 2 decades": span >= 2.0},
        deciding=f"decreasing at {sum(monotone)}/{len(monotone)} forces", figure="fig5.png")]
    if slopes:
        inside = [-2.2 <= s <= -1.5 for _, s, _, _ in slopes]
        out.append(Claim.judged(
            MODEL, "in the Hertz regime the T1 duration grows as (h*/h0)^2",
            "paper 2 Eq. 34; softdyn spec check 11", "d ln T / d ln h0 between the two grid "
            "points nearest below h0/h* = 0.1 in [-2.2, -1.5] (-> -2 as h0/h* -> 0)",
            "; ".join(f"F~ = {f:g}: {s:.2f} (h0/h* {a:.3g}-{b:.3g})" for f, s, a, b in slopes),
            {"local slope in [-2.2, -1.5] at every force": all(inside)},
            deciding="slope " + " / ".join(f"{s:.2f}" for _, s, _, _ in slopes)
            + " ([-2.2, -1.5])", figure="fig5.png"))
    return out


def phase_claim(n: dict) -> Claim:
    """Fig. 3. Close to the line the threshold follows the deformed rhombus angle (AB is in
    tension iff F_h/F_v < cot theta, and the Hertz deflection lowers theta below 60 deg at
    larger forces), so points within NEAR_LINE of 1/sqrt(3) are judged separately."""
    agree = np.asarray(n["occurred"]) == np.asarray(n["predicted"])
    force = np.asarray(n["force"])
    ratio = np.broadcast_to(np.asarray(n["fh_over_fv"])[:, None], agree.shape)
    far = np.abs(ratio - 1 / math.sqrt(3)) > NEAR_LINE
    verdict, note = verdict_of({
        f"agreement with |F_h/F_v - 1/sqrt3| > {NEAR_LINE:g}": bool(agree[far].all()),
        "agreement at every point": bool(agree.all())})
    if not agree.all():
        note += ("; near the line the threshold is cot(theta) with the deformed angle, not "
                 "sqrt(3) (docs/softdyn.md)")
    off = ", ".join(f"F_h/F_v = {ratio[i, j]:g} at F~ = {force[j]:g}"
                    for i, j in zip(*np.nonzero(~agree), strict=True))
    return Claim(MODEL, "a T1 happens if and only if F_h < F_v / sqrt(3)",
                 "paper 2 Fig. 3; softdyn spec check 7",
                 f"T1 occurrence equals the prediction at the points farther than {NEAR_LINE:g}"
                 f" from the line, and at every point of the (F_h/F_v, F~) scan",
                 f"{int(agree.sum())}/{agree.size} points agree"
                 + (f" (differs: {off})" if off else ""), verdict, note,
                 deciding=f"{int(agree.sum())}/{agree.size} points agree", figure="fig3.png")


def t1_claim(n: dict) -> Claim:
    final, rising = n["theta_final"], n["largest_rise"]
    return Claim.judged(
        MODEL, "four spheres complete a T1: the rhombus angle goes from 60 to about 30 degrees",
        "paper 2 Fig. 4; softdyn spec check 9", "theta non-increasing, final theta in [29, 33] deg",
        f"theta {n['theta_start']:.2f} -> {final:.2f} deg in {n['duration']:.4g} tau (largest "
        f"rise {rising:.1e} deg)", {"final angle in [29, 33] deg": 29.0 <= final <= 33.0,
                                    "angle non-increasing": rising <= 1e-9},
        deciding=f"theta {final:.2f} deg (29-33)", figure="fig4.png")


def approach_claims(n: dict) -> list[Claim]:
    """Check 4 on the approach run: exponential while h >= 100 h*, h^-2 linear once h <= h*/100."""
    out = []
    if (rate := n["rate"]) is not None:
        out.append(Claim.judged(
            MODEL, "far apart (h >> h*), two spheres pressed together approach exponentially, "
            "h = h0 exp(-t / (c_n tau))", "paper 1 (Poiseuille limit); softdyn spec check 4",
            "fitted rate of ln h while h >= 100 h* within 1 % of 1/(c_n tau)",
            f"rate x c_n tau = {rate:.4f} over {n['rate_samples']} samples",
            {"rate within 1 %": abs(rate - 1) <= 0.01},
            deciding=f"rate {rate - 1:+.2%} (within 1 %)", figure="gaps.png"))
    if (ratio := n["hertz_ratio"]) is not None:
        out.append(Claim.judged(
            MODEL, "in elastic contact (h << h*) the gap closes as h^-2 - h0^-2 = 2t / (c_n tau "
            "h*^2)", "paper 1 (Hertz limit); softdyn spec check 4",
            "d(h^-2)/dt while h <= h*/100 within 2 % of 2/(c_n tau h*^2)",
            f"measured / predicted = {ratio:.4f}", {"within 2 %": abs(ratio - 1) <= 0.02},
            deciding=f"ratio {ratio - 1:+.2%} (within 2 %)", figure="gaps.png"))
    return out


def separation_claim(n: dict) -> Claim:
    h0, force = n["h0"], n["reduced_force"]
    predicted, duration = n["predicted"], n["duration"]
    return Claim.judged(
        MODEL, "two spheres pulled apart open from h0 to R in the time given by the lubrication "
        "+ Hertz quadrature", "paper 1; softdyn spec check 5",
        "opening time within 2 % of the quadrature of spec section 7",
        f"{duration:.5g} tau against {predicted:.5g} tau ({duration / predicted - 1:+.2%}), "
        f"h0 = {h0:g} R, F~ = {force:g}", {"within 2 %": abs(duration / predicted - 1) <= 0.02},
        deciding=f"{duration / predicted - 1:+.2%} (within 2 %)", figure="gaps.png")


def accuracy_claim(n: dict) -> Claim:
    order, state = n["duration_order"], n["state_order"]
    return Claim.judged(
        MODEL, "the fixed-step integrator converges to the adaptive reference at second order",
        "softdyn spec check 13; accuracy-versus-cost study",
        "observed order of Heun's method 2 +- 0.2 (T1 duration and state)",
        f"order {order:.2f} (duration), {state:.2f} (state)",
        {"order 2 +- 0.2 on the duration": abs(order - 2) <= 0.2,
         "order 2 +- 0.2 on the state": abs(state - 2) <= 0.2},
        deciding=f"order {order:.2f} / {state:.2f} (2 +- 0.2)", figure="accuracy.png")


BY_KIND = {"sweep": sweep_claims, "phase": phase_claim, "t1": t1_claim,
           "approach": approach_claims, "separation": separation_claim, "accuracy": accuracy_claim}


def claims(sources: list[Path]) -> list[Claim]:
    """Claims of the ``summary.json`` files (one per profile run)."""
    out: list[Claim] = []
    for path in sources:
        for numbers in json.loads(Path(path).read_text())["sources"]:
            found = BY_KIND[numbers["kind"]](numbers)  # one claim or a list
            out += found if isinstance(found, list) else [found]
    return out
