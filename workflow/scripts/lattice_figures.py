"""Summary and figure of one lattice scene run (gravity_block, calving or fretting)."""

import sys

from craquelure.io import open_dataset
from craquelure.lattice import analysis, figures

if "snakemake" in globals():
    smk = snakemake  # noqa: F821
    sys.stderr = sys.stdout = open(smk.log[0], "w")  # noqa: SIM115
    ds = open_dataset(smk.input[0])
    title = f"{smk.params.title} ({analysis.describe(smk.input[0])})"
    out, scene = smk.output, smk.wildcards.scene
    if scene == "gravity_block":
        summary = analysis.gravity_summary(ds, out.summary)
        figures.gravity(ds, summary["predicted"], out.figure, title)
    elif scene == "calving":
        summary = analysis.calving_summary(ds, out.summary)
        figures.calving(ds, analysis.fragment_labels(ds), summary, out.figure, title)
    else:
        summary = analysis.fretting_summary(ds, out.summary)
        figures.fretting(ds, analysis.fragment_labels(ds), summary["cycles"], out.figure,
                         title)
    print(summary)
