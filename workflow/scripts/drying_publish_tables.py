"""Snakemake script of rule drying_publish_tables: a finished drying ensemble as the compact
tables of its archived result (craquelure.drying.published), the first seed's snapshots that
Fig. 2 draws, and its provenance: scene, criterion, box size, seeds, the measured cost (the
rules' benchmark files) and the companion ensembles shown beside it (config
drying.companions).

Outside Snakemake: ``python workflow/scripts/drying_publish_tables.py OUTDIR RUN.nc FRAG1.nc ...``.
"""

import json
import sys
from pathlib import Path

import numpy as np

from craquelure.archive import benchmark_cpu_seconds
from craquelure.drying.published import write_tables
from craquelure.io import open_dataset, write_dataset, write_text_atomic
from craquelure.provenance import git_commit

# Fig. 2's panels: four snapshots evenly spaced over the run's second half.
SNAPSHOT_PANELS = 4
SNAPSHOT_VARIABLES = ("x", "y", "alive", "mean_stress")


def cpu_seconds(paths: list[str]) -> dict[str, float]:
    """CPU seconds of each Snakemake benchmark file that exists (the jobs' measured cost)."""
    return {Path(p).stem: cpu for p in paths if (cpu := benchmark_cpu_seconds(p)) is not None}


def main(outdir: str, run: str, fragments: list[str], benchmarks: dict[str, list[str]],
         profile: str = "", companions: list[str] = ()) -> None:
    out = Path(outdir)
    datasets = [open_dataset(p) for p in fragments]
    write_tables(datasets, out)
    ds = open_dataset(run)
    times = ds["time"].values
    picks = np.unique(np.linspace(times.size // 2, times.size - 1, SNAPSHOT_PANELS).astype(int))
    snap = ds[list(SNAPSHOT_VARIABLES)].isel(time=picks)
    snap = snap.assign({name: snap[name].astype(np.float32) for name in ("x", "y", "mean_stress")})
    snap.attrs = dict(ds.attrs)
    write_dataset(snap, out / "snapshots.nc")
    costs = {kind: cpu_seconds(paths) for kind, paths in benchmarks.items()}
    first = datasets[0].attrs
    provenance = {
        "profile": profile,
        "git_commit": git_commit(),
        "run_git_commits": sorted({str(d.attrs.get("run_git_commit", "")) for d in datasets}),
        "scene": out.parent.name,  # results/drying/<scene>/: a criterion run's folder
        "scene_name": str(first.get("scene_name", "")),
        "fracture_stress_measure": str(first.get("fracture_stress_measure", "")),
        "box_length": float(first["box_length"]),
        "n_particles": int(first["n_particles"]),
        "seeds": [int(d.attrs["seed"]) for d in datasets],
        "snapshot_run": {"seed": int(ds.attrs.get("seed", -1)),
                         "times": [float(t) for t in times[picks]]},
        "cpu_seconds": costs,
        "cpu_hours_total": sum(sum(c.values()) for c in costs.values()) / 3600.0,
        **({"companions": list(companions)} if companions else {}),
    }
    write_text_atomic(out / "provenance.json", json.dumps(provenance, indent=1) + "\n")
    print(f"wrote {out}: {len(datasets)} seeds, {provenance['cpu_hours_total']:.2f} CPU-hours")


if "snakemake" in globals():
    with open(snakemake.log[0], "w") as log:  # noqa: F821
        sys.stdout = sys.stderr = log
        main(snakemake.output[0], snakemake.input.run, list(snakemake.input.fragments),  # noqa: F821
             {kind: list(paths) for kind, paths in snakemake.params.benchmarks.items()},  # noqa: F821
             snakemake.params.profile, snakemake.params.companions)  # noqa: F821
elif __name__ == "__main__":
    main(sys.argv[1], sys.argv[2], sys.argv[3:], {})
