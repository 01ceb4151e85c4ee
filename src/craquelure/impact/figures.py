"""Report figures of the impact model (spec sections 6-7): mass distribution, damage maps,
pre-crack comparison, contact force and accuracy curves, from the run datasets and their
measurements (:func:`craquelure.impact.analysis.run_metrics`; no simulation here)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from craquelure.impact.analysis import run_fact, run_metrics, run_scene
from craquelure.io import open_dataset
from craquelure.plotting import plt, save


def _disc(ax, ds, values, snapshot=-1, cmap="gray_r", vmin=0.0, vmax=1.0, reference=False):
    x = ds["x0"].values if reference else ds["snap_x"].values[snapshot]
    y = ds["y0"].values if reference else ds["snap_y"].values[snapshot]
    size = 9.0 * (0.004 / float(run_fact(ds, "spacing"))) ** 2
    sc = ax.scatter(x * 1e3, y * 1e3, c=values, s=size, cmap=cmap, vmin=vmin, vmax=vmax,
                    linewidths=0)
    ax.set_aspect("equal")
    ax.set_xticks([])
    ax.set_yticks([])
    return sc


def _failed(ds, snapshot=-1):
    """0 intact, 0.5 crushed, 1 cracked (the source's grey/black maps)."""
    crack = ds["snap_softening"].values[snapshot]
    if run_scene(ds).get("material.cracked_measure", "softening") == "damage":
        crack = ds["snap_damage"].values[snapshot]
    crushed = ds["snap_plastic_strain"].values[snapshot] >= 0.0035
    return np.where(crack >= 0.9, 1.0, np.where(crushed, 0.55, 0.12))


def _title(ds):
    m = run_metrics(ds)
    return (f"kappa = {float(m['kappa']):g} (eps_AS {float(m['as_epsilon']):g}), "
            f"{m['distribution']}, seed {int(ds.attrs.get('seed', 0))}:\n"
            f"N_mc = {int(m['n_main_cracks'])}, crossings {int(m['centre_crossings'])}"
            f", phi_c = {float(m['cracked_fraction']):.2f}")


def figure_masses(run: Path, out: Path, label: str) -> None:
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
    save(fig, out)


def figure_damage_grid(runs, out: Path, title: str, label: str) -> None:
    runs = list(runs)
    cols = len(runs)
    fig, axes = plt.subplots(1, cols, figsize=(3.2 * cols, 3.6), squeeze=False)
    for ax, run in zip(axes[0], runs, strict=True):
        ds = open_dataset(run)
        _disc(ax, ds, _failed(ds))
        ax.set_title(_title(ds), fontsize=7)
    fig.suptitle(f"{title}\n{label}", fontsize=9)
    save(fig, out)


def figure_precracks(runs, out: Path, label: str) -> None:
    runs = list(runs)
    fig, axes = plt.subplots(2, len(runs), figsize=(3.2 * len(runs), 6.6), squeeze=False)
    for c, run in enumerate(runs):
        ds = open_dataset(run)
        _disc(axes[0, c], ds, ds["mass"].values * 1e3, cmap="viridis", vmin=0,
              vmax=float(ds["mass"].max()) * 1e3, reference=True)
        m = run_metrics(ds)
        axes[0, c].set_title(f"{m['precrack_layout']}: masses", fontsize=8)
        _disc(axes[1, c], ds, _failed(ds))
        fr = m.get("precrack_cracked_fraction")
        fr = float("nan") if fr is None else fr
        axes[1, c].set_title(f"failure; {100 * float(fr):.0f} % cracked near the line",
                             fontsize=7)
    fig.suptitle(f"pre-cracks as zero-mass lines (Figs. 11-13)\n{label}", fontsize=9)
    save(fig, out)


def figure_contact(runs_by_kappa: dict, out: Path, label: str) -> None:
    fig, ax = plt.subplots(figsize=(6.5, 4))
    scales = set()
    for kappa, runs in sorted(runs_by_kappa.items()):
        for i, run in enumerate(runs):
            ds = open_dataset(run)
            scales.add(f"{float(run_fact(ds, 'contact_a', float('nan'))):.3g}")
            distribution = run_metrics(ds)["distribution"]
            t = ds["time"].values * 1e6
            f = ds["series_contact_force"].values / 1e6
            style = "-" if distribution == "homogeneous" else ":"
            ax.plot(t, f, style, lw=1.2 if style == "-" else 0.7,
                    color={0.7: "C0", 1.0: "C1", 1.5: "C2"}.get(kappa, "k"),
                    label=f"kappa = {kappa:g} ({distribution})"
                    if i < 2 else None)
    ax.set_xlabel("t [us]")
    ax.set_ylabel("contact force [MN/m]")
    ax.legend(fontsize=7)
    ax.set_title(f"{label}\npenalty scale factor a = {', '.join(sorted(scales))}", fontsize=8)
    save(fig, out)


def figure_accuracy(rows: list[dict], floors: dict, out: Path, label: str) -> None:
    """Error of the P-wave mode frequency versus CPU time, one curve per kappa (spacing
    annotated), the lattice floor 1 - g(kappa) dashed."""
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
    save(fig, out)
