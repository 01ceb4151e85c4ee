"""Regime map of the homogeneous disc: where does it split once and where does it fan out, over
tensile strength f_t, contact stiffness (penalty scale a) and impact speed, in 2D and in 3D?

Each run is a short homogeneous run of the campaign's 2D scene (config ``impact.regime``) or of
the 3D disc (``impact.regime.three_d``), measured as every run
(:func:`craquelure.impact.analysis.run_metrics`) and classified by its main cracks counted by
opening, as check 12 counts them: ``splits once`` (one), ``fans out`` (two or more) or ``no
main crack``; the softening clusters' count is a secondary number. The class is also taken at
each field snapshot before the end, so that a row says from when on it no longer changed.
"""

from __future__ import annotations

from itertools import takewhile
from pathlib import Path

from craquelure.io import open_dataset

CLASSES = ("no main crack", "splits once", "fans out")
SNAPSHOT_FIELDS = ("x", "y", "softening", "damage", "plastic_strain")
MAIN_CRACKS = "n_main_cracks_opening"  # the count that classifies (run_metrics' key)


def classify(n_main: int) -> str:
    return CLASSES[min(int(n_main), 2)]


def class_history(ds) -> list[dict]:
    """Main cracks and class at each field snapshot (the last one is the end of the run)."""
    from craquelure.impact.analysis import run_metrics

    out = []
    for i, t in enumerate(ds["snapshot_time"].values):
        at = ds.assign({k: ds[f"snap_{k}"].isel(snapshot_time=i, drop=True)
                        for k in SNAPSHOT_FIELDS})
        n_main = int(run_metrics(at)[MAIN_CRACKS])
        out.append({"t": float(t), "n_main_cracks": n_main, "class": classify(n_main)})
    return out


def settled_from(history: list[dict]) -> float | None:
    """Earliest snapshot time from which on the class stays the final one (None: no snapshot)."""
    final = history[-1]["class"] if history else None
    same = list(takewhile(lambda h: h["class"] == final, reversed(history)))
    return same[-1]["t"] if same else None


def changed_at_end(row: dict) -> bool:
    """Did the class change after the last snapshot (a longer run might classify it otherwise)?"""
    hist = row.get("class_history") or []
    return len(hist) >= 2 and hist[-2]["class"] != hist[-1]["class"]


def regime_row(path: Path) -> dict:
    from craquelure.impact.analysis import run_metrics

    ds = open_dataset(path)
    m = run_metrics(ds)  # the current measurement code, from the final fields
    n_main = int(m[MAIN_CRACKS])
    x_mid = m["main_run_x_mid"]
    history = class_history(ds)
    return {"dim": f"{int(m['dim'])}D", "scene": str(ds.attrs.get("scene_name", "")),
            "f_t": float(m["f_t"]), "contact_a": float(m["contact_a"]),
            "impact_velocity": float(m["impact_velocity"]),
            "t_end": float(ds["time"].values[-1]), "n_main_cracks": n_main,
            "main_runs_x_mm": m["row_runs_x_mm"],
            "main_crack_x_mid_mm": None if x_mid is None else 1e3 * x_mid,
            "main_run_share": m["main_run_share"],
            "centre_crossings": int(m["centre_crossings"]),
            "n_main_cracks_softening": int(m["n_main_cracks_revised"]),
            "cracked_fraction": float(m["cracked_fraction"]),
            "crushed_area": float(m["crushed_area"]),
            "energy_balance_error_max": float(m["energy_balance_error_max"]),
            "material_model": str(m.get("material_model") or ""),
            "strength_to_load": (float(ds["strength_to_load"]) if "strength_to_load" in ds
                                 else None),
            "class": classify(n_main), "class_history": history,
            "class_settled_from": settled_from(history),
            "wall_time_s": ds.attrs.get("wall_time_s"), "path": str(path)}


def regime_maps(rows: list[dict]) -> dict:
    """Per dimension ("2D", then "3D"): scene, end time, number of runs and of each class."""
    out = {}
    for dim in sorted({r["dim"] for r in rows}):
        sub = [r for r in rows if r["dim"] == dim]
        out[dim] = {"scene": sorted({r["scene"] for r in sub}),
                    "t_end": max(r["t_end"] for r in sub), "n_runs": len(sub),
                    "classes": {c: sum(r["class"] == c for r in sub) for c in CLASSES},
                    "settled_from_max": max((r["class_settled_from"] or 0.0) for r in sub),
                    "n_changed_at_end": sum(changed_at_end(r) for r in sub)}
    return out


