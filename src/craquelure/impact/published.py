"""The archived result of check 12 (``results/published/impact-check12/``): the campaign's two
summaries (without and with CSCM's rate effects, every run's measured quantities per case), the
rows decided from them, pictures, provenance and cost of the runs, and a SHA-256 manifest.
:func:`rebuild` decides check 12 again from the summaries' ``cases`` without a simulation (target
``published``); the rows it writes must equal the committed ones.
"""

from __future__ import annotations

import json
import shutil
from collections import defaultdict
from collections.abc import Sequence
from pathlib import Path

from craquelure.archive import benchmark_cpu_seconds
from craquelure.errors import CraquelureError
from craquelure.impact import check12
from craquelure.impact.claims import claims, with_rate
from craquelure.io import write_text_atomic
from craquelure.validation import tally, write_json

SUMMARIES = ("summary.json", "summary_rate.json")


def findings_from_cases(summary: dict, distribution: str) -> list[dict]:
    """Check 12's findings decided again from a summary's ``cases``, per dimension."""
    by_dim: dict[str, dict] = defaultdict(dict)
    for key, case in summary["cases"].items():
        dim = case["dim"]
        by_dim[dim][key.removeprefix(f"{dim}/")] = {k: v for k, v in case.items() if k != "dim"}
    findings: list[dict] = []
    for dim in summary["dimensions"]:
        found, _ = check12.evaluate(by_dim[dim], distribution, dim,
                                    summary.get("fixed_across_kappa", {}))
        findings += json.loads(json.dumps(found))  # as the summary stores them
    return findings


def cpu_seconds(benchmarks: Sequence[str | Path]) -> float:
    """CPU seconds of the Snakemake benchmark files that exist (the runs' measured cost)."""
    return sum(filter(None, map(benchmark_cpu_seconds, benchmarks)))


def readme(summaries: Sequence[dict], rows: list, provenance: dict) -> str:
    """README.md: what the folder holds, both tallies, every row."""
    lines = ["# Check 12, without and with CSCM's rate effects", "",
             "Concrete impact: the source's 3D disc (CSCM-like concrete) and the 2D slice, "
             "judged twice: without rate effects (`summary.json`) and with CSCM's rate effects "
             "(`summary_rate.json`). `validation.json` holds the rows, `figures/` the "
             "judged-run pictures and the static-strength sensitivity; target `published` "
             "decides the rows again from the summaries' per-run measurements.", ""]
    for summary in summaries:
        label = "with rate effects" if with_rate(summary) else "without rate effects"
        sub = [c for c in rows if label in c.claim]
        counts = ", ".join(f"{n} {v}" for v, n in tally(sub).get("impact", {}).items() if n)
        lines.append(f"- {label}: scene {summary['scene']}, {summary['n_runs']} runs; {counts}")
    lines += [f"- the check-12 runs (the sensitivity's not counted): commit(s) "
              f"{', '.join(provenance['run_git_commits'])}; "
              f"{provenance['cpu_hours_total']:.2f} CPU-hours", "",
              "| claim | verdict | deciding number | figure |", "|---|---|---|---|"]
    lines += [f"| {c.claim} | {c.verdict} | {c.deciding} | {c.figure} |" for c in rows]
    return "\n".join(lines) + "\n"


def publish(summaries: Sequence[str | Path], figures: Sequence[str | Path],
            provenance: dict, dest: str | Path, extra: Sequence[str | Path] = ()) -> Path:
    """Install check 12's archive in ``dest``: the summaries, their rows (``validation.json``),
    ``figures/``, ``extra`` files, ``provenance.json``, ``README.md`` and the manifest, written
    beside ``dest`` and renamed into place (a failure leaves the old folder whole)."""
    from craquelure.archive import MANIFEST, manifest_text, sha256_file

    summaries = [Path(p) for p in summaries]
    if sorted(p.name for p in summaries) != sorted(SUMMARIES):
        raise CraquelureError(f"publish check 12: summaries {[p.name for p in summaries]}; "
                              f"allowed: {', '.join(SUMMARIES)}")
    dest = Path(dest)
    work = dest.with_name(dest.name + ".tmp")
    shutil.rmtree(work, ignore_errors=True)
    (work / "figures").mkdir(parents=True)
    for src in [*summaries, *map(Path, extra)]:
        shutil.copyfile(src, work / src.name)
    for src in map(Path, figures):
        shutil.copyfile(src, work / "figures" / src.name)
    rows = claims([work / name for name in SUMMARIES])
    write_json(rows, work / "validation.json", provenance["profile"],
               {"impact": list(SUMMARIES)})
    write_text_atomic(work / "provenance.json", json.dumps(provenance, indent=1) + "\n")
    write_text_atomic(work / "README.md", readme(
        [json.loads((work / name).read_text()) for name in SUMMARIES], rows, provenance))
    files = sorted(p for p in work.rglob("*") if p.is_file())
    (work / MANIFEST).write_text(manifest_text(
        {p.relative_to(work).as_posix(): sha256_file(p) for p in files}))
    shutil.rmtree(dest, ignore_errors=True)
    work.rename(dest)
    return dest


def rebuild(folder: str | Path, out: str | Path) -> Path:
    """Check 12 decided again from an archived folder's summaries, written to ``out``."""
    folder, out = Path(folder), Path(out)
    provenance = json.loads((folder / "provenance.json").read_text())
    out.mkdir(parents=True, exist_ok=True)
    for name in SUMMARIES:
        summary = json.loads((folder / name).read_text())
        summary["findings"] = findings_from_cases(summary, provenance["distribution"])
        write_text_atomic(out / name, json.dumps(summary, indent=2) + "\n")
    write_json(claims([out / name for name in SUMMARIES]), out / "validation.json",
               provenance["profile"], {"impact": list(SUMMARIES)})
    return out
