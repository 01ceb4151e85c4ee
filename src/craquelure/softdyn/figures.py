"""Figures of the Soft Dynamics model: Fig. 4 (one T1 in time), Fig. 5 (duration map), Fig. 3
(T1 occurrence in the (F_h, F_v) plane), the two-sphere gap history and the integrators' error
versus wall time."""

import math

import numpy as np

from craquelure.plotting import label_axes, plt, save


def fig4(ds, path, profile: str, scene: str):
    t = ds.time.values
    keep = t > 0
    fig, ax = plt.subplots(4, 1, figsize=(6.5, 9), sharex=True)
    ax[0].semilogx(t[keep], ds.theta.values[keep])
    ax[0].set_ylabel("theta [deg]")
    ax[1].loglog(t[keep], ds.gap.sel(pair="AB").values[keep])
    ax[1].set_ylabel("h_AB / R")
    ax[2].loglog(t[keep], ds.zeta_n.sel(pair="AB").values[keep])
    ax[2].set_ylabel("zeta_n,AB / (eta R)")
    for pair in ("AB", "AC", "CD"):
        ax[3].semilogx(t[keep], ds.force_normal.sel(pair=pair).values[keep], label=pair)
    label_axes(ax[3], "t / tau", "f_n / F_v", legend={})
    if ds.attrs.get("stopped"):
        for a in ax:
            a.axvline(ds.attrs["duration"], color="grey", lw=0.8, ls="--")
    fig.suptitle(f"T1 in time ({profile} profile, scene {scene}): h0 = {ds.attrs['h0']:g} R, "
                 f"F~ = {ds.attrs['reduced_force']:g}, T = {ds.attrs['duration']:.4g} tau",
                 fontsize=9)
    return save(fig, path)


def fig5(ds, path, profile: str, scene: str):
    fig, ax = plt.subplots(1, 2, figsize=(11, 4.5))
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for j, force in enumerate(ds.force.values):
        col = ds.sel(force=force)
        ok = np.isfinite(col.duration.values)
        c = colors[j % len(colors)]
        h0 = col.h0.values
        ax[0].loglog(h0[ok], col.duration.values[ok], "o-", color=c, label=f"F~ = {force:g}")
        ax[0].loglog(h0, col.T_P.values, ":", color=c, lw=0.8)
        ax[0].loglog(h0, col.T_H.values, "--", color=c, lw=0.8)
        ax[1].loglog(col.h0_over_h_star.values[ok], col.duration.values[ok], "o-", color=c,
                     label=f"F~ = {force:g}")
    ax[0].set_ylim(5, None)
    label_axes(ax[0], "h0 / R", "T / tau", legend={"fontsize": 8})
    ax[0].set_title("dotted: T_P (Eq. 33), dashed: T_H (Eq. 34)", fontsize=8)
    ax[1].axvline(1.0, color="grey", lw=0.8)
    label_axes(ax[1], "h0 / h*", "T / tau", legend={"fontsize": 8})
    fig.suptitle(f"T1 duration ({profile} profile, scene {scene}): "
                 f"{int(ds.attrs['n_points'])} runs, {int(ds.attrs['n_finished'])} finished",
                 fontsize=9)
    return save(fig, path)


def fig3(ds, path, profile: str, scene: str):
    fig, ax = plt.subplots(figsize=(5.5, 5))
    fh, fv, occ = ds.f_h.values.ravel(), ds.f_v.values.ravel(), ds.occurred.values.ravel()
    ax.scatter(fh[occ == 1], fv[occ == 1], marker="o", facecolor="white", edgecolor="k", label="T1")
    ax.scatter(fh[occ == 0], fv[occ == 0], marker="s", color="grey", label="no T1")
    top = max(fh.max(), fv.max() / math.sqrt(3)) * 1.1
    # many points: a two-point segment is drawn straight in display space (symlog x, log y)
    x = np.geomspace(fv[fv > 0].min() / math.sqrt(3) / 3, top, 200)
    ax.plot(x, math.sqrt(3) * x, "k-", lw=0.8, label="F_v = sqrt3 F_h")
    ax.set_xscale("symlog", linthresh=1e-4)
    ax.set_yscale("log")
    label_axes(ax, "F_h / (E R^2)", "F_v / (E R^2)", legend={"fontsize": 8})
    ax.set_title(f"T1 occurrence ({profile} profile, scene {scene}), h0 = {ds.attrs['h0']:g} R,"
                 f"\ntheta <= {ds.attrs['theta_end_deg']:g} deg within {ds.attrs['t_end']:g} "
                 f"tau", fontsize=9)
    return save(fig, path)


def two_sphere(ds, path, profile: str, scene: str):
    t = ds.time.values
    keep = t > 0
    fig, ax = plt.subplots(figsize=(6, 4.5))
    ax.loglog(t[keep], ds.gap.values[keep, 0], label="h / R")
    ax.loglog(t[keep], np.abs(ds.deflection_normal.values[keep, 0]), label="|s| / R")
    ax.axhline(ds.attrs["h_star"], color="grey", lw=0.8, ls="--", label="h*")
    label_axes(ax, "t / tau", legend={"fontsize": 8})
    ax.set_title(f"two spheres ({profile} profile, scene {scene}): h0 = {ds.attrs['h0']:g} R, "
                 f"F~ = {ds.attrs['reduced_force']:g}", fontsize=9)
    return save(fig, path)


def accuracy(ds, path, profile: str, scene: str):
    """T1 duration error (and state error at the probe time) versus integration wall time."""
    fig, ax = plt.subplots(1, 2, figsize=(11, 4.6))
    markers = {"LSODA": "o", "BDF": "s", "Radau": "^"}
    for k, (err, label) in enumerate((("error", "|T - T_ref| / tau"),
                                      ("state_error", f"max |y - y_ref| / R at t = "
                                                      f"{ds.attrs['probe_time']:g} tau"))):
        a = ax[k]
        for m, method in enumerate(ds.integrator.values):
            w = ds.adaptive_wall_time_s.values[m]
            e = ds[f"adaptive_{err}"].values[m]
            a.loglog(w, np.maximum(e, 1e-16), marker=markers.get(str(method), "x"),
                     label=f"{method} (rtol {ds.rtol.values[0]:.0e}..{ds.rtol.values[-1]:.0e})")
        ok = ds.heun_stable.values > 0
        if ok.any():
            a.loglog(ds.heun_wall_time_s.values[ok], np.maximum(ds[f"heun_{err}"].values[ok],
                                                                1e-16),
                     marker="D", ls="--", color="k",
                     label=f"heun (dt {ds.dt.values[ok][0]:g}..{ds.dt.values[ok][-1]:g} tau)")
        label_axes(a, "integration wall time [s]", label)
        a.grid(True, which="both", alpha=0.3)
    ax[0].legend(fontsize=8)
    order = ds.attrs.get("heun_duration_order", math.nan)
    fig.suptitle(
        f"softdyn accuracy vs cost, profile {profile}, scene {scene}: T1 at h0 = "
        f"{ds.attrs['h0']:g} R, F~ = {ds.attrs['reduced_force']:g} (T_ref = "
        f"{ds.attrs['reference_duration']:.4f} tau)\nreference: {ds.attrs['reference']}; "
        f"heun order (3 finest dt): duration {order:.2f}, state "
        f"{ds.attrs.get('heun_state_order', math.nan):.2f}", fontsize=9)
    return save(fig, path)
