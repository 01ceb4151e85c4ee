"""Campaign summary and figures of the impact model (spec sections 6-7, check 12).

:func:`summarise` reads the run datasets' ``metric_*`` attributes, groups them by case
(masses, pre-crack, κ), gives per-seed values, medians and spread (min, max, interquartile
range), and evaluates each of the source's qualitative findings as a criterion with the
measured numbers and a verdict, per seed (:mod:`.check12`, check 12 as revised).
:func:`make_figures` draws the report figures.
"""

from __future__ import annotations

import json
import math
from collections import defaultdict
from pathlib import Path

import numpy as np

from craquelure.impact import check12
from craquelure.io import open_dataset

PER_RUN = ("n_main_cracks", "main_crack_angle_deg", "cracked_fraction",
           "cracked_fraction_damage", "crushed_area", "crushed_height", "contact_force_peak",
           "contact_impulse", "contact_duration", "rebound_velocity",
           "energy_balance_error_max", "min_y_final", "precrack_cracked_fraction",
           "precrack_angle_deg", "wall_time_s", "steps", "centre_crossings",
           "centre_crossings_x_mm",
           # revised check 12 (craquelure.impact.check12)
           "n_main_cracks_revised", "main_crossings_x_mm", "main_crack_length_revised",
           "main_crack_theta_deg", "main_crack_x_mid", "second_crack_length",
           "n_secondary_cracks", "cracked_fraction_near_main", "precrack_coverage",
           "precrack_tip_extension_low", "precrack_tip_extension_high",
           "main_cracks_elsewhere",
           # what the comparisons hold fixed, per run
           "spacing", "as_epsilon", "crack_band_width", "contact_a", "material_model")


def _num(v):
    if isinstance(v, np.generic):
        v = v.item()
    if isinstance(v, float) and not math.isfinite(v):
        return None
    return v


def crack_metrics(ds) -> dict:
    """The revised check-12 measurements recomputed from a run dataset's final fields (the
    run's own ``metric_*`` were computed with the measurement code of its day), with the
    thresholds of the run's resolved scene."""
    import yaml

    from craquelure.impact.measure import precrack_following, revised_cracks

    material = yaml.safe_load(ds.attrs["scene"]).get("material", {})
    cracked = material.get("cracked_threshold", 0.9)
    crushed = material.get("crushed_strain", 0.0035)
    field = "damage" if material.get("cracked_measure") == "damage" else "softening"
    x0, y0 = ds["x0"].values, ds["y0"].values
    crack, plastic = ds[field].values, ds["plastic_strain"].values
    precrack = ds["precrack"].values.astype(bool)
    spacing = float(ds.attrs["metric_spacing"])
    centre_y = 0.5 * (y0.min() + y0.max())
    out = revised_cracks(x0, y0, crack, plastic, spacing, centre_y, cracked, crushed)
    if precrack.any():
        out.update(precrack_following(x0, y0, crack, plastic, precrack, spacing, centre_y,
                                      cracked, crushed))
    return out


def read_metrics(path: Path) -> dict:
    ds = open_dataset(path)
    out = {k[len("metric_"):]: _num(v) for k, v in ds.attrs.items() if k.startswith("metric_")}
    out.update({k: _num(v) for k, v in crack_metrics(ds).items()})
    out["wall_time_s"] = _num(ds.attrs.get("wall_time_s"))
    out["seed"] = int(ds.attrs.get("seed", 0))
    out["path"] = str(path)
    return out


def case_key(m: dict) -> str:
    return f"{m['distribution']}/{m['precrack_layout']}/kappa{float(m['kappa']):g}"


def _stats(values):
    vals = np.array([v for v in values if v is not None and not isinstance(v, str)], float)
    if vals.size == 0:
        return None
    q1, med, q3 = np.percentile(vals, [25, 50, 75])
    return {"median": float(med), "min": float(vals.min()), "max": float(vals.max()),
            "iqr": float(q3 - q1), "n": int(vals.size)}


