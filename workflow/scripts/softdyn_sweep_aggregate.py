"""Aggregate the T1 sweep points into one dataset with dims (h0, force) and draw Fig. 5."""

from craquelure.io import open_dataset, write_dataset
from craquelure.provenance import WallClock, provenance_attrs
from craquelure.scene import load_scene
from craquelure.softdyn.figures import fig5
from craquelure.softdyn.studies import aggregate_sweep

sm = snakemake  # noqa: F821
clock = WallClock()
scene = load_scene(sm.input.scene, sm.params.overrides)
ds = aggregate_sweep(scene, [open_dataset(p) for p in sm.input.points])
ds.attrs.update(provenance_attrs(scene, None, clock))
write_dataset(ds, sm.output.data)
fig5(ds, sm.output.figure, sm.config["profile"], scene.name)
