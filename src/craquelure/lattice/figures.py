"""Figures of the lattice model (matplotlib, Agg). Each draws a run dataset and the numbers of
:mod:`craquelure.lattice.analysis` (fragment labels, fits, summaries), with a title that
states the profile, scene and sizes; nothing here fits or judges."""

import numpy as np

from craquelure.lattice import fragments
from craquelure.plotting import label_axes, plt, save


def _save(fig, out, title=None, **title_kw) -> None:
    if title is not None:
        fig.suptitle(title, **title_kw)
    save(fig, out)


def calving(ds, labels, summary, out, title):
    """Fragments at the last frame (``labels``), broken beams in time and the size
    distribution with the fits of ``summary`` (:func:`craquelure.lattice.analysis.
    calving_summary`)."""
    sz = fragments.sizes(labels)
    fig, ax = plt.subplots(2, 2, figsize=(11, 7), gridspec_kw={"height_ratios": [1.2, 1]})
    ax = ax.ravel()
    gs = ax[0].get_gridspec()
    ax[0].remove()
    ax[1].remove()
    big = fig.add_subplot(gs[0, :])
    x, y = ds.x.values[-1], ds.y.values[-1]
    counts = np.bincount(labels[labels >= 0])
    main = np.argmax(counts)
    colour = np.where(labels == main, 0.0, (labels * 0.618) % 1 + 0.1)
    big.scatter(x, y, c=colour, s=4, cmap="tab20b", vmin=0, vmax=1.1)
    wl = ds.attrs.get("water_level")
    if wl is not None and np.isfinite(wl):
        big.axhline(wl, color="tab:blue", lw=0.8)
    big.set(aspect="equal", title=f"t = {float(ds.frame_time[-1]):.0f}: fragments (main body dark)")
    ax[2].plot(ds.time, ds.broken, color="k")
    label_axes(ax[2], "t", "broken beams")
    c, d, n = fragments.size_distribution(sz)
    slope, decades = summary["slope"], summary["decades"]
    tau, cut = summary["ml_exponent"], summary["ml_cutoff"]
    sel = n > 0
    ax[3].loglog(c[sel], d[sel], "o", color="k", label="n(s)")
    if np.isfinite(slope):
        ref = d[sel][0] * (c[sel] / c[sel][0]) ** -1.5
        ax[3].loglog(c[sel], ref, "--", color="tab:red", label="s^-3/2")
    if np.isfinite(tau):
        # maximum-likelihood form: expected counts in the same log bins / bin width
        grid = np.arange(1, int(50 * c[sel].max()) + 1)
        w = grid ** -tau * np.exp(-grid / cut)
        edges = np.sqrt(c[:-1] * c[1:])
        edges = np.r_[c[0] ** 2 / edges[0], edges, c[-1] ** 2 / edges[-1]]
        expected, _ = np.histogram(grid, edges, weights=(sz.size - 1) * w / w.sum())
        ax[3].loglog(c[sel], (expected / np.diff(edges))[sel], "-", color="tab:blue",
                     label=f"ML s^-{tau:.2f} exp(-s/{cut:.0f}), same bins")
    label_axes(ax[3], "fragment size s (particles)", "n(s)", legend={"fontsize": 8})
    ax[3].set_title(f"{sz.size - 1} fragments: ML exponent {tau:.2f} (cut-off {cut:.0f}); "
                    f"binned slope {slope:.2f} over {decades:.1f} dec.", fontsize=9)
    _save(fig, out, title)


def fretting(ds, labels, per_cycle, out, title):
    fig, ax = plt.subplots(3, 1, figsize=(10, 9), gridspec_kw={"height_ratios": [1, 1, 0.8]})
    body = ds.body.values == 0
    x0, y0 = ds.x.values[0], ds.y.values[0]
    broken = ds.bond_state.values == 0
    i, j = ds.bond_i.values[broken], ds.bond_j.values[broken]
    ax[0].scatter(x0[body], y0[body], s=1, color="0.8")
    sc = ax[0].scatter(0.5 * (x0[i] + x0[j]), 0.5 * (y0[i] + y0[j]),
                       c=ds.bond_break_time.values[broken], s=6, cmap="viridis")
    fig.colorbar(sc, ax=ax[0], label="break time")
    ax[0].set(aspect="equal", title="broken beams in the reference configuration")
    counts = np.bincount(labels[labels >= 0])
    main = np.argmax(counts)
    x, y = ds.x.values[-1], ds.y.values[-1]
    ax[1].scatter(x[~body], y[~body], s=3, color="tab:gray")
    ax[1].scatter(x[body], y[body], s=3, c=np.where(labels[body] == main, 0.0, 1.0),
                  cmap="coolwarm", vmin=0, vmax=1)
    ax[1].set_aspect("equal")
    ax[1].set_title(f"t = {float(ds.frame_time[-1]):.0f}: pad, body and detached platelets (red)")
    cyc = np.arange(1, len(per_cycle) + 1)
    ax[2].bar(cyc, [p["platelets"] for p in per_cycle], width=0.5, color="tab:red")
    for k, p in zip(cyc, per_cycle, strict=True):
        ax[2].annotate(f"mean size {p['mean_size']:.1f}\nmax depth {p['max_depth']:.1f} L\n"
                       f"{p['broken']} broken beams", (k, p["platelets"]), ha="center",
                       va="bottom", fontsize=7)
    ax[2].set_xticks(cyc)
    label_axes(ax[2], "cycle", "detached platelets")
    _save(fig, out, title)


