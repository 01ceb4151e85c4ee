"""Snakemake script of rule drying_kappa: the onset study's fixed-F runs -> kappa_max per point
(:func:`craquelure.drying.onset.kappa_study`, with provenance).

Outside Snakemake: ``python workflow/scripts/drying_kappa.py OUT.nc RUN.nc [RUN.nc ...]``
(the point label is the run's folder name).
"""

import sys
from pathlib import Path

from craquelure.drying.analysis import run_scene
from craquelure.drying.onset import kappa_study
from craquelure.io import open_dataset, write_dataset
from craquelure.provenance import WallClock, provenance_attrs


def main(out: str, runs: list[str]) -> None:
    clock = WallClock()
    datasets = [open_dataset(p) for p in runs]
    labels = [f"{Path(p).parent.name}/{Path(p).stem}" for p in runs]
    study = kappa_study(datasets, labels)
    study.attrs.update(provenance_attrs(run_scene(datasets[0]), None, clock,
                                        effects=str(datasets[0].attrs.get("effects", ""))
                                        .split(",")))
    study.attrs["sources"] = ",".join(runs)
    write_dataset(study, out)
    for label, kappa in zip(labels, study["kappa_max"].values, strict=True):
        print(f"{label}: kappa_max = {kappa:.3f} -> first removal {1 / kappa:.3f} t*")


if "snakemake" in globals():
    with open(snakemake.log[0], "w") as log:  # noqa: F821
        sys.stdout = sys.stderr = log
        main(snakemake.output[0], list(snakemake.input))  # noqa: F821
elif __name__ == "__main__":
    main(sys.argv[1], sys.argv[2:])
