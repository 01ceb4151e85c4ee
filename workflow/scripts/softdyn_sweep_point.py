"""One grid point of the T1 sweep (Snakemake script), run through the runner as a batch of
one point (the layout of a batch file)."""

import numba

from craquelure.scene import load_scene
from craquelure.softdyn.api import run

sm = snakemake  # noqa: F821
numba.set_num_threads(sm.threads)
run(load_scene(sm.input.scene, sm.params.overrides), sm.output[0], seed=None,
    batch=[(int(sm.wildcards.i), int(sm.wildcards.j))], resume=True)