def glen(table, fit, frozen_fit, out, title):
    fig, ax = plt.subplots(1, 2, figsize=(10, 4.2))
    for kind, marker, f in (("glen", "o", fit), ("frozen", "s", frozen_fit)):
        rows = [r for r in table if r["kind"] == kind]
        tau = np.array([r["tau"] for r in rows])
        mu = np.array([r["mu"] for r in rows])
        rate = np.array([r["gamma_dot"] for r in rows])
        lab = "melting-freezing" if kind == "glen" else "lambda frozen (Newtonian)"
        ax[0].loglog(tau, mu, marker, label=f"{lab}: slope {f[0]:.2f}")
        ax[0].loglog(tau, f[1] * tau ** f[0], "-", lw=0.8, color="0.4")
        ax[1].loglog(tau, rate, marker, label=lab)
    label_axes(ax[0], "applied shear stress tau_app", "viscosity mu = 2 tau / gamma_dot",
               legend={"fontsize": 8})
    label_axes(ax[1], "tau_app", "strain rate gamma_dot", legend={"fontsize": 8})
    _save(fig, out, title)


def gravity(ds, predicted, out, title):
    row = ds.row.values
    top = row == row.max()
    x0 = ds.x.values[0][top]
    dy = ds.y.values[0][top] - ds.y.values[-1][top]
    fig, ax = plt.subplots(figsize=(8, 4))
    ax.plot(x0, dy, ".", label="top row settlement")
    ax.axhline(predicted, color="tab:red", label="rho_2 g H^2 / (2M)")
    label_axes(ax, "x", "settlement", legend={})
    ax.set_title(title, fontsize=9)
    _save(fig, out)


def scaling(rows, out, title):
    n = np.array([r["particles"] for r in rows])
    t = np.array([r["time_per_step_per_particle"] for r in rows])
    cpu = np.array([r["cpu_per_thread_per_step_per_particle"] for r in rows])
    rate = np.array([r["bond_updates_per_s"] for r in rows])
    fig, ax = plt.subplots(1, 2, figsize=(10, 4))
    ax[0].loglog(n, t * 1e9, "o-", label="wall time")
    ax[0].loglog(n, cpu * 1e9, "s--", label="CPU time per thread")
    label_axes(ax[0], "particles N", "time per step per particle [ns]", legend={})
    both = np.concatenate([t, cpu])
    ax[0].set_ylim(both.min() * 1e9 / 3, both.max() * 1e9 * 3)
    ax[1].semilogx(n, rate / 1e6, "o-")
    ax[1].axhline(20, color="tab:red", ls="--", label="target 2e7/s")
    label_axes(ax[1], "particles N", "bond updates per second [1e6]", legend={})
    _save(fig, out, title, fontsize=9)


def accuracy(rows, out, title):
    """Error versus wall time (and versus resolution) of the column-mode study
    (:mod:`craquelure.lattice.accuracy`), one curve per time-step factor."""
    fig, ax = plt.subplots(1, 2, figsize=(11, 4.2))
    factors = sorted({r["dt_factor"] for r in rows}, reverse=True)
    for f in factors:
        sel = [r for r in rows if r["dt_factor"] == f]
        wall = np.array([r["wall_s"] for r in sel])
        err = np.array([r["relative_error"] for r in sel])
        n = np.array([r["rows"] for r in sel])
        line, = ax[0].loglog(wall, err, "o-", label=f"dt = {f:g} x 2/omega_est")
        for w, e, k in zip(wall, err, n, strict=True):
            ax[0].annotate(f"N={k}", (w, e), fontsize=7, xytext=(3, 3),
                           textcoords="offset points", color=line.get_color())
        ax[1].loglog(n, err, "o-", color=line.get_color(), label=f"dt factor {f:g}")
    n_all = np.array(sorted({r["rows"] for r in rows}))
    chain = np.array([next(r["chain_prediction"] for r in rows if r["rows"] == k) for k in n_all])
    ax[1].loglog(n_all, chain, "k--", lw=0.8, label="fixed-free chain (sin x/x - 1)")
    label_axes(ax[0], "wall time of the run [s] (compilation excluded)",
               "|T / T_continuum - 1|", legend={"fontsize": 8})
    ax[0].set_title("error versus cost", fontsize=9)
    label_axes(ax[1], "free rows N (h = H/(N + 1/2))", "|T / T_continuum - 1|",
               legend={"fontsize": 8})
    ax[1].set_title("error versus resolution (order 2 expected)", fontsize=9)
    _save(fig, out, title, fontsize=9)
