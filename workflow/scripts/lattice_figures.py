"""Figure and summary of one lattice scene run (gravity_block, calving or fretting)."""

import sys

from craquelure.lattice import workflow

if "snakemake" in globals():
    smk = snakemake  # noqa: F821
    sys.stderr = sys.stdout = open(smk.log[0], "w")  # noqa: SIM115
    make = {"gravity_block": workflow.gravity_summary, "calving": workflow.calving_summary,
            "fretting": workflow.fretting_summary}[smk.wildcards.scene]
    title = f"{smk.params.title} ({workflow.describe(smk.input[0])})"
    print(make(smk.input[0], smk.output.figure, smk.output.summary, title))
