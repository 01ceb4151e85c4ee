"""Publish check 12 (with and without CSCM's rate effects): both summaries, the report rows of
both tallies (CHECK12.md, rendered from the summaries), the judged-run pictures and a SHA-256
manifest (``craquelure verify results/published/impact-check12``)."""

import shutil
import sys
from pathlib import Path

from craquelure.archive import MANIFEST, manifest_text, sha256_file
from craquelure.impact.claims import claims

if "snakemake" in globals():
    smk = snakemake  # noqa: F821
    sys.stderr = sys.stdout = open(smk.log[0], "w")  # noqa: SIM115
    out = Path(smk.output[0])
    (out / "figures").mkdir(parents=True, exist_ok=True)
    for src in smk.input.summaries:
        shutil.copyfile(src, out / Path(src).name)
    for src in smk.input.figures:
        shutil.copyfile(src, out / "figures" / Path(src).name)
    rows = claims([Path(p) for p in smk.input.summaries])
    tally: dict[str, dict[str, int]] = {}
    lines = ["| claim | verdict | deciding number | figure |", "|---|---|---|---|"]
    for c in rows:
        group = c.claim.split("]")[0].lstrip("[")
        tally.setdefault(group, {})
        tally[group][c.verdict] = tally[group].get(c.verdict, 0) + 1
        lines.append(f"| {c.claim} | {c.verdict} | {c.deciding} | {c.figure} |")
    head = ["# Check 12, with and without CSCM's rate effects", ""]
    head += [f"- {group}: " + ", ".join(f"{n} {s}" for s, n in sorted(t.items()))
             for group, t in tally.items()]
    (out / "CHECK12.md").write_text("\n".join([*head, "", *lines]) + "\n")
    files = sorted(p for p in out.rglob("*") if p.is_file() and p.name != MANIFEST)
    (out / MANIFEST).write_text(manifest_text(
        {p.relative_to(out).as_posix(): sha256_file(p) for p in files}))
    print(f"published {len(files)} files to {out}")
