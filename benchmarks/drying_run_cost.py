"""What finished drying runs cost, measured: per scene (fracture criterion) and pair kernel, the
CPU seconds of a run (its rule's Snakemake benchmark file), the engine's own counts (steps, rate
evaluations), the CPU of labelling its snapshots and of its mass solve, and what a 100-seed
campaign of that scene costs on this machine.

A benchmark file times the last job of a run only, so a run resumed from a checkpoint
(``run_resumed_at_step`` > 0) adds its counts but not its CPU. Runs made before the cluster pair
kernel (commit 2b0c038) are rows of their own.

    python benchmarks/drying_run_cost.py [--scenes SCENE ...] [--write PATH]
"""

from __future__ import annotations

import argparse
import subprocess
from collections import defaultdict
from pathlib import Path

import numpy as np
import xarray as xr

from craquelure.archive import benchmark_cpu_seconds

ROOT = Path(__file__).resolve().parent.parent
CLUSTER_KERNEL = "2b0c038"
CAMPAIGN_SEEDS = 100


def cpu_time(rule: str, scene: str, seed: str) -> float | None:
    return benchmark_cpu_seconds(ROOT / "benchmarks" / "results" / rule / scene / f"{seed}.tsv")


def kernel(commit: str) -> str:
    commit = commit.removesuffix("-dirty")  # a run from a checkout with uncommitted edits
    after = subprocess.run(["git", "merge-base", "--is-ancestor", CLUSTER_KERNEL, commit],
                           cwd=ROOT, capture_output=True).returncode == 0
    return "cluster" if after else "gather"


def spread(values: list[float], fmt: str = "{:.0f}") -> str:
    if not values:
        return "-"
    v = np.asarray(values)
    return f"{fmt.format(np.median(v))} ({fmt.format(v.min())}-{fmt.format(v.max())})"


def rows(scenes: list[str]) -> list[dict]:
    groups: dict[tuple[str, str, str], dict[str, list[float]]] = defaultdict(
        lambda: defaultdict(list))
    for scene in scenes:
        for path in sorted((ROOT / "results" / "drying" / scene / "run").glob("seed*.nc")):
            with xr.open_dataset(path) as ds:
                a = dict(ds.attrs)
            g = groups[(scene, str(a["fracture_stress_measure"]), kernel(str(a["git_commit"])))]
            g["steps"].append(int(a["steps"]))
            g["evaluations"].append(int(a["rate_evaluations"]))
            run = cpu_time("drying_run", scene, path.stem)
            if run is not None and not int(a.get("run_resumed_at_step", 0)):
                g["run"].append(run)
            for rule in ("drying_fragments", "mass_consistency"):
                cost = cpu_time(rule, scene, path.stem)
                if cost is not None:
                    g[rule].append(cost)
    out = []
    for (scene, measure, kern), g in sorted(groups.items()):
        per_seed = sum(float(np.median(g[k])) for k in ("run", "drying_fragments",
                                                         "mass_consistency") if g[k])
        out.append({"scene": scene, "measure": measure, "kernel": kern, **g,
                    "campaign_core_hours": CAMPAIGN_SEEDS * per_seed / 3600.0})
    return out


def table(found: list[dict]) -> str:
    lines = ["| scene | criterion | pair kernel | runs (CPU timed) | run CPU-s, median (range) | "
             "steps | rate evaluations | labelling CPU-s per run | 100 seeds, core-hours |",
             "|---|---|---|---|---|---|---|---|---|"]
    for r in found:
        lines.append(
            f"| `{r['scene']}` | {r['measure']} | {r['kernel']} | {len(r['steps'])} "
            f"({len(r['run'])}) | {spread(r['run'])} | {spread(r['steps'])} | "
            f"{spread(r['evaluations'])} | {spread(r['drying_fragments'], '{:.1f}')} | "
            f"{r['campaign_core_hours']:.1f} |")
    lines += ["", "CPU seconds from the rules' Snakemake benchmark files (one numba thread per "
              "run, two runs at a time on a shared 2-core machine); steps and evaluations are the "
              "engine's counts; a campaign is its runs, labelling and mass solves at the medians "
              "(half the core-hours on two cores). Written by `benchmarks/drying_run_cost.py`."]
    return "\n".join(lines) + "\n"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenes", nargs="+", default=["table1_trace", "table1_rkc2",
                                                         "paper_speed", "paper_speed_Ctrace"])
    parser.add_argument("--write", type=Path, help="also write the Markdown table here")
    args = parser.parse_args()
    text = table(rows(args.scenes))
    print(text)
    if args.write:
        args.write.write_text(text)


if __name__ == "__main__":
    main()
