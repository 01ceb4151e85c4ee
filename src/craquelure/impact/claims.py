"""The impact paper's findings for the validation report (:mod:`craquelure.validation`).

Source: ``results/impact/summary.json`` (:mod:`craquelure.impact.analysis`), whose ``findings``
already carry the spec's check-12 criteria and ``reproduced`` flags computed from the runs;
this module only words them as claims and adds the robustness demand (every variant to the end,
closed energy balance).
"""

from __future__ import annotations

import json
import math
from pathlib import Path

from craquelure.validation import Claim, verdict_of

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


def finding_claim(finding: dict, caveat: str) -> Claim:
    measured = "; ".join(f"{k} = {_number(v)}" for k, v in finding["values"].items())
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
        out += [finding_claim(f, caveat) for f in summary["findings"]]
        out.append(robustness_claim(summary))
    return out
