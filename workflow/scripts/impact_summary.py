"""Summary of the impact campaign: per-case metrics and the source's findings (check 12)."""

import sys
from pathlib import Path

from craquelure.impact.analysis import summarise, write_summary

if "snakemake" in globals():
    sys.stderr = sys.stdout = open(snakemake.log[0], "w")  # noqa: F821, SIM115
    summary = summarise(snakemake.input, snakemake.params.profile,  # noqa: F821
                        snakemake.params.scene, snakemake.params.distribution,  # noqa: F821
                        snakemake.params.fixed_across_kappa)  # noqa: F821
    write_summary(summary, Path(snakemake.output[0]))  # noqa: F821
    for f in summary["findings"]:
        print(f"{f['status']:>15}: [{f['dim']}] {f['finding']} | {f['values']}")
