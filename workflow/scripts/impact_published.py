"""Snakemake script of rule impact_published: check 12 decided again from an archived folder's
per-run measurements (craquelure.impact.published.rebuild), without a simulation."""

import sys

from craquelure.impact.published import rebuild

if "snakemake" in globals():
    with open(snakemake.log[0], "w") as log:  # noqa: F821
        sys.stdout = sys.stderr = log
        out = rebuild(snakemake.params.published, snakemake.params.outdir)  # noqa: F821
        print(f"decided check 12 again from {snakemake.params.published} into {out}")  # noqa: F821
