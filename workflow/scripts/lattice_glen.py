"""Glen's-law figure, table and summary from the stress-sweep datasets."""

import sys

from craquelure.lattice import analysis

if "snakemake" in globals():
    smk = snakemake  # noqa: F821
    sys.stderr = sys.stdout = open(smk.log[0], "w")  # noqa: SIM115
    desc = analysis.describe(smk.input.glen[0])
    summary = analysis.glen_summary({"glen": list(smk.input.glen),
                                     "frozen": list(smk.input.frozen)},
                                    smk.output.figure, smk.output.summary, smk.output.table,
                                    f"{smk.params.title} ({desc})")
    print(summary)
