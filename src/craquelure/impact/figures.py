"""Report figures of the impact model (spec sections 6-7): mass distribution, damage maps,
pre-crack comparison, contact force and accuracy curves, from the run datasets and their
measurements (:func:`craquelure.impact.analysis.run_metrics`; no simulation here)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from craquelure.impact.analysis import run_fact, run_metrics, run_scene
from craquelure.io import open_dataset
from craquelure.plotting import plt, save


def _map(ax, x, y, values, size, cmap, vmin, vmax):
    """Particles at (x, y) [m], drawn in mm and coloured by ``values``, on bare equal axes."""
    sc = ax.scatter(x * 1e3, y * 1e3, c=values, s=size, cmap=cmap, vmin=vmin, vmax=vmax,
                    linewidths=0)
    ax.set(aspect="equal", xticks=[], yticks=[])
    return sc


def _disc(ax, ds, values, snapshot=-1, cmap="gray_r", vmin=0.0, vmax=1.0, reference=False):
    x = ds["x0"].values if reference else ds["snap_x"].values[snapshot]
    y = ds["y0"].values if reference else ds["snap_y"].values[snapshot]
    return _map(ax, x, y, values, 9.0 * (0.004 / float(run_fact(ds, "spacing"))) ** 2, cmap,
                vmin, vmax)


def _failed(ds, snapshot=-1):
    """0 intact, 0.5 crushed, 1 cracked (the source's grey/black maps)."""
    crack = ds["snap_softening"].values[snapshot]
    if run_scene(ds).get("material.cracked_measure") == "damage":
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
        axes[1, c].set_title(f"failure; {100 * float(fr):.0f} % cracked near the line", fontsize=7)
    fig.suptitle(f"pre-cracks as zero-mass lines (Figs. 11-13)\n{label}", fontsize=9)
    save(fig, out)


def figure_contact(runs_by_kappa: dict, out: Path, label: str) -> None:
    fig, ax = plt.subplots(figsize=(6.5, 4))
    scales = set()
    for colour, (kappa, runs) in enumerate(sorted(runs_by_kappa.items())):
        for i, run in enumerate(runs):
            ds = open_dataset(run)
            scales.add(f"{float(run_fact(ds, 'contact_a', float('nan'))):.3g}")
            distribution = run_metrics(ds)["distribution"]
            t = ds["time"].values * 1e6
            f = ds["series_contact_force"].values / 1e6
            style = "-" if distribution == "homogeneous" else ":"
            ax.plot(t, f, style, lw=1.2 if style == "-" else 0.7, color=f"C{colour}",
                    label=f"kappa = {kappa:g} ({distribution})" if i < 2 else None)
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


# --- pictures of the judged runs: opening maps, time sequence, energy
# partition, fragment sizes; from the run datasets only ---------------------------------------

def _layer(ds):
    """Index array of the plane (2D) or the mid-thickness layer (3D) the measure uses."""
    from craquelure.impact.measure import mid_slab

    if "z0" in ds:
        return np.flatnonzero(mid_slab(ds["z0"].values, float(run_fact(ds, "spacing"))))
    return np.arange(ds.sizes["particle"])


def _layer_openings(ds, x=None, y=None):
    """(layer indices, the opening measure's pairs of the layer, their openings [m]) at the
    positions ``x``, ``y`` (all particles; default the final ones)."""
    from craquelure.impact.measure import neighbour_pairs, pair_openings

    idx = _layer(ds)
    x0, y0, mass = (ds[k].values[idx] for k in ("x0", "y0", "mass"))
    xs = (ds["x"].values if x is None else x)[idx]
    ys = (ds["y"].values if y is None else y)[idx]
    pairs = neighbour_pairs(x0, y0, mass, float(run_fact(ds, "spacing")))
    return idx, pairs, pair_openings(pairs, x0, y0, xs, ys)


def particle_opening(ds, x=None, y=None) -> tuple[np.ndarray, np.ndarray]:
    """(layer indices, largest opening of each layer particle's pairs [m]) at the positions
    ``x``, ``y`` (all particles; default the final ones), by the opening measure's pairs."""
    idx, pairs, w = _layer_openings(ds, x, y)
    per = np.zeros(idx.size)
    np.maximum.at(per, pairs[:, 0], w)
    np.maximum.at(per, pairs[:, 1], w)
    return idx, per


def fragments(ds) -> np.ndarray:
    """Sizes (particle counts) of the fragments of the layer: massive particles joined by
    pairs that did not open (w <= w_c), largest first."""
    from craquelure.impact.measure import components, full_softening_opening

    scene = run_scene(ds)
    w_c = full_softening_opening(scene.get("material.G_F"), scene.get("material.f_t"))
    idx, pairs, w = _layer_openings(ds)
    _, labels = components(idx.size, pairs[w <= w_c])
    sizes = np.bincount(labels[ds["mass"].values[idx] > 0])
    return np.sort(sizes[sizes > 0])[::-1]


# The opening-map figures hold tens of scatter panels: at the default 120 dpi each was 2-3 MB.
MAP_DPI = 80


def _opening_panel(ax, ds, x=None, y=None, vmax=2.0):
    idx, per = particle_opening(ds, x, y)
    xs = (ds["x"].values if x is None else x)[idx]
    ys = (ds["y"].values if y is None else y)[idx]
    cells = float(np.ptp(ds["x0"].values)) / float(run_fact(ds, "spacing")) + 1.0
    size = (140.0 / cells) ** 2  # markers about one cell wide in a ~2.4 inch panel
    return _map(ax, xs, ys, np.clip(per * 1e3, 0, vmax), size, "magma_r", 0.0, vmax)


def _dim_label(ds) -> str:
    return "3D mid-layer" if "z0" in ds else "2D plane"


def _wrapped(title: str, panels: int) -> str:
    """A title broken into lines that fit ``panels`` map panels side by side."""
    import textwrap

    return "\n".join(textwrap.wrap(title, width=max(40, 38 * panels)))


def figure_opening_maps(runs_by_kappa: dict, out: Path, label: str) -> None:
    """Small multiples: one row per kappa, one panel per seed, the opening map (largest pair
    opening per particle, mm) at the end, titled with N_main by opening and the main run's
    share of the centre row's opening."""
    kappas = sorted(runs_by_kappa)
    cols = max(len(runs_by_kappa[k]) for k in kappas)
    fig, axes = plt.subplots(len(kappas), cols, figsize=(2.4 * cols + 1.0, 2.6 * len(kappas) + 0.8),
                             squeeze=False, layout="constrained")
    sc = None
    dims = set()
    for r, kappa in enumerate(kappas):
        for c in range(cols):
            ax = axes[r, c]
            if c >= len(runs_by_kappa[kappa]):
                ax.axis("off")
                continue
            ds = open_dataset(runs_by_kappa[kappa][c])
            dims.add(_dim_label(ds))
            m = run_metrics(ds)
            sc = _opening_panel(ax, ds)
            share = m.get("main_run_share")
            ax.set_title(f"kappa {kappa:g}, seed {int(ds.attrs.get('seed', 0))}: N = "
                         f"{m.get('n_main_cracks_opening')}, share "
                         f"{'-' if share is None else f'{share:.2f}'}", fontsize=6)
    if sc is not None:
        fig.colorbar(sc, ax=axes, shrink=0.6, label="largest pair opening [mm]")
    fig.suptitle(_wrapped(f"opening maps at the end, {', '.join(sorted(dims))}; {label}", cols),
                 fontsize=8)
    save(fig, out, dpi=MAP_DPI, tight=False)


def figure_time_sequence(runs, out: Path, label: str) -> None:
    """Opening maps at each snapshot (0.1 ... 1 ms), one row per run (one seed per variant)."""
    rows = [open_dataset(run) for run in runs]
    cols = max(ds.sizes["snapshot_time"] for ds in rows)
    fig, axes = plt.subplots(len(rows), cols, figsize=(2.6 * cols + 1.0, 2.8 * len(rows) + 0.8),
                             squeeze=False, layout="constrained")
    sc = None
    for r, ds in enumerate(rows):
        m = run_metrics(ds)
        for k in range(cols):
            ax = axes[r, k]
            if k >= ds.sizes["snapshot_time"]:
                ax.axis("off")
                continue
            sc = _opening_panel(ax, ds, ds["snap_x"].values[k], ds["snap_y"].values[k])
            ax.set_title(f"t = {float(ds['snapshot_time'].values[k]) * 1e3:.2f} ms", fontsize=7)
        axes[r, 0].set_ylabel(f"kappa {float(m['kappa']):g}, {m['distribution']}, "
                              f"{m['precrack_layout']}, seed {int(ds.attrs.get('seed', 0))}",
                              fontsize=6)
    fig.colorbar(sc, ax=axes, shrink=0.7, label="largest pair opening [mm]")
    fig.suptitle(_wrapped(f"time sequence, {_dim_label(rows[0])}; {label}", cols), fontsize=8)
    save(fig, out, dpi=MAP_DPI, tight=False)


ENERGY_TERMS = ("kinetic", "elastic", "plastic", "damage", "unattributed", "viscous",
                "artificial_stress", "penalty", "kinematic_removed")


def figure_energy(run: Path, out: Path, label: str) -> None:
    """Energy partition against time (stacked), with the balance error."""
    ds = open_dataset(run)
    t = ds["time"].values * 1e3
    terms = [k for k in ENERGY_TERMS if f"series_{k}" in ds]
    fig, ax = plt.subplots(figsize=(6.5, 4))
    ax.stackplot(t, *[ds[f"series_{k}"].values for k in terms], labels=terms)
    err = float(np.abs(ds["series_balance_error"].values).max())
    unit = "J" if "z0" in ds else "J/m"
    m = run_metrics(ds)
    ax.set_xlabel("t [ms]")
    ax.set_ylabel(f"energy [{unit}]")
    ax.legend(fontsize=6, loc="lower left")
    ax.set_title(f"{'3D disc' if 'z0' in ds else '2D plane'}, kappa {float(m['kappa']):g}, "
                 f"{m['distribution']}, seed {int(ds.attrs.get('seed', 0))}: max balance error "
                 f"{err:.2%}\n{label}", fontsize=7)
    save(fig, out)


def figure_fragments(runs_by_kappa: dict, out: Path, label: str) -> None:
    """Fragment-size distribution per kappa (all seeds pooled): the share of the layer's
    particles in fragments of at least a given size."""
    fig, ax = plt.subplots(figsize=(6.5, 4))
    dims = set()
    for kappa in sorted(runs_by_kappa):
        sizes, seeds = [], []
        for run in runs_by_kappa[kappa]:
            ds = open_dataset(run)
            dims.add(_dim_label(ds))
            sizes.append(fragments(ds))
            seeds.append(int(ds.attrs.get("seed", 0)))
        s = np.sort(np.concatenate(sizes))
        share = np.cumsum(s[::-1])[::-1] / s.sum()
        # markers: a disc still in one piece is one point, which a step line would not show
        ax.step(s, share, where="post", marker="o", ms=3, label=f"kappa {kappa:g} (seeds {seeds})")
    ax.set_xscale("log")
    ax.set_xlabel("fragment size [particles of the layer]")
    ax.set_ylabel("share of particles in fragments >= size")
    ax.set_ylim(0.0, 1.05)
    ax.legend(fontsize=6)
    ax.set_title(f"fragments (closed pairs, w <= 2 G_F/f_t), {', '.join(sorted(dims))}\n"
                 f"{label}", fontsize=7)
    save(fig, out)

