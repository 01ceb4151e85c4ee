"""Validation report: the papers' claims, one row each, with what was measured and a verdict
(docs/outputs.md, "Validation report").

Last stage of the pipeline: it reads analysis outputs only, never runs a simulation. Each model
states its claims in ``craquelure.<model>.claims`` (``claims(sources) -> list[Claim]``); this
module collects them and writes ``results/validation.json`` and ``results/validation.html``.
Verdicts are computed from the criterion's conditions (:func:`verdict_of`), never typed in, and
from the data alone, so the same analysis outputs give the same report byte for byte: a claim
whose only measurement is a timing is judged by a script in ``benchmarks/`` instead
(:func:`benchmarked`).
"""

from __future__ import annotations

import html
import json
from collections.abc import Mapping, Sequence
from dataclasses import asdict, dataclass
from functools import cache
from importlib import import_module
from pathlib import Path

import numpy as np

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
    deciding: str = ""  # the one number the verdict turns on, with its bound (summary table)
    figure: str = ""  # the figure that decides it: the tail of its path ("glen/glen.png")

    def __post_init__(self) -> None:
        if self.verdict not in VERDICTS:
            raise ValueError(f"verdict: {self.verdict!r} is not allowed; allowed values: "
                             f"{', '.join(VERDICTS)}")

    @classmethod
    def judged(cls, model: str, claim: str, source: str, criterion: str, measured: str,
               conditions: Mapping[str, bool], undecided: Mapping[str, str] | None = None,
               partial: bool = True, *, deciding: str = "", figure: str = "") -> Claim:
        """A claim whose verdict and note :func:`verdict_of` computes from its conditions."""
        return cls(model, claim, source, criterion, measured,
                   *verdict_of(conditions, undecided, partial), deciding=deciding, figure=figure)


def verdict_of(conditions: Mapping[str, bool], undecided: Mapping[str, str] | None = None,
               partial: bool = True) -> tuple[str, str]:
    """(verdict, note) for named boolean conditions.

    ``undecided`` maps what the sample cannot decide to the sample it would need: when no
    condition fails, such a claim is ``inconclusive``, not ``reproduced``. A failing condition
    still decides (a test that rejects at its level is evidence whatever its power);
    ``partial=False`` makes any failure ``not reproduced`` (claims the source states as one
    test)."""
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
    return True if lo >= threshold else (False if hi < threshold else None)


def fraction_interval(k: float, n: int, level: float = DECISION_LEVEL) -> tuple[float, float]:
    """Exact (Clopper-Pearson) two-sided ``level`` interval of a fraction k/n."""
    from scipy import stats

    tail = (1.0 - level) / 2.0
    lo = stats.beta.ppf(tail, k, n - k + 1) if k > 0 else 0.0
    hi = stats.beta.ppf(1 - tail, k + 1, n - k) if k < n else 1.0
    return float(lo), float(hi)


def bootstrap_interval(replicates, axis: int | None = None):
    """The 95 % percentile interval of bootstrap replicates, their 2.5th and 97.5th percentiles
    (NaN replicates left out): ``[lo, hi]``, or along ``axis`` the arrays ``(lo, hi)``."""
    lo, hi = np.nanpercentile(replicates, [2.5, 97.5], axis=axis)
    return [float(lo), float(hi)] if axis is None else (lo, hi)


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
    return [claim for model in MODELS if sources.get(model)
            for claim in import_module(f"craquelure.{model}.claims").claims(
                [Path(p) for p in sources[model]])]


def benchmarked(models: Sequence[str] = MODELS) -> list[dict[str, str]]:
    """Claims a model leaves out of the report because their only measurement is a timing
    (``BENCHMARKED = {claim: benchmark script}`` in its claims module), with that script."""
    return [{"model": model, "claim": claim, "judged_by": script} for model in models
            for claim, script in getattr(import_module(f"craquelure.{model}.claims"),
                                         "BENCHMARKED", {}).items()]


def _models_of(claims: Sequence[Claim]) -> list[str]:
    return [m for m in MODELS if any(c.model == m for c in claims)]


def tally(claims: Sequence[Claim]) -> dict[str, dict[str, int]]:
    """Counts of each verdict per model and in all."""
    out: dict[str, dict[str, int]] = {}
    for c in claims:
        for key in (c.model, "all"):
            out.setdefault(key, dict.fromkeys(VERDICTS, 0))[c.verdict] += 1
    return out


