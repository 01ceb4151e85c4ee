"""Snakemake script of rule drying_accuracy: error versus wall time of the drying integrators
(:mod:`craquelure.drying.accuracy`), written as a dataset with provenance.

Outside Snakemake: ``python workflow/scripts/drying_accuracy.py SCENE OUT.nc SEED DT [DT ...]``.
"""

import sys

import numba

from craquelure.drying.accuracy import error_versus_wall_time
from craquelure.io import write_dataset
from craquelure.provenance import WallClock, provenance_attrs
from craquelure.scene import load_scene


def main(scene_ref: str, out: str, seed: int, time_steps: list[float], threads: int = 1) -> None:
    numba.set_num_threads(threads)
    clock = WallClock()
    scene = load_scene(scene_ref)
    study = error_versus_wall_time(scene, seed, time_steps)
    study.attrs.update(provenance_attrs(scene, seed, clock, effects=scene.effects))
    study.attrs["threads"] = threads
    write_dataset(study, out)
    for name in study["integrator"].values:
        row = study.sel(integrator=name)
        print(f"{name}: errors {row['error'].values} wall {row['wall_time'].values} s "
              f"orders {row['observed_order'].values}")


if "snakemake" in globals():
    with open(snakemake.log[0], "w") as log:  # noqa: F821
        sys.stdout = sys.stderr = log
        main(snakemake.input.scene, snakemake.output[0], snakemake.params.seed,  # noqa: F821
             snakemake.params.time_steps, snakemake.threads)  # noqa: F821
elif __name__ == "__main__":
    main(sys.argv[1], sys.argv[2], int(sys.argv[3]), [float(v) for v in sys.argv[4:]])