def summarise(paths, profile: str, scene: str, distribution: str) -> dict:
    runs = [read_metrics(Path(p)) for p in paths]
    cases: dict[str, list] = defaultdict(list)
    for m in runs:
        cases[case_key(m)].append(m)
    out_cases = {}
    for key, ms in sorted(cases.items()):
        ms = sorted(ms, key=lambda m: m["seed"])
        out_cases[key] = {
            "seeds": [m["seed"] for m in ms],
            "as_epsilon": ms[0].get("as_epsilon"),
            "contact_a": ms[0].get("contact_a"),
            "per_seed": {q: [m.get(q) for m in ms] for q in PER_RUN},
            "stats": {q: _stats([m.get(q) for m in ms]) for q in PER_RUN
                      if q not in ("precrack_angle_deg",)},
            "fraction_one_main_crack": float(np.mean([m["n_main_cracks"] == 1 for m in ms])),
        }
    findings, reported = check12.evaluate(out_cases, distribution, "2D")
    total_wall = sum(m["wall_time_s"] or 0 for m in runs)
    return {
        "profile": profile, "scene": scene, "n_runs": len(runs),
        "n_seeds_heterogeneous": max((len(c["seeds"]) for k, c in out_cases.items()
                                      if not k.startswith("homogeneous/")), default=0),
        "all_runs_finished": True,
        "max_energy_balance_error": max(abs(m["energy_balance_error_max"]) for m in runs),
        "total_run_wall_time_s": total_wall,
        "material_model": sorted({str(m.get("material_model")) for m in runs}),
        "cases": out_cases, "findings": findings,
        # findings carry their dimension ("dim"); a 3D campaign's sit beside the 2D ones
        "dimensions": ["2D"], "reported_without_verdict": {"2D": reported},
        "notes": ("cracked = softening s >= 0.9 (residual tensile strength <= 0.1 f_t); "
                  "D_t >= 0.9 is reported as cracked_fraction_damage. Main cracks: clusters of "
                  "cracked, not crushed particles (reference distance <= 1.5 Delta) with extent "
                  ">= R; parallel crack bands closer than 1.5 Delta merge into one cluster, "
                  "and cracks joined by a branch or a transverse crack count once: "
                  "centre_crossings (cracked runs along the row at the disc centre height) "
                  "counts them separately and is given with each finding."),
    }


def write_summary(summary: dict, path: Path) -> None:
    from craquelure.io import write_text_atomic

    write_text_atomic(path, json.dumps(summary, indent=2, default=_num) + "\n")


# --- figures ------------------------------------------------------------------------------

def _disc(ax, ds, values, snapshot=-1, cmap="gray_r", vmin=0.0, vmax=1.0, reference=False):
    x = ds["x0"].values if reference else ds["snap_x"].values[snapshot]
    y = ds["y0"].values if reference else ds["snap_y"].values[snapshot]
    size = 9.0 * (0.004 / float(ds.attrs["metric_spacing"])) ** 2 * (1264 / x.size) ** 0.0
    sc = ax.scatter(x * 1e3, y * 1e3, c=values, s=size, cmap=cmap, vmin=vmin, vmax=vmax,
                    linewidths=0)
    ax.set_aspect("equal")
    ax.set_xticks([])
    ax.set_yticks([])
    return sc


def _failed(ds, snapshot=-1):
    """0 intact, 0.5 crushed, 1 cracked (the source's grey/black maps)."""
    crack = ds["snap_softening"].values[snapshot]
    if ds.attrs.get("metric_cracked_measure") == "damage":
        crack = ds["snap_damage"].values[snapshot]
    crushed = ds["snap_plastic_strain"].values[snapshot] >= 0.0035
    return np.where(crack >= 0.9, 1.0, np.where(crushed, 0.55, 0.12))


def _title(ds):
    return (f"kappa = {float(ds.attrs['metric_kappa']):g} (eps_AS "
            f"{float(ds.attrs.get('metric_as_epsilon', float('nan'))):g}), "
            f"{ds.attrs['metric_distribution']}, "
            f"seed {int(ds.attrs.get('seed', 0))}:\nN_mc = {int(ds.attrs['metric_n_main_cracks'])}"
            f", crossings {int(ds.attrs.get('metric_centre_crossings', -1))}"
            f", phi_c = {float(ds.attrs['metric_cracked_fraction']):.2f}")


def figure_masses(run: Path, out: Path, label: str) -> None:
    import matplotlib.pyplot as plt

    ds = open_dataset(run)
    mbar = float(np.mean(ds["mass"].values))
    fig, (a, b) = plt.subplots(1, 2, figsize=(10, 4.4))
    a.hist(ds["mass"].values / mbar, bins=40, color="0.4")
    a.set_xlabel("m_i / mean mass")
    a.set_ylabel("particles")
    a.set_title("mass distribution (Fig. 5)")
    sc = _disc(b, ds, ds["mass"].values * 1e3, cmap="viridis", vmin=0,
               vmax=float(ds["mass"].max()) * 1e3, reference=True)
    fig.colorbar(sc, ax=b, label="mass per metre [g/m]")
    b.set_title("mass map (Fig. 6)")
    fig.suptitle(label, fontsize=9)
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    plt.close(fig)


