"""The beam-lattice (NUMFRAC/HiDEM) claims for the validation report
(:mod:`craquelure.validation`), from the ``summary.json`` files of
:mod:`craquelure.lattice.analysis` (folder name = what it summarises). Spec check 12 (weak
scaling) is a speed target whose only measurement is a timing: :data:`BENCHMARKED`.
"""

import json
from pathlib import Path

from craquelure.validation import Claim

MODEL = "lattice"
# Claims judged by a benchmark instead of the report (their measurement is a timing).
BENCHMARKED = {"cost per particle and step is independent of the system size (lattice spec "
               "check 12, weak scaling)": "benchmarks/lattice_scaling.py"}
CALVING_MIN_FRAGMENTS = 20  # spec check 11: fewer cannot decide the exponent


def glen_claims(s: dict) -> list[Claim]:
    glen = Claim.judged(
        MODEL, "melting-freezing of bonds gives Glen's flow law, strain rate ~ stress^3",
        "lattice spec section 7; check 8",
        "log-log slope of the viscosity versus the applied stress -2 +- 0.2; Newtonian (slope 0 "
        "+- 0.2) with the bond state frozen",
        f"viscosity slope {s['viscosity_slope']:.3f} (strain-rate exponent "
        f"{s['strain_rate_exponent']:.3f}); frozen {s['frozen_viscosity_slope']:.4f}",
        {"viscosity slope -2 +- 0.2": s["check8_glen_slope_pass"],
         "frozen bonds: slope 0 +- 0.2": s["check8_newtonian_pass"]},
        deciding=f"slope {s['viscosity_slope']:.2f} (-2 +- 0.2)", figure="glen/glen.png")
    steady = Claim.judged(
        MODEL, "with melting the creep rate under constant stress is steady",
        "lattice spec check 9", "strain rate in the second half of the run within 10 % of the "
        "first", f"largest deviation {s['max_steadiness_deviation']:.1%}",
        {"steady within 10 %": s["check9_steady_pass"]},
        deciding=f"deviation {s['max_steadiness_deviation']:.1%} (<= 10 %)", figure="glen/glen.png")
    return [glen, steady]


def gravity_claim(s: dict) -> Claim:
    return Claim.judged(
        MODEL, "an elastic block settles under gravity as continuum elasticity predicts",
        "lattice spec check 10", "interior settlement within 5 % of rho_2 g H^2 / (2M)",
        f"{s['measured']:.4g} against {s['predicted']:.4g} ({s['relative_error']:+.2%})",
        {"within 5 %": s["check10_pass"]}, deciding=f"{s['relative_error']:+.2%} (within 5 %)",
        figure="gravity_block/gravity_block.png")


def calving_claim(s: dict) -> Claim:
    conditions = {
        "maximum-likelihood exponent of s^-tau exp(-s/s*) in [1.2, 1.9] (>= 20 fragments)":
            s["check11_slope_pass"],
        "log-binned slope in [-1.9, -1.2] over >= 1 decade": s["binned_slope_in_band"]}
    undecided = {}
    if s["fragments"] < CALVING_MIN_FRAGMENTS:  # too few fragments to fit an exponent
        conditions = {}
        undecided[f"exponent from {s['fragments']} fragments"] = (
            f">= {CALVING_MIN_FRAGMENTS} fragments (spec check 11)")
    return Claim.judged(
        MODEL, "calved fragment sizes follow n(s) ~ s^-3/2 with a cut-off (2D brittle "
        "fragmentation)", "lattice spec section 10 (calving); check 11",
        "exponent in [1.2, 1.9] by maximum likelihood and by the log-binned slope",
        f"{s['fragments']} fragments: tau = {s['ml_exponent']:.2f} (cut-off {s['ml_cutoff']:.3g}"
        f"), binned slope {s['slope']:.2f} over {s['decades']:.2f} decades", conditions, undecided,
        deciding=(f"tau = {s['ml_exponent']:.2f} (1.2-1.9)" if conditions else
                  f"{s['fragments']} fragments (>= {CALVING_MIN_FRAGMENTS})"),
        figure="calving/calving.png")


def fretting_claim(s: dict) -> Claim:
    cycles = s["cycles"]
    platelets = sum(c["platelets"] for c in cycles)
    per_cycle = ", ".join(f"{c['platelets']}" for c in cycles)
    return Claim.judged(
        MODEL, "fretting: cracks start at the contact edges and detach platelets within a few "
        "oscillations", "lattice spec section 10 (fretting)",
        "broken beams under the pad and at least one detached platelet",
        f"{s['broken']} broken beams; platelets per cycle: {per_cycle or 'none run'}",
        {"cracks under the pad": s["broken"] > 0, "platelets detach": platelets > 0},
        deciding=f"{platelets} platelets (>= 1)", figure="fretting/fretting.png")


def accuracy_claim(s: dict) -> Claim:
    orders = ", ".join(f"{v:.2f} (dt factor {k})" for k, v in s["convergence_order"].items())
    return Claim.judged(
        MODEL, "the lattice converges to the continuum at second order in the spacing",
        "accuracy-versus-cost study (column mode)",
        "convergence order of the mode period -2 +- 0.2 at every time step",
        f"order {orders}; deviation from the chain prediction <= "
        f"{s['max_deviation_from_chain_prediction']:.1%}", {"order -2 +- 0.2": s["order_two_pass"]},
        deciding="order " + " / ".join(f"{v:.2f}" for v in s["convergence_order"].values())
        + " (-2 +- 0.2)", figure="accuracy/accuracy.png")


_BY_FOLDER = {"glen": glen_claims, "gravity_block": gravity_claim, "calving": calving_claim,
              "fretting": fretting_claim, "accuracy": accuracy_claim}


def claims(sources: list[Path]) -> list[Claim]:
    out: list[Claim] = []
    for path in sources:
        if path.name == "summary.json" and path.parent.name in _BY_FOLDER:
            found = _BY_FOLDER[path.parent.name](json.loads(path.read_text()))
            out += found if isinstance(found, list) else [found]
        else:
            raise ValueError(f"lattice claims: unexpected source {path} (summary.json of "
                             f"{', '.join(_BY_FOLDER)}; the scaling timings are judged by "
                             f"{BENCHMARKED[next(iter(BENCHMARKED))]})")
    return out
