"""Snakemake script of rule drying_published: the paper's drying figures, the summary with
checks 14-16 for both fragment labellings and the validation rows of an archived ensemble,
rebuilt from its committed tables (results/published/<name>/) without running a simulation.

The check 14-16 rows of the companion ensembles it names (their rebuilt summaries,
results/drying_published/<companion>/summary.json) stand beside its own in the validation
report (craquelure.drying.claims.companion). An ensemble whose runs override their scene's
criterion with one that departs from the source's (results/drying/<scene>_C<measure>/) is such
a variant itself: its rows carry no verdict.

Outside Snakemake: ``python workflow/scripts/drying_published.py PUBLISHED_DIR OUTDIR
[COMPANION_SUMMARY ...]``.
"""

import json
import sys
from pathlib import Path

from craquelure import validation
from craquelure.drying.analysis import run_scene
from craquelure.drying.campaign import LABELLINGS, build_campaign
from craquelure.drying.claims import companion, criterion_variant
from craquelure.drying.figures import FIGURES, make_figures
from craquelure.drying.published import read_tables
from craquelure.drying.summary import write_summary
from craquelure.io import open_dataset, write_dataset
from craquelure.provenance import WallClock, provenance_attrs


def main(published: str, outdir: str, *companions: str, window: str = "paper") -> None:
    source, out = Path(published), Path(outdir)
    provenance = json.loads((source / "provenance.json").read_text())
    profile = provenance.get("profile", "")
    clock = WallClock()
    fragments = read_tables(source)
    paths = {}
    for labelling in LABELLINGS:
        campaign = build_campaign(fragments, window_mode=window, labelling=labelling)
        campaign.attrs.update(provenance_attrs(
            run_scene(fragments[0]), None, clock,
            effects=str(fragments[0].attrs.get("effects", "")).split(",")))
        campaign.attrs["sources"] = str(source / "tables")
        paths[labelling] = write_dataset(campaign, out / f"campaign_{labelling}.nc")
    summary = write_summary(paths["periodic"], out / "summary.json", profile=profile,
                            open_campaign_path=paths["open"])
    written = make_figures(open_dataset(paths["periodic"]), summary,
                           open_dataset(source / "snapshots.nc"),
                           {name: out / "figures" / f"drying_{name}.png" for name in FIGURES},
                           profile)
    claims = validation.collect({"drying": [out / "summary.json"]})
    beside = [companion(Path(p).parent.name, json.loads(Path(p).read_text()))
              for p in companions]
    if criterion_variant(provenance):  # its rows without verdicts, as beside a headline
        claims = []
        beside = [companion(source.name, json.loads((out / "summary.json").read_text()))]
    validation.write_json(claims, out / "validation.json", profile,
                          {"drying": [str(out / "summary.json")]}, beside)
    validation.write_html(claims, out / "validation.html", profile,
                          [p for p in written if p.suffix == ".png"], beside)
    for c in claims:
        print(f"{c.verdict:>14}: {c.claim} | {c.source}")


if "snakemake" in globals():
    with open(snakemake.log[0], "w") as log:  # noqa: F821
        sys.stdout = sys.stderr = log
        main(snakemake.params.published, snakemake.params.outdir,  # noqa: F821
             *snakemake.input.companions)  # noqa: F821
elif __name__ == "__main__":
    main(*sys.argv[1:])