def write_json(claims: Sequence[Claim], path: str | Path, profile: str,
               sources: Mapping[str, Sequence[str | Path]] | None = None,
               companions: Sequence[Mapping] = ()) -> Path:
    """The report as JSON; ``companions``: other ensembles' rows shown beside these (``name``,
    ``setting``, ``judged``, ``why`` not judged, ``claims``; e.g.
    :func:`craquelure.drying.claims.companion`), outside the tally, verdicts ``null`` when
    not judged."""
    doc = {"profile": profile, "tally": tally(claims), "claims": [asdict(c) for c in claims],
           "benchmarked": benchmarked(_models_of(claims)),
           "provenance": {"git_commit": git_commit(), **library_versions(),
                          "sources": {m: [str(p) for p in paths]
                                      for m, paths in (sources or {}).items()}}}
    if companions:
        doc["companions"] = [
            {**{k: v for k, v in c.items() if k != "claims"},
             "tally": tally(c["claims"]) if c["judged"] else None,
             "claims": [asdict(x) | ({} if c["judged"] else {"verdict": None})
                        for x in c["claims"]]} for c in companions]
    return write_text_atomic(path, json.dumps(doc, indent=2) + "\n")


# --- rendering: results/validation.html and the summary that opens the Snakemake report -------

# Thumbnails are the deciding figures themselves, scaled down once per figure and embedded (the
# page and the report stay single files); rows show them small, the folded details large.
FIGURE_WIDTH = 720  # pixels of the embedded copy of a figure
SUMMARY_CLASS = "cq-summary"
KEY_FIGURE_SIZE = (300, 220)  # largest width and height of a key figure below the table

_STYLE = """
.cq-summary { font-family: sans-serif; font-size: 13px; line-height: 1.3; color: #222; }
.cq-summary h2 { font-size: 18px; margin: 0 0 4px 0; }
.cq-summary p.cq-tally { margin: 0 0 8px 0; }
.cq-grid { display: grid; grid-template-columns: repeat(auto-fit, minmax(470px, 1fr));
           gap: 0 16px; align-items: start; }
.cq-summary table.cq-table { border-collapse: collapse; width: 100%; table-layout: fixed;
                             margin: 0; }
.cq-table th, .cq-table td { border-bottom: 1px solid #ddd; padding: 1px 4px; text-align: left;
                             vertical-align: middle; }
.cq-table col.cq-c-thumb { width: 48px; } .cq-table col.cq-c-verdict { width: 104px; }
.cq-table col.cq-c-number { width: 34%; }
.cq-table tr.cq-model th { background: #eee; font-weight: bold; padding: 3px 4px; }
.cq-table td.cq-claim { overflow: hidden; }
.cq-table td.cq-claim summary { display: block; cursor: pointer; white-space: nowrap;
                                overflow: hidden; text-overflow: ellipsis; }
.cq-table td.cq-claim summary::before { content: "\\25B8  "; color: #777; }
.cq-table td.cq-claim details[open] summary { white-space: normal; }
.cq-table td.cq-claim details[open] summary::before { content: "\\25BE  "; }
.cq-table td.cq-number { white-space: nowrap; overflow: hidden; text-overflow: ellipsis; }
.cq-table dl { margin: 4px 0; } .cq-table dt { font-weight: bold; margin-top: 3px; }
.cq-table dd { margin: 0 0 0 12px; white-space: normal; }
.cq-thumb { display: block; width: 44px; height: 29px; background: #f6f6f6 center / contain
            no-repeat; border: 1px solid #ccc; }
.cq-thumb.cq-none { background: repeating-linear-gradient(45deg, #f6f6f6, #f6f6f6 4px,
                    #e8e8e8 4px, #e8e8e8 8px); }
.cq-figure { width: 100%; max-width: 720px; background: center / contain no-repeat;
             margin-top: 4px; }
.cq-badge { display: inline-block; border-radius: 8px; padding: 1px 7px; font-size: 11px;
            font-weight: bold; white-space: nowrap; }
.cq-badge.reproduced { background: #2e7d32; color: #fff; }
.cq-badge.partly { background: #f9a825; color: #222; }
.cq-badge.not-reproduced { background: #c62828; color: #fff; }
.cq-badge.inconclusive { background: #5c6bc0; color: #fff; }
.cq-keyfigs { display: flex; flex-wrap: wrap; gap: 8px; margin-top: 10px; }
.cq-keyfigs figure { margin: 0; }
.cq-keyfigs figcaption { font-size: 11px; color: #555; }
"""


