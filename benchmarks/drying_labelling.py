"""Fragment labelling of one drying snapshot: the Shepard field summed at every mesh point (the
binarisation up to commit 4db0bf1, kept as the reference in tests/drying/field_reference.py)
against the block-classified image of ``craquelure.drying.field.mesh_image``, side by side in
one process, and what a coarser mesh would cost and change.

For each mesh spacing (0.01 h, the source's, then 0.02, 0.05 and 0.1 h) it prints the CPU
seconds per snapshot (binarisation and periodic labelling, one thread) of both algorithms,
whether their images are identical bit for bit, and the fragments of the new image: count and
mean area, and their change against the 0.01 h mesh. Writes the table as Markdown and JSON
(``--out``, default ``benchmarks/tables/drying_labelling``; docs/performance.md includes the
Markdown).

    python benchmarks/drying_labelling.py [RUN.nc] [--time-index -1] [--out PREFIX]

Without RUN: a synthetic Table I-size snapshot (L = 10, N = 4e4 jittered lattice, h = 0.2,
particles removed along lines that cross the periodic edges).
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numba
import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))  # the reference routine lives in tests/

from craquelure.drying.analysis import run_scene  # noqa: E402
from craquelure.drying.binarise import fragment_areas, label_periodic  # noqa: E402
from craquelure.drying.field import mesh_image, mesh_spacing  # noqa: E402
from craquelure.io import open_dataset  # noqa: E402
from tests.drying.field_reference import mesh_field as reference_field  # noqa: E402

SPACINGS_H = (0.01, 0.02, 0.05, 0.1)
SNAPSHOTS_PER_RUN = 22


def synthetic_snapshot(seed: int = 1):
    """(x, y, volume, alive, box_length, h, phi0, kernel, description)."""
    rng = np.random.default_rng(seed)
    length, n_side, h = 10.0, 200, 0.2
    g = (np.arange(n_side) + 0.5) * length / n_side
    x, y = (a.ravel() + rng.uniform(-0.01, 0.01, n_side**2) for a in np.meshgrid(g, g))
    volume = (length / n_side) ** 2 * rng.uniform(0.97, 1.03, x.size)
    alive = np.ones(x.size, bool)
    for slope, offset in ((0.3, 2.0), (-1.7, 4.0), (5.0, 1.0)):
        alive &= np.abs(np.mod(y - slope * x - offset, length) - length / 2) > 0.06
    alive &= np.minimum(x, length - x) > 0.05
    return x, y, volume, alive, length, h, 0.8, "quintic", "synthetic (lines removed)"


def run_snapshot(path: Path, index: int):
    run = open_dataset(path)
    snap = run.isel(time=index)
    alive = snap["alive"].values.astype(bool)
    volume = snap["mass"].values / snap["rho"].values
    scene = run_scene(run)
    description = (f"{scene.get('description').split(';')[0]}, t = {float(snap['time']):g}, "
                   f"{int((~alive).sum())} of {alive.size} particles removed")
    return (snap["x"].values, snap["y"].values, volume, alive, float(run.attrs["box_length"]),
            float(run.attrs["h"]), float(scene.get("outputs.binarisation_threshold")),
            str(scene.get("numerics.kernel")), description)


def old_areas(image: np.ndarray, spacing: float) -> np.ndarray:
    """Fragment areas as up to 4db0bf1: the relabelled image, then its pixel counts."""
    labels, n = label_periodic(image)
    return np.bincount(labels.ravel(), minlength=n + 1)[1:] * float(spacing) ** 2


def measure(x, y, volume, alive, length, h, phi0, kernel):
    value = np.where(alive, volume, 0.0)
    rows = []
    base = None
    for spacing_h in SPACINGS_H:
        spacing = spacing_h * h
        pixel = mesh_spacing(length, spacing)
        start = time.process_time()
        old = reference_field(x, y, value, length, h, spacing, kernel, active=alive) >= phi0
        reference = old_areas(old, pixel)
        t_old = time.process_time() - start
        start = time.process_time()
        new = mesh_image(x, y, value, length, h, spacing, kernel, phi0, active=alive)
        areas = fragment_areas(new, pixel)
        t_new = time.process_time() - start
        row = dict(spacing_h=spacing_h, mesh=int(new.shape[0]), old_cpu_s=t_old,
                   new_cpu_s=t_new, identical=bool(np.array_equal(old, new)),
                   same_areas=bool(np.array_equal(areas, reference)),
                   fragments=int(areas.size), mean_area=float(areas.mean()),
                   paste_area=float(areas.sum()))
        base = base or row
        row["fragments_change"] = row["fragments"] - base["fragments"]
        row["mean_area_change"] = row["mean_area"] / base["mean_area"] - 1.0
        row["paste_area_change"] = row["paste_area"] / base["paste_area"] - 1.0
        rows.append(row)
        print(f"{spacing_h:6.2f} h {row['mesh']:5d}^2  old {row['old_cpu_s']:6.2f} s  new "
              f"{row['new_cpu_s']:6.2f} s  ({row['old_cpu_s'] / row['new_cpu_s']:4.1f}x)  "
              f"identical image {row['identical']}, areas {row['same_areas']}  fragments "
              f"{row['fragments']:4d} ({row['fragments_change']:+d})  mean area "
              f"{row['mean_area']:.5g} ({100 * row['mean_area_change']:+.3f} %)  paste area "
              f"{100 * row['paste_area_change']:+.3f} %", flush=True)
    return rows


def markdown(rows, description: str) -> str:
    lines = [f"Snapshot: {description}. CPU seconds per snapshot, one thread, binarisation and "
             "labelling; old = the field summed at every mesh point (up to 4db0bf1), new = "
             "block-classified; changes against the 0.01 h mesh.", "",
             "| spacing | mesh | old CPU-s | new CPU-s | old/new | same image and areas | "
             "fragments | mean area | mean area change | paste area change |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['spacing_h']:g} h | {r['mesh']}^2 | {r['old_cpu_s']:.2f} | "
                     f"{r['new_cpu_s']:.2f} | {r['old_cpu_s'] / r['new_cpu_s']:.1f} | "
                     f"{'yes' if r['identical'] and r['same_areas'] else 'NO'} | "
                     f"{r['fragments']} ({r['fragments_change']:+d}) | {r['mean_area']:.5g} | "
                     f"{100 * r['mean_area_change']:+.3f} % | "
                     f"{100 * r['paste_area_change']:+.3f} % |")
    per_run = SNAPSHOTS_PER_RUN * rows[0]["new_cpu_s"]
    lines += ["", f"At 0.01 h a {SNAPSHOTS_PER_RUN}-snapshot run costs about {per_run:.0f} CPU-s "
              f"of labelling (old: {SNAPSHOTS_PER_RUN * rows[0]['old_cpu_s']:.0f})."]
    return "\n".join(lines) + "\n"


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run", nargs="?", type=Path, help="run dataset (default: synthetic)")
    parser.add_argument("--time-index", type=int, default=-1)
    parser.add_argument("--out", type=Path, default=ROOT / "benchmarks/tables/drying_labelling")
    args = parser.parse_args(argv)
    numba.set_num_threads(1)
    snapshot = (run_snapshot(args.run, args.time_index) if args.run else synthetic_snapshot())
    *particles, description = snapshot
    x, y, volume, alive, length, h, phi0, kernel = particles
    few = slice(0, 50)  # compile both, and label a whole image once, before timing
    for spacing_h in SPACINGS_H:
        reference_field(x[few], y[few], volume[few], length, h, spacing_h * h, kernel)
        image = mesh_image(x[few], y[few], volume[few], length, h, spacing_h * h, kernel, phi0)
    whole = np.ones((10 * image.shape[0],) * 2, bool)  # the 0.01 h mesh
    old_areas(whole, 1.0)
    fragment_areas(whole, 1.0)
    print(f"snapshot: {description}; phi0 {phi0}, h {h}, kernel {kernel}")
    rows = measure(x, y, volume, alive, length, h, phi0, kernel)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.with_suffix(".json").write_text(json.dumps(
        dict(snapshot=description, phi0=phi0, h=h, kernel=kernel, rows=rows), indent=1) + "\n")
    args.out.with_suffix(".md").write_text(markdown(rows, description))
    print(f"wrote {args.out.with_suffix('.md')} and .json")


if __name__ == "__main__":
    main()
