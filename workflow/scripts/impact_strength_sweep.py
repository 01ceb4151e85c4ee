"""Static-strength sensitivity of the 3D disc (config impact.strength_sweep): measure each run,
write strength_sweep.json and the opening-map figure."""

import json
import sys
from pathlib import Path

from craquelure.impact.analysis import run_metrics
from craquelure.impact.figures import MAP_DPI, _opening_panel, _wrapped
from craquelure.impact.regime import MAIN_CRACKS
from craquelure.io import open_dataset, write_text_atomic
from craquelure.plotting import plt, save
from craquelure.scene import load_scene


def strength_row(path: Path, base_f_t: float) -> dict:
    """One run of the static-strength sensitivity (``impact.strength_sweep``): its f_t factor
    over ``base_f_t`` (the scene's), specimen, main cracks by opening and where they cross the
    centre row (a run of k opened gaps counts ceil(k/2): one wide band counts many), the main
    run's share and the strength-to-load ratio."""
    ds = open_dataset(path)
    m = run_metrics(ds)
    return {"factor": round(float(m["f_t"]) / base_f_t, 6),
            "masses": str(m["distribution"]),
            "seed": int(ds.attrs.get("seed", 0)), "n_main_cracks": int(m[MAIN_CRACKS]),
            "main_runs_x_mm": m["row_runs_x_mm"], "row_runs_cracks": m["row_runs_cracks"],
            "row_runs_opening_mm": m["row_runs_opening_mm"], "main_run_share": m["main_run_share"],
            "strength_to_load": float(ds["strength_to_load"]),
            "energy_balance_error_max": float(m["energy_balance_error_max"]),
            "path": str(path)}


def figure_strength_sweep(rows: list[dict], out: Path, label: str) -> None:
    """Opening maps of the static-strength sensitivity: one row per f_t factor, one panel per
    specimen (homogeneous, then the seeds), titled with N_main by opening and the
    strength-to-load ratio; ``rows`` as :func:`strength_row`."""
    factors = sorted({r["factor"] for r in rows})
    keys = sorted({(r["masses"] != "homogeneous", r["seed"]) for r in rows})
    fig, axes = plt.subplots(len(factors), len(keys),
                             figsize=(2.4 * len(keys) + 1.0, 2.6 * len(factors) + 0.8),
                             squeeze=False, layout="constrained")
    sc = None
    for r in rows:
        ax = axes[factors.index(r["factor"]), keys.index((r["masses"] != "homogeneous",
                                                         r["seed"]))]
        sc = _opening_panel(ax, open_dataset(r["path"]))
        runs = len([k for k in r["row_runs_cracks"].split(",") if k])
        ax.set_title(f"f_t x{r['factor']:g}, {r['masses']} seed {r['seed']}, F/F_s = "
                     f"{r['strength_to_load']:.2f}\nN = {r['n_main_cracks']} in {runs} "
                     f"row run{'s' * (runs != 1)}", fontsize=6)
    if sc is not None:
        fig.colorbar(sc, ax=axes, shrink=0.6, label="largest pair opening [mm]")
    fig.suptitle(_wrapped(f"static f_t sensitivity, opening maps at the end (3D mid-layer); "
                          f"{label}", len(keys)), fontsize=8)
    save(fig, out, dpi=MAP_DPI, tight=False)


if "snakemake" in globals():
    smk = snakemake  # noqa: F821
    sys.stderr = sys.stdout = open(smk.log[0], "w")  # noqa: SIM115
    sweep = smk.config["impact"]["strength_sweep"]
    base = load_scene(f"impact/{sweep['scene']}").get("material.f_t")
    rows = sorted((strength_row(Path(p), base) for p in smk.input),
                  key=lambda r: (r["factor"], r["masses"] != "homogeneous", r["seed"]))
    write_text_atomic(Path(smk.output.json), json.dumps(
        {"profile": smk.params.profile, "kind": "sensitivity (not judged)", **sweep,
         "base_f_t": base, "runs": rows}, indent=2) + "\n")
    figure_strength_sweep(rows, Path(smk.output.png),
                          f"profile {smk.params.profile}, scene impact/{sweep['scene']}")
    for r in rows:
        print(f"f_t x{r['factor']:g} {r['masses']} seed {r['seed']}: {r['n_main_cracks']} main "
              f"(x = {r['main_runs_x_mm']} mm), F/F_s = {r['strength_to_load']:.2f}")
