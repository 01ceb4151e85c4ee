"""An independent check of the crack count by opening (issue 39): the project's main-crack
count (craquelure.impact.analysis.run_metrics, ``n_main_cracks_opening``) of a run beside a
count made here from the dataset alone, without the project's measurement code: on the
mid-thickness layer (3D; the lower layer nearest z = 0) take the grid row nearest the disc
centre height (the lower one on a tie), sort its massive particles by reference x, and count
the runs of consecutive gaps that opened by more than ``--threshold`` (0.2 mm by default;
crushed pairs included); a run of k opened gaps counts ceil(k/2) cracks, as a crack band
opening over two gaps is one crack.

The independent count is compared with the project's main-crack count; with ``--threshold w_c``
(the project's own threshold) it is compared with the project's count over all the centre row's
runs, main cracks or not, which it must equal. With several runs the output ends with a tally
per threshold (``--tally FILE.json`` writes it as rows).

    .venv/bin/python benchmarks/impact_opening_count.py RUN.nc [RUN.nc ...]
        [--threshold 2e-4 | w_c ...] [--brief] [--out FILE] [--tally FILE.json]
"""

import argparse
import json
import math
from collections import Counter
from pathlib import Path

import numpy as np

from craquelure.impact.analysis import run_metrics
from craquelure.io import open_dataset


def independent_count(ds, threshold: float) -> tuple[int, list[tuple[float, float]]]:
    """(cracks, [(x of the run's middle [mm], summed opening [mm])]) along the centre row."""
    dx = float(ds.attrs["spacing"])
    keep = ds["mass"].values > 0
    if "z0" in ds:
        z0 = ds["z0"].values
        layers = np.unique(np.round(z0 / dx, 6))
        mid = layers[np.argmin(np.abs(layers) + 1e-9 * (layers > 0))]
        keep &= np.isclose(z0 / dx, mid)
    y0 = ds["y0"].values
    centre = float(ds.attrs["centre_y"])
    rows = np.unique(np.round(y0[keep] / dx, 6))
    row = rows[np.argmin(np.abs(rows - centre / dx) + 1e-9 * (rows > centre / dx))]
    idx = np.flatnonzero(keep & np.isclose(y0 / dx, row))
    idx = idx[np.argsort(ds["x0"].values[idx])]
    x0, x, y = ds["x0"].values, ds["x"].values, ds["y"].values
    gap = (np.hypot(np.diff(x[idx]), np.diff(y[idx])) - np.diff(x0[idx]))
    where = 0.5 * (x0[idx][1:] + x0[idx][:-1])
    opened = gap > threshold
    runs, cracks, k = [], 0, 0
    while k < opened.size:
        if opened[k]:
            end = k
            while end + 1 < opened.size and opened[end + 1]:
                end += 1
            cracks += math.ceil((end - k + 1) / 2)
            runs.append((1e3 * where[k:end + 1].mean(), 1e3 * gap[k:end + 1].sum()))
            k = end + 1
        else:
            k += 1
    return cracks, runs


def report(path: Path, threshold: str, brief: bool = False) -> tuple[list[str], int, int, str]:
    """The lines comparing one run's counts (one line if ``brief``), the independent count, the
    project's count it is compared with, and which count that is."""
    ds = open_dataset(path)
    m = run_metrics(ds)
    cut = m["opening_w_c"] if threshold == "w_c" else float(threshold)
    n, runs = independent_count(ds, cut)
    row_total = sum(int(k) for k in m["row_runs_cracks"].split(",") if k)
    # at w_c the centre row is the project's own measure; at another threshold the main count
    # is what the independent count stands in for
    against, what = ((row_total, "centre-row count") if threshold == "w_c"
                     else (m["n_main_cracks_opening"], "main-crack count"))
    agree = n == against
    if brief:
        return [f"{path}: project {m['n_main_cracks_opening']} main cracks, {row_total} in the "
                f"centre row's runs; independent {n} (> {1e3 * cut:.4g} mm); agree {agree}"], \
            n, against, what
    lines = [f"run {path} (scene impact/{ds.attrs.get('scene_name')}, seed "
             f"{ds.attrs.get('seed')}, kappa {m['kappa']:g}, {ds.attrs.get('material_model')}, "
             f"commit {str(ds.attrs.get('git_commit', ''))[:7]}, t_end "
             f"{1e3 * float(ds['time'].values[-1]):g} ms)",
             f"project: {m['n_main_cracks_opening']} main cracks by opening (w_c = "
             f"{1e3 * m['opening_w_c']:.4f} mm), centre-row runs at x = "
             f"{m['row_runs_x_mm'] or 'none'} mm, openings "
             f"{m['row_runs_opening_mm'] or 'none'} mm, "
             f"{row_total} cracks in all the row's runs",
             f"independent: {n} cracks opened > {1e3 * cut:.4g} mm along the "
             f"mid-layer centre row: " + (", ".join(f"x = {xm:.0f} mm ({w:.3f} mm)"
                                                   for xm, w in runs) or "none"),
             f"agree: {agree} (the independent count against the project's {what})",
             f"largest pair opening of the layer {1e3 * m['max_opening']:.3f} mm, cracked "
             f"fraction {m['cracked_fraction']:.3f}, peak contact force "
             f"{1e-3 * float(ds['series_contact_force'].values.max()):.1f} kN"
             + (f", strength-to-load ratio {float(ds['strength_to_load']):.3f}"
                if "strength_to_load" in ds else "")]
    return lines, n, against, what


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("runs", type=Path, nargs="+")
    ap.add_argument("--threshold", action="append",
                    help="opening threshold [m], or w_c for the project's own (default 2e-4); "
                         "repeat for several")
    ap.add_argument("--brief", action="store_true", help="one line per run")
    ap.add_argument("--out", type=Path, help="also write the lines to this file")
    ap.add_argument("--tally", type=Path, help="write the tally per threshold to this JSON file")
    args = ap.parse_args()
    lines, tally = [], []
    for threshold in args.threshold or ["2e-4"]:
        differences, what = Counter(), ""
        for path in args.runs:
            block, n, against, what = report(path, threshold, args.brief)
            lines += block if args.brief else block + [""]
            differences[n - against] += 1
        tally.append({"threshold": threshold if threshold == "w_c"
                      else f"{1e3 * float(threshold):g} mm",
                      "compared with the project's": what, "runs": len(args.runs),
                      "agree": differences[0],
                      "independent minus project: runs": ", ".join(
                          f"{d:+d}: {k}" for d, k in sorted(differences.items()))})
        if len(args.runs) > 1:
            lines.append(f"threshold {tally[-1]['threshold']}: agree in {differences[0]} of "
                         f"{len(args.runs)} runs; independent minus project: "
                         f"{tally[-1]['independent minus project: runs']}")
    print("\n".join(lines))
    for path, text in ((args.out, "\n".join(lines) + "\n"),
                       (args.tally, json.dumps(tally, indent=1) + "\n")):
        if path:
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_text(text)


if __name__ == "__main__":
    main()
