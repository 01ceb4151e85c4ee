"""One batch of T1 sweep points, run serially in one process (Snakemake script): a process
start (imports, kernel cache load) costs more than most points."""

import numba

from craquelure.io import write_dataset
from craquelure.provenance import WallClock, provenance_attrs
from craquelure.scene import load_scene
from craquelure.softdyn.studies import run_sweep_batch, sweep_batches

sm = snakemake  # noqa: F821
numba.set_num_threads(sm.threads)
clock = WallClock()
scene = load_scene(sm.input.scene, sm.params.overrides)
points = sweep_batches(scene, sm.params.n_batches)[int(sm.wildcards.b)]
ds = run_sweep_batch(scene, points)
ds.attrs.update(provenance_attrs(scene, None, clock))
ds.attrs["batch"] = f"{int(sm.wildcards.b)} of {sm.params.n_batches}"
write_dataset(ds, sm.output[0])
