"""Integrator error versus wall time on one T1 (Snakemake script): dataset and report figure."""

import numba

from craquelure.io import write_dataset
from craquelure.provenance import WallClock, provenance_attrs
from craquelure.scene import load_scene
from craquelure.softdyn.accuracy import run_accuracy
from craquelure.softdyn.figures import accuracy

sm = snakemake  # noqa: F821
numba.set_num_threads(sm.threads)
clock = WallClock()
scene = load_scene(sm.input.scene, sm.params.overrides)
ds = run_accuracy(scene)
ds.attrs.update(provenance_attrs(scene, None, clock))
write_dataset(ds, sm.output.data)
accuracy(ds, sm.output.figure, sm.config["profile"], scene.name)
