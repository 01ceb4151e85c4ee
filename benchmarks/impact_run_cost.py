"""What finished impact runs cost, measured: per scene and kappa (the campaign's runs under
``results/impact/<scene>/``, the static-strength sensitivity's under
``results/impact/strength/<scene>/``), the number of runs, the CPU seconds of a run (its
rule's Snakemake benchmark file), the steps the engine took and the CPU hours of all of them.

A benchmark file times the last job of a run only, so a run resumed from a checkpoint
(``run_resumed_at_step`` > 0) is counted without CPU.

    python benchmarks/impact_run_cost.py [--write PATH]
"""

from __future__ import annotations

import argparse
from collections import defaultdict
from pathlib import Path

import numpy as np
import xarray as xr

from craquelure.archive import benchmark_cpu_seconds

ROOT = Path(__file__).resolve().parent.parent
RESULTS = ROOT / "results" / "impact"


def benchmark_of(run: Path) -> Path:
    """The Snakemake benchmark file of a run (rule impact_run or impact_strength_run)."""
    rel = run.relative_to(RESULTS).with_suffix(".tsv")
    if rel.parts[0] == "strength":
        return ROOT / "benchmarks/results/impact_strength_run" / Path(*rel.parts[1:])
    return ROOT / "benchmarks/results/impact_run" / rel


def spread(values: list[float]) -> str:
    if not values:
        return "-"
    v = np.asarray(values)
    return f"{np.median(v):.0f} ({v.min():.0f}-{v.max():.0f})"


def rows() -> list[dict]:
    groups: dict[tuple[str, str], dict[str, list]] = defaultdict(lambda: defaultdict(list))
    for run in sorted(RESULTS.rglob("seed*.nc")):
        if "regime" in run.parts:
            continue
        with xr.open_dataset(run) as ds:
            a = dict(ds.attrs)
        sweep = run.relative_to(RESULTS).parts[0] == "strength"
        overrides = dict(o.split("=", 1) for o in str(a.get("scene_overrides", "")).split()
                         if "=" in o)
        scene = f"`impact/{a['scene_name']}`" + (" (strength sweep)" if sweep else "")
        g = groups[(scene, overrides.get("numerics.kappa", "-"))]
        g["steps"].append(int(a["run_steps"]))
        if int(a.get("run_resumed_at_step", 0)) == 0:
            cpu = benchmark_cpu_seconds(benchmark_of(run))
            if cpu is not None:
                g["cpu"].append(cpu)
    return [{"scene": scene, "kappa": kappa, **g} for (scene, kappa), g in sorted(groups.items())]


def table(found: list[dict]) -> str:
    lines = ["| scene | kappa | runs | CPU-s per run, median (range) | steps, median | "
             "CPU-hours |", "|---|---|---|---|---|---|"]
    total = 0.0
    for r in found:
        hours = sum(r["cpu"]) / 3600
        total += hours
        timed = "" if len(r["cpu"]) == len(r["steps"]) else f" ({len(r['cpu'])} timed)"
        lines.append(f"| {r['scene']} | {r['kappa']} | {len(r['steps'])}{timed} | "
                     f"{spread(r['cpu'])} | {np.median(r['steps']):.0f} | {hours:.2f} |")
    lines += ["", f"All runs: {sum(len(r['steps']) for r in found)}, {total:.2f} CPU-hours. "
              "Written by `benchmarks/impact_run_cost.py` from the runs' datasets and the "
              "rules' benchmark files.", ""]
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--write", type=Path, help="also write the table to this file")
    args = parser.parse_args()
    text = table(rows())
    print(text)
    if args.write:
        args.write.write_text(text)


if __name__ == "__main__":
    main()
