"""Validation report: the papers' claims, one row each, with what was measured and a verdict.

Last stage of the pipeline: it reads analysis outputs only (``summary.json`` files and analysis
datasets), never runs a simulation. Each model states its claims in ``craquelure.<model>.claims``
(``claims(sources) -> list[Claim]``, ``sources`` being the files its rules registered); this
module collects them and writes ``results/validation.json`` and ``results/validation.html``
(the latter embedded in the Snakemake report).

Verdicts are computed from the criterion's conditions, never typed in:

- ``reproduced``: every condition holds;
- ``partly``: some hold; the row names the ones that do not;
- ``not reproduced``: none holds (or, for a claim whose source states it as a single test, any
  fails);
- ``inconclusive``: no condition fails, but the sample cannot decide the claim (a test without
  the power to reject the named alternative, too few samples for an extreme-value statement);
  the row says what cannot be decided and the sample it would need. A small profile therefore
  never prints ``reproduced`` on a claim its sample cannot decide.

Helpers for sample-size decisions shared by the models: :func:`fraction_decision` (a fraction of
samples against a threshold, exact binomial interval), :func:`fraction_power` (its power against
a named alternative fraction, by simulation at a given sample size) and
:func:`samples_for_power` (the sample size that power needs).
"""

from __future__ import annotations

import html
import json
from collections.abc import Mapping, Sequence
from dataclasses import asdict, dataclass
from functools import cache
from importlib import import_module
from pathlib import Path

from craquelure.io import write_text_atomic
from craquelure.models import MODELS
from craquelure.provenance import git_commit, library_versions

VERDICTS = ("reproduced", "partly", "not reproduced", "inconclusive")
POWER_NEEDED = 0.8  # power (or confirmation rate) a sample needs to decide a claim
DECISION_LEVEL = 0.95  # confidence of the intervals that decide fractions of samples


@dataclass(frozen=True)
class Claim:
    """One claim of a source paper (or of a spec check standing for it) and how it fared."""

    model: str
    claim: str  # the paper's statement
    source: str  # where it is stated: paper figure, spec section or check
    criterion: str  # the test applied to the measurement
    measured: str  # the numbers
    verdict: str  # one of VERDICTS
    note: str = ""  # failed conditions, caveats (sample size, profile departures)

    def __post_init__(self) -> None:
        if self.verdict not in VERDICTS:
            raise ValueError(f"verdict: {self.verdict!r} is not allowed; allowed values: "
                             f"{', '.join(VERDICTS)}")

    @classmethod
    def judged(cls, model: str, claim: str, source: str, criterion: str, measured: str,
               conditions: Mapping[str, bool], undecided: Mapping[str, str] | None = None,
               partial: bool = True) -> Claim:
        """A claim whose verdict and note :func:`verdict_of` computes from its conditions."""
        return cls(model, claim, source, criterion, measured,
                   *verdict_of(conditions, undecided, partial))


def verdict_of(conditions: Mapping[str, bool], undecided: Mapping[str, str] | None = None,
               partial: bool = True) -> tuple[str, str]:
    """(verdict, note) for named boolean conditions.

    ``undecided`` maps what the sample cannot decide to the sample it would need (e.g.
    ``{"power 0.31 against t^-2 < 0.8": "about 40 seeds"}``): when no condition fails, such a
    claim is ``inconclusive``, not ``reproduced``. A failing condition still decides (a test
    that rejects at its level is evidence whatever its power); ``partial=False`` makes any
    failure ``not reproduced`` (claims the source states as one test)."""
    undecided = dict(undecided or {})
    if not conditions and not undecided:
        raise ValueError("a verdict needs at least one condition")
    failed = [name for name, ok in conditions.items() if not ok]
    open_ = "; cannot decide: " + "; ".join(f"{k} (needs {v})" for k, v in undecided.items())
    if failed:
        note = "fails: " + ", ".join(failed) + (open_ if undecided else "")
        whole = not partial or len(failed) == len(conditions)
        return ("not reproduced" if whole else "partly"), note
    if undecided:
        return "inconclusive", "sample cannot decide: " + open_.split(": ", 1)[1]
    return "reproduced", ""


@cache
def fraction_decided(successes: int, n: int, threshold: float,
                     level: float = DECISION_LEVEL) -> bool | None:
    """Does a fraction of ``n`` samples meet ``>= threshold``? True/False when the exact
    (Clopper-Pearson) two-sided ``level`` interval of ``successes / n`` lies on one side of the
    threshold (lower bound >= threshold / upper bound < threshold), None when it straddles it."""
    if n <= 0:
        return None
    lo, hi = fraction_interval(successes, n, level)
    if lo >= threshold:
        return True
    if hi < threshold:
        return False
    return None


def fraction_interval(k: float, n: int, level: float = DECISION_LEVEL) -> tuple[float, float]:
    """Exact (Clopper-Pearson) two-sided ``level`` interval of a fraction k/n."""
    from scipy import stats

    tail = (1.0 - level) / 2.0
    lo = stats.beta.ppf(tail, k, n - k + 1) if k > 0 else 0.0
    hi = stats.beta.ppf(1 - tail, k + 1, n - k) if k < n else 1.0
    return float(lo), float(hi)


def fraction_decision(successes: int, n: int, threshold: float,
                      level: float = DECISION_LEVEL) -> tuple[bool | None, str]:
    """:func:`fraction_decided` and, when undecided, the sample that would decide at the
    observed fraction (smallest n' whose interval at the same fraction excludes the
    threshold)."""
    if n <= 0:
        return None, "at least one sample"
    decided = fraction_decided(successes, n, threshold, level)
    if decided is not None:
        return decided, ""
    fraction = successes / n
    if fraction == threshold:
        return None, "more samples than any finite count (fraction on the threshold)"
    for m in range(n + 1, 100 * n + 1000):
        lo, hi = fraction_interval(round(fraction * m), m, level)
        if lo >= threshold or hi < threshold:
            return None, f"about {m} samples at the observed fraction {fraction:.2f}"
    return None, f"more than {100 * n + 1000} samples"


