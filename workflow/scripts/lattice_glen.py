"""Glen's-law summary, table and figure from the stress-sweep datasets."""

import math
import sys

from craquelure.lattice import analysis, figures

if "snakemake" in globals():
    smk = snakemake  # noqa: F821
    sys.stderr = sys.stdout = open(smk.log[0], "w")  # noqa: SIM115
    desc = analysis.describe(smk.input.glen[0])
    summary, rows, fits = analysis.glen_summary({"glen": list(smk.input.glen),
                                                 "frozen": list(smk.input.frozen)},
                                                smk.output.summary, smk.output.table)
    figures.glen(rows, fits["glen"], fits.get("frozen", (math.nan, math.nan)),
                 smk.output.figure, f"{smk.params.title} ({desc})")
    print(summary)
