"""The impact paper's findings for the validation report (:mod:`craquelure.validation`).

Source: ``results/impact/summary.json`` (:mod:`craquelure.impact.analysis`), whose ``findings``
already carry the spec's check-12 criteria and ``reproduced`` flags computed from the runs;
this module only words them as claims and adds the robustness demand (every variant to the end,
closed energy balance). A finding that did not run, or that is stated as a fraction of seeds
whose exact binomial 95 % interval at this seed count straddles the threshold, is inconclusive
(with the seed count that would decide), never reproduced or not reproduced.
"""

from __future__ import annotations

import json
import math
import re
from pathlib import Path

from craquelure.validation import Claim, fraction_decision, verdict_of

MODEL = "impact"
# Spec check 9's energy-balance tolerance, applied to every run of the campaign.
ENERGY_BALANCE_MAX = 0.02


def _number(value) -> str:
    if isinstance(value, bool) or value is None:
        return str(value)
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        return f"{value:.3g}" if math.isfinite(value) else str(value)
    if isinstance(value, dict):
        return "{" + ", ".join(f"{k}: {_number(v)}" for k, v in value.items()) + "}"
    if isinstance(value, list | tuple):
        return "[" + ", ".join(_number(v) for v in value) + "]"
    return str(value)


# Findings stated as a fraction of seeds ("in >= 60 % of seeds"): value key -> threshold.
FRACTION_KEYS = ("fraction_N_mc_1", "fraction_1_crossing")


def _undecided(finding: dict, n_seeds: int) -> dict[str, str]:
    """What the seeds cannot decide: a finding that did not run, or a fraction of seeds whose
    exact binomial interval straddles the finding's threshold."""
    if finding["reproduced"] is None:
        return {"not run": "the case's runs"}
    out = {}
    for key in FRACTION_KEYS:
        value = finding["values"].get(key)
        match = re.search(r">= (\d+) % of seeds", finding["criterion"])
        if value is None or match is None or n_seeds <= 0:
            continue
        threshold = float(match.group(1)) / 100.0
        decided, need = fraction_decision(round(value * n_seeds), n_seeds, threshold)
        if decided is None:
            out[f"{key} = {value:.2f} of {n_seeds} seeds against {threshold:.0%}"] = need
    return out


def finding_claim(finding: dict, caveat: str, n_seeds: int = 0) -> Claim:
    measured = "; ".join(f"{k} = {_number(v)}" for k, v in finding["values"].items())
    undecided = _undecided(finding, n_seeds)
    if undecided:  # the seeds cannot decide this finding: no pass or miss on it
        verdict, note = verdict_of({}, undecided)
    else:
        verdict, note = verdict_of({finding["criterion"]: bool(finding["reproduced"])})
    return Claim(MODEL, finding["finding"], "impact spec section 7; check 12",
                 finding["criterion"], measured, verdict,
                 f"{note}; {caveat}" if note else caveat)


def robustness_claim(summary: dict) -> Claim:
    err = float(summary["max_energy_balance_error"])
    verdict, note = verdict_of({"all runs finished": bool(summary["all_runs_finished"]),
                                f"energy balance error < {ENERGY_BALANCE_MAX:.0%}":
                                err < ENERGY_BALANCE_MAX})
    return Claim(MODEL, "every variant (zero-mass pre-cracks and kappa = 0.7 included) runs to "
                 "the end time with no NaN and a closed energy balance",
                 "issue #5 acceptance; impact spec check 9 tolerance",
                 f"all runs finished; max energy-balance error < {ENERGY_BALANCE_MAX:.0%}",
                 f"{summary['n_runs']} runs, all finished: {summary['all_runs_finished']}; max "
                 f"energy-balance error {err:.2%}", verdict, note)


def claims(sources: list[Path]) -> list[Claim]:
    out: list[Claim] = []
    for path in sources:
        if path.name != "summary.json":
            raise ValueError(f"impact claims: unexpected source {path} (summary.json)")
        summary = json.loads(path.read_text())
        caveat = (f"profile {summary['profile']}, 2D, {summary['n_seeds_heterogeneous']} "
                  f"heterogeneous specimens per kappa")
        n_het = int(summary.get("n_seeds_heterogeneous") or 0)
        out += [finding_claim(f, caveat, n_het) for f in summary["findings"]]
        out.append(robustness_claim(summary))
    return out
