"""Regime map of the homogeneous disc (issue 16 item 5): where does it split once and where does
it fan out, over tensile strength f_t, contact stiffness (penalty scale a) and impact speed?

Each run is a short homogeneous 2D run of the campaign's scene (``impact.regime`` config
section: f_t values, ``numerics.contact_a`` values, speeds, end time). A run is classified by
the revised check-12 main cracks (:func:`craquelure.impact.measure.revised_cracks`: cracked
clusters from the contact zone reaching >= 0.5 D): ``splits once`` (one main crack), ``fans
out`` (two or more) or ``no main crack``; the centre-row crossings of all cracks are given too.
"""

from __future__ import annotations

from pathlib import Path

from craquelure.io import open_dataset

CLASSES = ("no main crack", "splits once", "fans out")


def classify(n_main: int) -> str:
    return CLASSES[min(int(n_main), 2)]


def regime_row(path: Path) -> dict:
    from craquelure.impact.analysis import run_metrics

    ds = open_dataset(path)
    m = run_metrics(ds)  # the current measurement code, from the final fields
    n_main = int(m["n_main_cracks_revised"])
    x_mid = m["main_crack_x_mid"]
    return {"f_t": float(m["f_t"]), "contact_a": float(m["contact_a"]),
            "impact_velocity": float(m["impact_velocity"]),
            "t_end": float(ds["time"].values[-1]), "n_main_cracks": n_main,
            "main_crossings_x_mm": m["main_crossings_x_mm"],
            "main_crack_x_mid_mm": None if x_mid is None else 1e3 * x_mid,
            "centre_crossings": int(m["centre_crossings"]),
            "cracked_fraction": float(m["cracked_fraction"]),
            "crushed_area": float(m["crushed_area"]),
            "energy_balance_error_max": float(m["energy_balance_error_max"]),
            "material_model": str(m.get("material_model") or ""),
            "class": classify(n_main), "path": str(path)}


def figure_regime(rows: list[dict], out: Path, label: str) -> None:
    """One panel per contact scale a: f_t (x) against impact speed (y), marker = class, number
    = main cracks (centre-row crossings in brackets)."""
    import matplotlib.pyplot as plt

    scales = sorted({r["contact_a"] for r in rows})
    fig, axes = plt.subplots(1, len(scales), figsize=(4.6 * len(scales), 4.2), squeeze=False)
    style = {"no main crack": ("s", "0.75"), "splits once": ("o", "C2"),
             "fans out": ("X", "C3")}
    for ax, a in zip(axes[0], scales, strict=True):
        seen = set()
        for r in (r for r in rows if r["contact_a"] == a):
            marker, color = style[r["class"]]
            ax.scatter(r["f_t"] / 1e6, r["impact_velocity"], marker=marker, color=color, s=160,
                       label=r["class"] if r["class"] not in seen else None)
            seen.add(r["class"])
            ax.annotate(f"{r['n_main_cracks']} ({r['centre_crossings']})",
                        (r["f_t"] / 1e6, r["impact_velocity"]), textcoords="offset points",
                        xytext=(9, -3), fontsize=7)
        ax.set_xlabel("tensile strength f_t [MPa]")
        ax.set_ylabel("impact speed [m/s]")
        ax.set_title(f"penalty scale a = {a:.3g}", fontsize=9)
        ax.margins(0.2)
        low, high = ax.get_ylim()
        ax.set_ylim(low, high + 0.3 * (high - low))  # room for the legend above the points
        ax.legend(fontsize=7, loc="upper center", ncol=3)
    t_end = max(r["t_end"] for r in rows)
    fig.suptitle(f"homogeneous disc at {t_end * 1e6:.0f} us: main cracks from the contact zone "
                 f"(centre-row crossings)\n{label}", fontsize=8)
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    plt.close(fig)
