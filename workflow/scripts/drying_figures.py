"""Snakemake script of rule drying_figures: the paper's Figs. 2-6 from the campaign dataset,
the summary and one run dataset (PNG + PDF).

Outside Snakemake:
``python workflow/scripts/drying_figures.py CAMPAIGN.nc SUMMARY.json RUN.nc OUTDIR PROFILE``.
"""

import json
import sys
from pathlib import Path

from craquelure.drying.figures import FIGURES, make_figures
from craquelure.io import open_dataset


def main(campaign: str, summary: str, run: str, outputs: dict, profile: str) -> None:
    written = make_figures(open_dataset(campaign), json.loads(Path(summary).read_text()),
                           open_dataset(run), outputs, profile)
    print("wrote " + ", ".join(map(str, written)))


if "snakemake" in globals():
    with open(snakemake.log[0], "w") as log:  # noqa: F821
        sys.stdout = sys.stderr = log
        out = snakemake.output  # noqa: F821
        main(snakemake.input.campaign, snakemake.input.summary,  # noqa: F821
             snakemake.input.run, {name: out[name] for name in FIGURES},  # noqa: F821
             snakemake.params.profile)  # noqa: F821
elif __name__ == "__main__":
    campaign, summary, run, outdir, profile = sys.argv[1:6]
    main(campaign, summary, run,
         {name: Path(outdir) / f"drying_{name}.png" for name in FIGURES}, profile)