POWER_DRAWS = 4000  # simulated samples per power estimate
POWER_SEED = 20261201


@cache
def fraction_power(n: int, alternative: float, threshold: float,
                   level: float = DECISION_LEVEL, draws: int = POWER_DRAWS) -> float:
    """Power of :func:`fraction_decided` at ``n`` samples against a true fraction
    ``alternative``, by simulation: the share of ``draws`` binomial samples (fixed generator
    seed) that the test decides in the alternative's direction (True when the alternative
    meets the threshold, False when it does not)."""
    import numpy as np

    if n <= 0:
        return 0.0
    want = alternative >= threshold
    rng = np.random.default_rng([POWER_SEED, n, round(alternative * 1e6)])
    ks = rng.binomial(n, alternative, size=draws)
    values, counts = np.unique(ks, return_counts=True)
    hits = sum(int(c) for k, c in zip(values, counts, strict=True)
               if fraction_decided(int(k), n, threshold, level) is want)
    return hits / draws


def samples_for_power(n: int, alternative: float, threshold: float,
                      needed: float = POWER_NEEDED, largest: int = 200) -> int | None:
    """Smallest sample size >= ``n`` whose :func:`fraction_power` against ``alternative``
    reaches ``needed`` (None up to ``largest``). The exact interval is discrete, so power is not
    monotone in n; this is the first size that reaches it."""
    for m in range(max(n, 1), largest + 1):
        if fraction_power(m, alternative, threshold) >= needed:
            return m
    return None


def collect(sources: Mapping[str, Sequence[str | Path]]) -> list[Claim]:
    """Claims of every model that has sources, in the order of MODELS."""
    unknown = sorted(set(sources) - set(MODELS))
    if unknown:
        raise ValueError(f"validation sources: unknown model(s) {', '.join(unknown)}; allowed "
                         f"values: {', '.join(MODELS)}")
    claims: list[Claim] = []
    for model in MODELS:
        paths = [Path(p) for p in sources.get(model, ())]
        if paths:
            claims.extend(import_module(f"craquelure.{model}.claims").claims(paths))
    return claims


def tally(claims: Sequence[Claim]) -> dict[str, dict[str, int]]:
    """Counts of each verdict per model and in all."""
    out: dict[str, dict[str, int]] = {}
    for c in claims:
        for key in (c.model, "all"):
            out.setdefault(key, dict.fromkeys(VERDICTS, 0))[c.verdict] += 1
    return out


def write_json(claims: Sequence[Claim], path: str | Path, profile: str,
               sources: Mapping[str, Sequence[str | Path]] | None = None) -> Path:
    doc = {"profile": profile, "tally": tally(claims), "claims": [asdict(c) for c in claims],
           "provenance": {"git_commit": git_commit(), **library_versions(),
                          "sources": {m: [str(p) for p in paths]
                                      for m, paths in (sources or {}).items()}}}
    return write_text_atomic(path, json.dumps(doc, indent=2) + "\n")


_STYLE = """
body { font-family: sans-serif; font-size: 13px; margin: 1em; }
table { border-collapse: collapse; width: 100%; }
th, td { border: 1px solid #bbb; padding: 4px 6px; vertical-align: top; text-align: left; }
th { background: #eee; }
td.reproduced { background: #d9f2d9; }
td.partly { background: #fff2cc; }
td.not-reproduced { background: #f8d7d7; }
td.inconclusive { background: #e0e0ef; }
"""


def render_html(claims: Sequence[Claim], profile: str) -> str:
    counts = tally(claims)
    rows = []
    for model in MODELS:
        mine = [c for c in claims if c.model == model]
        if not mine:
            continue
        n = counts[model]
        rows.append(f'<tr><th colspan="5">{model}: {n["reproduced"]} reproduced, '
                    f'{n["partly"]} partly, {n["not reproduced"]} not reproduced, '
                    f'{n["inconclusive"]} inconclusive</th></tr>')
        for c in mine:
            cells = [c.claim, c.source, c.criterion, c.measured]
            tds = "".join(f"<td>{html.escape(x)}</td>" for x in cells)
            verdict = html.escape(c.verdict) + (f"<br><small>{html.escape(c.note)}</small>"
                                                if c.note else "")
            rows.append(f'<tr>{tds}<td class="{c.verdict.replace(" ", "-")}">{verdict}</td></tr>')
    head = "".join(f"<th>{h}</th>" for h in
                   ("claim", "source", "criterion", "measured", "verdict"))
    total = counts.get("all", dict.fromkeys(VERDICTS, 0))
    return (f"<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>craquelure validation"
            f"</title><style>{_STYLE}</style></head><body>\n"
            f"<h2>Validation, profile {html.escape(profile)}</h2>\n"
            f"<p>{len(claims)} claims: {total['reproduced']} reproduced, {total['partly']} partly, "
            f"{total['not reproduced']} not reproduced, {total['inconclusive']} inconclusive. "
            f"Verdicts are computed from the criterion's conditions; 'partly' names the "
            f"conditions that fail; 'inconclusive' means no condition fails but the sample "
            f"cannot decide the claim, and names the sample it would need.</p>\n"
            f"<table><tr>{head}</tr>\n" + "\n".join(rows) + "\n</table></body></html>\n")


def write_html(claims: Sequence[Claim], path: str | Path, profile: str) -> Path:
    return write_text_atomic(path, render_html(claims, profile))
