"""Snakemake script of rule drying_published: the paper's drying figures, the summary with
checks 14-16 for both fragment labellings and the validation rows of an archived ensemble,
rebuilt from its committed tables (results/published/<name>/) without running a simulation.

Outside Snakemake: ``python workflow/scripts/drying_published.py PUBLISHED_DIR OUTDIR``.
"""

import json
import sys
from pathlib import Path

from craquelure import validation
from craquelure.drying.campaign import LABELLINGS, build_campaign
from craquelure.drying.figures import FIGURES, make_figures
from craquelure.drying.published import read_tables
from craquelure.drying.summary import write_summary
from craquelure.io import open_dataset, write_dataset


def main(published: str, outdir: str, window: str = "paper") -> None:
    source, out = Path(published), Path(outdir)
    profile = json.loads((source / "provenance.json").read_text()).get("profile", "")
    fragments = read_tables(source)
    paths = {}
    for labelling in LABELLINGS:
        paths[labelling] = write_dataset(
            build_campaign(fragments, window_mode=window, labelling=labelling),
            out / f"campaign_{labelling}.nc")
    summary = write_summary(paths["periodic"], out / "summary.json", profile=profile,
                            open_campaign_path=paths["open"])
    written = make_figures(open_dataset(paths["periodic"]), summary,
                           open_dataset(source / "snapshots.nc"),
                           {name: out / "figures" / f"drying_{name}.png" for name in FIGURES},
                           profile)
    claims = validation.collect({"drying": [out / "summary.json"]})
    validation.write_json(claims, out / "validation.json", profile,
                          {"drying": [str(out / "summary.json")]})
    validation.write_html(claims, out / "validation.html", profile,
                          [p for p in written if p.suffix == ".png"])
    for c in claims:
        print(f"{c.verdict:>14}: {c.claim} | {c.source}")


if "snakemake" in globals():
    with open(snakemake.log[0], "w") as log:  # noqa: F821
        sys.stdout = sys.stderr = log
        main(snakemake.params.published, snakemake.params.outdir)  # noqa: F821
elif __name__ == "__main__":
    main(*sys.argv[1:])
