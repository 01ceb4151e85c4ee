"""One point of the Glen sweep: its scene (stress, confinement, run length from the melt rate)
is built when the job runs, not while Snakemake builds the DAG; then the run, through the
runner, as ``craquelure run`` would do it."""

import sys

import numba

from craquelure.lattice.analysis import glen_point_scene
from craquelure.lattice.api import run

if "snakemake" in globals():
    smk = snakemake  # noqa: F821
    sys.stderr = sys.stdout = open(smk.log[0], "w")  # noqa: SIM115
    numba.set_num_threads(smk.threads)
    scene = glen_point_scene(smk.input.scene, smk.params.lattice, smk.wildcards.kind,
                             int(smk.wildcards.k))
    print(f"wrote {run(scene, smk.output[0], seed=smk.params.seed, resume=True)}")
