"""Error-versus-wall-time curve of the lattice: fundamental mode of a clamped column against
the continuum period, for several resolutions and time-step factors."""

import sys

import numba

from craquelure.lattice import accuracy, analysis, figures

if "snakemake" in globals():
    smk = snakemake  # noqa: F821
    sys.stderr = sys.stdout = open(smk.log[0], "w")  # noqa: SIM115
    numba.set_num_threads(smk.threads)
    rows = [{"dt_factor": float(f), **r} for f in smk.params.dt_factors
            for r in accuracy.study(smk.params.rows, dt_factor=float(f))]
    figures.accuracy(rows, smk.output.figure, smk.params.title)
    print(analysis.accuracy_summary(rows, smk.params.dt_factors, smk.output.table,
                                    smk.output.summary))
