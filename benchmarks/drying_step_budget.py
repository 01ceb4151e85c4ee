"""Where an rkc2 drying run spends its rate evaluations (issue 28, item 3), from finished run
datasets: the counts are the engine's own (``rate_evaluations``, ``spectral_radius_evaluations``,
``steps``, ``rejected_steps``), so the figures do not depend on the machine's load.

Per run the step series (``time_step`` every ``series_every`` steps) splits the simulated time
into the part at the step cap ``dt_max`` (the recorded step equals the cap: between cracks) and
the rest (cracks running: the error control and the removal-event limit set the step). At the
cap a step of s stages costs s evaluations (s - 1 stages and the end rate), so that part costs
``s(dt_max) / dt_max`` evaluations per time unit (s from the run's scene and its mean power-
iteration spectral radius is not stored: the stage count at the cap is given, ``--cap-stages``,
8 for the Table I paste); what is left of the run's evaluations went to the cracks, printed per
time unit off the cap and per removed particle. Prints one row per group of runs (min-max over
its seeds) and the evaluations a run would need at the target per time unit.

    python benchmarks/drying_step_budget.py RUN.nc [RUN.nc ...] [--cap-stages 8] [--target 25]
"""

from __future__ import annotations

import argparse
from collections import defaultdict
from pathlib import Path

import numpy as np
import xarray as xr


def budget(path: Path, cap_stages: int) -> dict:
    ds = xr.open_dataset(path)
    from craquelure.scene import stored_scene

    scene = stored_scene(str(ds.attrs["scene"]))
    dt_max = float(scene.get("numerics.step_control.dt_max"))
    t_end = float(ds.attrs["run_simulated_time"])
    times, steps = ds["step_time"].values, ds["time_step"].values
    span = np.diff(times)
    at_cap = steps[1:] >= dt_max * (1 - 1e-6)
    t_cap = float(span[at_cap].sum())
    evals = int(ds.attrs["rate_evaluations"])
    power = int(ds.attrs["spectral_radius_evaluations"])
    cap_evals = cap_stages / dt_max * t_cap
    removed = int(ds.sizes["particle"] - ds["alive"].values[-1].sum())
    crack_evals = evals - power - cap_evals
    return dict(
        group=f"{path.parent.parent.name} (N = {ds.sizes['particle']})",
        per_time=evals / t_end, t_cap=t_cap, t_end=t_end, cap_share=cap_evals / evals,
        crack_per_time=crack_evals / max(t_end - t_cap, 1e-12),
        crack_per_removed=crack_evals / max(removed, 1), removed=removed,
        rejected=int(ds.attrs["rejected_steps"]) / int(ds.attrs["steps"]),
        crack_evals=crack_evals)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("runs", nargs="+", type=Path)
    ap.add_argument("--cap-stages", type=int, default=8)
    ap.add_argument("--target", type=float, default=25.0)
    args = ap.parse_args()
    groups = defaultdict(list)
    for path in args.runs:
        row = budget(path, args.cap_stages)
        groups[row["group"]].append(row)

    def span(rows, key, fmt="{:.1f}"):
        values = [r[key] for r in rows]
        return f"{fmt.format(min(values))}-{fmt.format(max(values))}"

    for group, rows in groups.items():
        t_end = rows[0]["t_end"]
        print(f"{group}: {len(rows)} runs")
        print(f"  evaluations per time unit        {span(rows, 'per_time')}")
        print(f"  time at the step cap             {span(rows, 't_cap', '{:.0f}')} of "
              f"{t_end:.0f}; its share of the evaluations {span(rows, 'cap_share', '{:.2f}')}")
        print(f"  off the cap: per time unit       {span(rows, 'crack_per_time', '{:.0f}')}; "
              f"per removed particle {span(rows, 'crack_per_removed')} "
              f"({span(rows, 'removed', '{:.0f}')} removed)")
        print(f"  rejected steps / steps           {span(rows, 'rejected', '{:.2f}')}")
        print(f"  target {args.target:g} per time unit = {args.target * t_end:.0f} evaluations a "
              f"run; off the cap alone {span(rows, 'crack_evals', '{:.0f}')}")


if __name__ == "__main__":
    main()