def figure_damage_grid(runs, out: Path, title: str, label: str) -> None:
    import matplotlib.pyplot as plt

    runs = list(runs)
    cols = len(runs)
    fig, axes = plt.subplots(1, cols, figsize=(3.2 * cols, 3.6), squeeze=False)
    for ax, run in zip(axes[0], runs, strict=True):
        ds = open_dataset(run)
        _disc(ax, ds, _failed(ds))
        ax.set_title(_title(ds), fontsize=7)
    fig.suptitle(f"{title}\n{label}", fontsize=9)
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    plt.close(fig)


def figure_precracks(runs, out: Path, label: str) -> None:
    import matplotlib.pyplot as plt

    runs = list(runs)
    fig, axes = plt.subplots(2, len(runs), figsize=(3.2 * len(runs), 6.6), squeeze=False)
    for c, run in enumerate(runs):
        ds = open_dataset(run)
        _disc(axes[0, c], ds, ds["mass"].values * 1e3, cmap="viridis", vmin=0,
              vmax=float(ds["mass"].max()) * 1e3, reference=True)
        axes[0, c].set_title(f"{ds.attrs['metric_precrack_layout']}: masses", fontsize=8)
        _disc(axes[1, c], ds, _failed(ds))
        fr = ds.attrs.get("metric_precrack_cracked_fraction", float("nan"))
        axes[1, c].set_title(f"failure; {100 * float(fr):.0f} % cracked near the line",
                             fontsize=7)
    fig.suptitle(f"pre-cracks as zero-mass lines (Figs. 11-13)\n{label}", fontsize=9)
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    plt.close(fig)


def figure_contact(runs_by_kappa: dict, out: Path, label: str) -> None:
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.5, 4))
    scales = set()
    for kappa, runs in sorted(runs_by_kappa.items()):
        for i, run in enumerate(runs):
            ds = open_dataset(run)
            scales.add(f"{float(ds.attrs.get('metric_contact_a', float('nan'))):.3g}")
            t = ds["time"].values * 1e6
            f = ds["series_contact_force"].values / 1e6
            style = "-" if ds.attrs["metric_distribution"] == "homogeneous" else ":"
            ax.plot(t, f, style, lw=1.2 if style == "-" else 0.7,
                    color={0.7: "C0", 1.0: "C1", 1.5: "C2"}.get(kappa, "k"),
                    label=f"kappa = {kappa:g} ({ds.attrs['metric_distribution']})"
                    if i < 2 else None)
    ax.set_xlabel("t [us]")
    ax.set_ylabel("contact force [MN/m]")
    ax.legend(fontsize=7)
    ax.set_title(f"{label}\npenalty scale factor a = {', '.join(sorted(scales))}", fontsize=8)
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    plt.close(fig)


def figure_accuracy(rows: list[dict], floors: dict, out: Path, label: str) -> None:
    """Error of the P-wave mode frequency versus CPU time, one curve per kappa (spacing
    annotated), the lattice floor 1 - g(kappa) dashed."""
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.5, 4.2))
    for i, kappa in enumerate(sorted({r["kappa"] for r in rows})):
        sel = sorted((r for r in rows if r["kappa"] == kappa), key=lambda r: -r["spacing"])
        cpu = [max(r["cpu_seconds"], 1e-3) for r in sel]
        err = [r["error"] for r in sel]
        color = f"C{i}"
        ax.loglog(cpu, err, "o-", color=color, label=f"kappa = {kappa:g}")
        for c, e, r in zip(cpu, err, sel, strict=True):
            ax.annotate(f"{r['spacing'] * 1e3:g} mm", (c, e), fontsize=6,
                        textcoords="offset points", xytext=(3, 3))
        ax.axhline(floors[kappa], color=color, ls="--", lw=0.8)
    ax.set_xlabel("CPU time of the run [s] (1 thread)")
    ax.set_ylabel("|omega / (k c_p) - 1|")
    ax.set_title(f"P-wave mode frequency error vs cost; reference: exact omega = k c_p, "
                 f"dashed: lattice floor 1 - g(kappa)\n{label}", fontsize=7)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    plt.close(fig)
