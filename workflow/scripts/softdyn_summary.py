"""Numbers of the Soft Dynamics runs for the claims (results/softdyn/summary.json)."""

import sys

from craquelure.softdyn.analysis import summarise

if "snakemake" in globals():
    smk = snakemake  # noqa: F821
    sys.stderr = sys.stdout = open(smk.log[0], "w")  # noqa: SIM115
    print(summarise(list(smk.input), smk.output[0]))