def figure_for(claim: Claim, figures: Sequence[str | Path]) -> Path | None:
    """The figure file of ``claim`` among ``figures``: the first of its model's (a path with
    the model's folder, ``results/<model>/...``) whose path ends with the claim's ``figure``
    (whole path components), else None."""
    if not claim.figure:
        return None
    tail = Path(claim.figure).parts
    for path in map(Path, figures):
        if path.parts[-len(tail):] == tail and claim.model in path.parts[:-len(tail)]:
            return path
    return None


def _figure_data(path: Path) -> tuple[str, float]:
    """``(data URI, height / width)`` of a figure scaled to :data:`FIGURE_WIDTH` pixels."""
    import base64
    import io

    from PIL import Image

    with Image.open(path) as im:
        im = im.convert("RGB")
        if im.width > FIGURE_WIDTH:
            im = im.resize((FIGURE_WIDTH, round(im.height * FIGURE_WIDTH / im.width)),
                           Image.LANCZOS)
        buf = io.BytesIO()  # 256 colours: a plot's few colours and their anti-aliasing
        im.quantize(256, dither=Image.Dither.NONE).save(buf, "PNG", optimize=True)
        ratio = im.height / im.width
    return "data:image/png;base64," + base64.b64encode(buf.getvalue()).decode(), ratio


def _figure_div(i: int, name: str, ratio: float) -> str:
    """The embedded figure ``i`` (class ``cq-f<i>``) at its aspect ratio."""
    return (f'<div class="cq-figure cq-f{i}" role="img" aria-label="figure {html.escape(name)}" '
            f'style="aspect-ratio: {1 / ratio:.4f}"></div>')


def _badge(verdict: str) -> str:
    return f'<span class="cq-badge {verdict.replace(" ", "-")}">{html.escape(verdict)}</span>'


