"""One grid point of the T1 sweep (Snakemake script)."""

from craquelure.io import write_dataset
from craquelure.provenance import WallClock, provenance_attrs
from craquelure.scene import load_scene
from craquelure.softdyn.studies import run_sweep_point

sm = snakemake  # noqa: F821
clock = WallClock()
scene = load_scene(sm.input.scene, sm.params.overrides)
ds = run_sweep_point(scene, int(sm.wildcards.i), int(sm.wildcards.j))
ds.attrs.update(provenance_attrs(scene, None, clock))
write_dataset(ds, sm.output[0])
