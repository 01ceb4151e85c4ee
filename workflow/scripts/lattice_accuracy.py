"""Error-versus-wall-time curve of the lattice: fundamental mode of a clamped column against
the continuum period, for several resolutions and time-step factors."""

import sys

import numba

from craquelure.lattice import analysis

if "snakemake" in globals():
    smk = snakemake  # noqa: F821
    sys.stderr = sys.stdout = open(smk.log[0], "w")  # noqa: SIM115
    numba.set_num_threads(smk.threads)
    print(analysis.accuracy_summary(smk.params.rows, smk.params.dt_factors, smk.output.figure,
                                    smk.output.table, smk.output.summary, smk.params.title))