def _limits(values: list[float], below: float, above: float) -> tuple[float, float]:
    low, high = min(values), max(values)
    span = (high - low) or max(abs(high), 1.0)
    return low - below * span, high + above * span


def figure_regime(rows: list[dict], out: Path, label: str) -> list[str]:
    """One row of panels per dimension, one panel per contact scale a (f_t against speed, marker =
    class, number = main cracks), a last one per row by :func:`ratio_panel`; returns the titles."""
    from craquelure.plotting import plt, save

    maps = regime_maps(rows)
    dims = list(maps)
    scales = {d: sorted({r["contact_a"] for r in rows if r["dim"] == d}) for d in dims}
    ncols = max(len(s) for s in scales.values()) + 1
    fig, axes = plt.subplots(len(dims), ncols, figsize=(4.6 * ncols, 4.2 * len(dims)),
                             squeeze=False)
    style = {"no main crack": ("s", "0.75"), "splits once": ("o", "C2"), "fans out": ("X", "C3")}
    titles = []
    xlim = _limits([r["f_t"] / 1e6 for r in rows], 0.2, 0.2)
    ylim = _limits([r["impact_velocity"] for r in rows], 0.2, 0.5)  # room for the legend
    for row_axes, dim in zip(axes, dims, strict=True):
        info = maps[dim]
        for ax in row_axes[len(scales[dim]):-1]:
            ax.set_visible(False)
        for ax, a in zip(row_axes, scales[dim], strict=False):
            seen = set()
            for r in (r for r in rows if r["dim"] == dim and r["contact_a"] == a):
                marker, color = style[r["class"]]
                ax.scatter(r["f_t"] / 1e6, r["impact_velocity"], marker=marker, color=color,
                           s=160, label=r["class"] if r["class"] not in seen else None)
                seen.add(r["class"])
                ax.annotate(f"{r['n_main_cracks']} ({r['n_main_cracks_softening']})"
                            + ("*" if changed_at_end(r) else ""),
                            (r["f_t"] / 1e6, r["impact_velocity"]), textcoords="offset points",
                            xytext=(9, -3), fontsize=7)
            titles.append(f"{dim}, {'/'.join(info['scene'])}, {info['t_end'] * 1e6:.0f} us: "
                          f"penalty scale a = {a:.3g}")
            ax.set_title(titles[-1], fontsize=9)
            # the same axes in every panel: 2D and 3D compare point by point
            ax.set(xlabel="tensile strength f_t [MPa]", ylabel="impact speed [m/s]", xlim=xlim,
                   ylim=ylim)
            ax.legend(fontsize=7, loc="upper center", ncol=3)
        ratio_panel(row_axes[-1], [r for r in rows if r["dim"] == dim], style)
        titles.append(f"{dim}: class against peak contact force / static splitting load")
        row_axes[-1].set_title(titles[-1], fontsize=9)
    fig.suptitle("homogeneous disc: main cracks by opening (softening clusters' count in "
                 "brackets; * class changed after the last snapshot); 3D on its mid-thickness "
                 "layer\n"
                 f"{label}", fontsize=8)
    save(fig, out)
    return titles


def ratio_panel(ax, rows: list[dict], style: dict) -> None:
    """Class of each run against its strength-to-load ratio (x, log) and speed (y)."""
    rows = [r for r in rows if r.get("strength_to_load")]
    seen = set()
    for r in rows:
        marker, color = style[r["class"]]
        ax.scatter(r["strength_to_load"], r["impact_velocity"], marker=marker, color=color,
                   s=90, label=r["class"] if r["class"] not in seen else None)
        seen.add(r["class"])
        ax.annotate(str(r["n_main_cracks"]), (r["strength_to_load"], r["impact_velocity"]),
                    textcoords="offset points", xytext=(6, 4), fontsize=7)
    if rows:
        ax.set_xscale("log")
        ax.legend(fontsize=7, loc="upper left")
    ax.set(xlabel="peak contact force / static splitting load pi D t f_t / 2",
           ylabel="impact speed [m/s]")

