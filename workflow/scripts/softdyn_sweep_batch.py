"""One batch of T1 sweep points, run serially in one process (Snakemake script) through the
runner (a process start (imports, kernel cache load) costs more than most points). A batch
beyond the number of grid points writes an empty batch."""

import numba

from craquelure.scene import load_scene
from craquelure.softdyn.api import run
from craquelure.softdyn.studies import sweep_batches

sm = snakemake  # noqa: F821
numba.set_num_threads(sm.threads)
scene = load_scene(sm.input.scene, sm.params.overrides)
batches = sweep_batches(scene, sm.params.n_batches)
points = batches[int(sm.wildcards.b)] if int(sm.wildcards.b) < len(batches) else []
run(scene, sm.output[0], seed=None, batch=points, resume=True,
    attrs={"batch": f"{int(sm.wildcards.b)} of {sm.params.n_batches}"})