def render_summary(claims: Sequence[Claim], profile: str,
                   figures: Sequence[str | Path] = (), heading: str = "",
                   not_judged: str = "") -> str:
    """The one-screen summary (docs/outputs.md, "The page") as a self-contained HTML fragment
    (its own style, figures embedded): the body of results/validation.html and the lead of the
    Snakemake report's first page. ``heading`` replaces the title; ``not_judged`` (why) shows
    the rows without verdicts."""
    counts = tally(claims)
    total = counts.get("all", dict.fromkeys(VERDICTS, 0))
    shown = dict.fromkeys(p for c in claims if (p := figure_for(c, figures)) is not None)
    used = {path: i for i, path in enumerate(shown)}  # each figure once, in claim order
    styles, ratios = [], {}
    for path, i in used.items():
        uri, ratios[i] = _figure_data(path)
        styles.append(f".cq-f{i} {{ background-image: url({uri}); }}")
    rows: list[tuple[str, str]] = []  # (model, row); a model heading row has model ""
    key: dict[str, Path] = {}  # one key figure per model: its first claim's that has one
    for model in MODELS:
        mine = [c for c in claims if c.model == model]
        if not mine:
            continue
        told = "" if not_judged else ": " + ", ".join(f"{counts[model][v]} {v}" for v in VERDICTS)
        rows.append(("", f'<tr class="cq-model"><th colspan="4">{html.escape(model)}{told}'
                         f'</th></tr>'))
        for c in mine:
            path = figure_for(c, figures)
            name = html.escape(path.name if path else "")
            if path is None:
                thumb = '<span class="cq-thumb cq-none" role="img" aria-label="no figure"></span>'
                large = ""
            else:
                i = used[path]
                key.setdefault(model, path)
                thumb = (f'<span class="cq-thumb cq-f{i}" role="img" '
                         f'aria-label="figure {name}" title="{name}"></span>')
                large = _figure_div(i, path.name, ratios[i])
            items = [("source", c.source), ("criterion", c.criterion), ("measured", c.measured),
                     ("note", c.note or None), ("figure", path.name if path else None)]
            dl = "".join(f"<dt>{k}</dt><dd>{html.escape(v)}</dd>" for k, v in items
                         if v is not None)
            number = html.escape(c.deciding or "-")
            rows.append((model, (
                f'<tr class="cq-row" data-verdict="{"" if not_judged else html.escape(c.verdict)}">'
                f'<td class="cq-fig">{thumb}</td>'
                f'<td class="cq-claim"><details><summary title="{html.escape(c.claim)}">'
                f'{html.escape(c.claim)}</summary><dl>{dl}</dl>{large}</details></td>'
                f'<td class="cq-verdict">{_badge("not judged" if not_judged else c.verdict)}'
                f'</td>'
                f'<td class="cq-number" title="{number}">{number}</td></tr>')))
    # Two columns of (nearly) equal length; a column never ends on a model heading, and one
    # that starts inside a model repeats its heading.
    split = (len(rows) + 1) // 2
    while 0 < split < len(rows) and not rows[split - 1][0]:
        split -= 1
    if 0 < split < len(rows) and rows[split][0]:
        rows.insert(split, ("", f'<tr class="cq-model"><th colspan="4">'
                                f'{html.escape(rows[split][0])} (continued)</th></tr>'))
    cols = '<colgroup><col class="cq-c-thumb"><col><col class="cq-c-verdict">' \
           '<col class="cq-c-number"></colgroup>'
    head = ('<thead><tr><th>figure</th><th>claim (click for criterion and numbers)</th>'
            '<th>verdict</th><th>deciding number</th></tr></thead>')
    tables = "".join(
        f'<table class="cq-table">{cols}{head}<tbody>{"".join(r for _, r in part)}'
        f'</tbody></table>' for part in (rows[:split], rows[split:]) if part)
    keyfigs = []
    for model, path in key.items():
        i = used[path]
        width = min(KEY_FIGURE_SIZE[0], KEY_FIGURE_SIZE[1] / ratios[i])
        keyfigs.append(f'<figure style="width: {width:.0f}px">'
                       f'{_figure_div(i, path.name, ratios[i])}<figcaption>'
                       f'{html.escape(model)}: {html.escape(path.name)}</figcaption></figure>')
    keys = (f'<h3>Key figures</h3><div class="cq-keyfigs">{"".join(keyfigs)}</div>'
            if keyfigs else "")
    timed = "; ".join(f"{html.escape(b['model'])}: {html.escape(b['claim'])}, judged by "
                      f"<code>{html.escape(b['judged_by'])}</code>"
                      for b in benchmarked(_models_of(claims)))
    timed = (f'<p class="cq-tally">Not judged here (the only measurement is a timing, which '
             f'depends on the machine\'s load; a verdict must follow from the data): {timed}.'
             f'</p>\n' if timed else "")
    heading = html.escape(heading or f"Validation, profile {profile}")
    if not_judged:
        return (f'<section class="{SUMMARY_CLASS}"><style>{_STYLE}.cq-badge.not-judged '
                f'{{ background: #9e9e9e; color: #fff; }}</style>\n<h2>{heading}</h2>'
                f'\n<p class="cq-tally">{len(claims)} rows, not judged: '
                f'{html.escape(not_judged)}.</p>\n<div class="cq-grid">{tables}</div>'
                f'</section>\n')
    return (f'<section class="{SUMMARY_CLASS}"><style>{_STYLE}\n' + "\n".join(styles) +
            f'</style>\n<h2>{heading}</h2>\n'
            f'<p class="cq-tally">{len(claims)} claims: '
            + ", ".join(f"{total[v]} {_badge(v)}" for v in VERDICTS) +
            '. Verdicts are computed from each criterion\'s conditions: '
            f'"partly" names the conditions that fail, "inconclusive" means none fails but the '
            f'sample cannot decide (the row names the sample it would need).</p>\n'
            f'<div class="cq-grid">{tables}</div>\n{timed}{keys}</section>\n')


def render_html(claims: Sequence[Claim], profile: str,
                figures: Sequence[str | Path] = (), companions: Sequence[Mapping] = ()) -> str:
    """results/validation.html: the summary (:func:`render_summary`) as a page, then the rows
    of each companion ensemble (:func:`write_json`) beside it."""
    beside = "".join(render_summary(c["claims"], profile, (), f"Beside it: {c['name']}, "
                                    f"{c['setting']}", "" if c["judged"] else c["why"])
                     for c in companions)
    return ("<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><meta name=\"viewport\" "
            "content=\"width=device-width\"><title>craquelure validation</title></head>"
            "<body style=\"margin: 8px\">\n" + render_summary(claims, profile, figures) +
            beside + "</body></html>\n")


def write_html(claims: Sequence[Claim], path: str | Path, profile: str,
               figures: Sequence[str | Path] = (), companions: Sequence[Mapping] = ()) -> Path:
    return write_text_atomic(path, render_html(claims, profile, figures, companions))


def write_summary(claims: Sequence[Claim], path: str | Path, profile: str,
                  figures: Sequence[str | Path] = ()) -> Path:
    """The summary fragment alone (the Snakemake report's first page includes it)."""
    return write_text_atomic(path, render_summary(claims, profile, figures))
