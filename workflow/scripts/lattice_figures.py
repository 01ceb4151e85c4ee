"""Figure and summary of one lattice scene run (gravity_block, calving or fretting)."""

import sys

from craquelure.lattice import analysis

if "snakemake" in globals():
    smk = snakemake  # noqa: F821
    sys.stderr = sys.stdout = open(smk.log[0], "w")  # noqa: SIM115
    make = {"gravity_block": analysis.gravity_summary, "calving": analysis.calving_summary,
            "fretting": analysis.fretting_summary}[smk.wildcards.scene]
    title = f"{smk.params.title} ({analysis.describe(smk.input[0])})"
    print(make(smk.input[0], smk.output.figure, smk.output.summary, title))
