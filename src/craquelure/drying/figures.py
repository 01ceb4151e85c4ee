r"""Figures of the drying-paste campaign (paper Figs. 2-6), from analysis datasets only.

Every figure, written as PNG and PDF, carries a caption line with the profile, N, L, the number
of seeds, the time unit (:math:`t^* = \sigma_Y/v_r`, and the profile's speed-up over the paper)
and the fitted numbers from the summary (:func:`craquelure.drying.summary.summarise`)."""

from __future__ import annotations

from functools import partial
from pathlib import Path
from typing import Any

import matplotlib.ticker
import numpy as np
import xarray as xr

from craquelure.drying.claims import LABELLING_KEYS, setting
from craquelure.drying.effects.fracture import SOURCE_MEASURE, departure_note
from craquelure.drying.summary import ccdf_bands, json_ready
from craquelure.drying.time_scales import drying_number, paper_t_star, window_of
from craquelure.plotting import label_axes, plt, save

FIGURES = ("snapshots", "inverse_mean_area", "size_distribution", "scaled_distribution")


def _fmt(value: Any, spec: str = ".3g") -> str:
    return "n/a" if value is None or (isinstance(value, float) and not np.isfinite(value)) \
        else format(value, spec)


def setup_line(campaign: xr.Dataset, profile: str) -> str:
    """Profile, sizes, seeds and the time unit, for every caption."""
    a = campaign.attrs
    tstar = float(a["t_star"])
    speed = paper_t_star() / tstar
    window = ("paper's window rescaled by t*" if str(a.get("window_mode", "paper")) == "paper"
              else "window from the first snapshot with every sample broken")
    pace = ("as the paper" if abs(speed - 1) < 1e-3
            else f"{speed:.3g}x faster than the paper; {window}")
    pi = drying_number(a)
    regime = ("" if pi["pi"] is None else f"; Pi = tau/t* = {pi['pi']:.3g} with tau = "
              f"eta/(2 mu) = {pi['tau']:.3g} (paper {pi['pi_paper']:.2g})")
    criterion = departure_note(str(a.get("fracture_stress_measure", SOURCE_MEASURE)))
    return (f"profile {profile}, scene {a.get('scene_name', '?')}: N = {int(a['n_particles'])}, "
            f"L = {float(a['box_length']):g}, {campaign.sizes['seed']} seeds; "
            f"t* = sigma_Y/v_r = {tstar:.3g} (drying {pace}){regime}"
            + (f"; {criterion.upper()[0]}{criterion[1:]}" if criterion else ""))


def fit_line(summary: dict[str, Any]) -> str:
    fit = summary.get("fit", {})
    ci = fit.get("alpha_ci95") or [None, None]
    c14 = summary["checks"]["check14_inverse_mean_area_linear"]
    lo, hi = (_fmt(v) for v in summary["window"])
    return (f"window t = [{lo}, {hi}]: "
            f"alpha = {_fmt(fit.get('alpha'))} (95% CI {_fmt(ci[0])}-{_fmt(ci[1])}), "
            f"1/<S> linear: reduced chi^2 = {_fmt(c14.get('reduced_chi2'))}, "
            f"b = {_fmt(c14.get('slope_b'))} = {_fmt(summary.get('slope_over_b_star'))} b*, "
            f"t0 = {_fmt(c14.get('x_intercept_t0'))}; check 14 {c14['verdict']} (power "
            f"{_fmt(c14.get('power'), '.2f')} against t^-2)")


def collapse_line(summary: dict[str, Any]) -> str:
    c15 = summary["checks"]["check15_scaling_collapse"]
    return (f"check 15: KS(X_first, X_last) = {_fmt(c15.get('ks_scaled_first_last'))} (upper 95% "
            f"{_fmt(c15.get('ks_scaled_first_last_upper95'))} vs margin "
            f"{_fmt(c15.get('ks_margin'))}), CV<X^2> upper 95% "
            f"{_fmt(c15.get('cv_mean_x2_upper95'))} vs {_fmt(c15.get('cv_margin'))} (margins: "
            f"half what a 25% width drift does), raw KS(S) first/last "
            f"{_fmt(c15.get('ks_raw_first_last'))}; power against the drift "
            f"{_fmt(c15.get('power'), '.2f')}, exact collapse passes "
            f"{_fmt(c15.get('confirmation_rate'), '.2f')}; {c15['verdict']}")


def _caption(fig, lines: list[str]):
    """``fig`` with the caption ``lines`` at its bottom left."""
    fig.text(0.01, 0.01, "\n".join(lines), fontsize=7, va="bottom", ha="left", wrap=True)
    return fig


def save_figure(fig, png: str | Path) -> tuple[Path, Path]:
    """Write ``png`` and the PDF next to it (same stem)."""
    png = save(fig, png, dpi=150, tight=False, pdf=True)
    return png, png.with_suffix(".pdf")


def _positive(values: np.ndarray) -> np.ndarray:
    """Empty bins as gaps on a log axis."""
    return np.where(values > 0, values, np.nan)


def _colours(n: int):
    return plt.cm.viridis(np.linspace(0.0, 0.9, n))


def fig_snapshots(run: xr.Dataset, campaign: xr.Dataset, summary: dict[str, Any],
                  profile: str, n_panels: int = 4):
    """Fig. 2: crack patterns of one sample at four snapshot times after the initial stage,
    surviving particles coloured by mean stress / sigma_Y (the run's recorded snapshots)."""
    sigma_y, tstar = float(campaign.attrs["yield_stress"]), float(campaign.attrs["t_star"])
    times = run["time"].values
    start = summary.get("initial_stage_end")  # None when no snapshot has every sample broken
    late = np.flatnonzero(times >= start) if start is not None else np.zeros(0, int)
    if late.size == 0 or times.size <= n_panels:  # an archived run holds only its panels
        late = np.arange(times.size)
    picks = np.unique(late[np.linspace(0, late.size - 1, min(n_panels, late.size)).astype(int)])
    length = float(run.attrs["box_length"])
    fig, axes = plt.subplots(1, picks.size, figsize=(3.2 * picks.size, 3.9), squeeze=False)
    size = max(0.5, 2.0e4 / run.sizes["particle"])
    image = None
    for ax, k in zip(axes[0], picks, strict=True):
        snap = run.isel(time=int(k))
        alive = snap["alive"].values.astype(bool)
        image = ax.scatter(snap["x"].values[alive], snap["y"].values[alive],
                           c=snap["mean_stress"].values[alive] / sigma_y, s=size,
                           cmap="coolwarm", vmin=-1.0, vmax=1.0, linewidths=0)
        ax.set(xlim=(0, length), ylim=(0, length), aspect="equal", xticks=[], yticks=[])
        ax.set_title(f"t = {times[k]:.3g} ({times[k] / tstar:.2f} t*), "
                     f"{int((~alive).sum())} removed", fontsize=8)
    fig.suptitle(f"Crack pattern of seed {run.attrs.get('seed', '?')} (cf. paper Fig. 2)")
    fig.subplots_adjust(bottom=0.2, top=0.85, left=0.02, right=0.9, wspace=0.08)
    fig.colorbar(image, cax=fig.add_axes([0.92, 0.25, 0.012, 0.55]),
                 label="mean stress / sigma_Y")
    return _caption(fig, [setup_line(campaign, profile), fit_line(summary)])


def fig_inverse_mean_area(campaign: xr.Dataset, summary: dict[str, Any], profile: str):
    """Fig. 3: 1/<S>_t (+- its SE over seeds) vs t, the linear fit over the window and t*."""
    t, inv, err = (campaign[key].values
                   for key in ("time", "inverse_mean_area", "inverse_mean_area_se"))
    fig, ax = plt.subplots(figsize=(6.4, 5.2))
    ax.errorbar(t, inv, yerr=np.where(np.isfinite(err), err, 0.0), fmt="o", ms=4,
                capsize=2, label="1/<S>_t (pooled over seeds, +- 1 SE)")
    fit = summary["checks"]["check14_inverse_mean_area_linear"]
    if "slope_b" in fit:
        tt = np.linspace(summary["window"][0], summary["window"][1], 50)
        ax.plot(tt, fit["intercept_a"] + fit["slope_b"] * tt, "k-",
                label=f"weighted linear fit (check 14), reduced chi^2 = {fit['reduced_chi2']:.3g}")
        t0 = fit["x_intercept_t0"]
        if np.isfinite(t0):
            ext = np.linspace(max(min(t0, tt[0]), 0.0), tt[0], 20)  # t >= 0 only
            ax.plot(ext, fit["intercept_a"] + fit["slope_b"] * ext, "k:", lw=0.8)
    if None not in summary["window"]:
        ax.axvspan(*summary["window"], color="0.9", zorder=0, label="fit window")
    ax.axvline(float(campaign.attrs["t_star"]), color="C3", ls="--", lw=1,
               label="t* = sigma_Y / v_r")
    label_axes(ax, "t [eta/lambda]", "1/<S>_t [1/length^2]")
    ax.set_ylim(bottom=0)
    ax.legend(fontsize=7, loc="upper left")
    ax.set_title("Inverse mean fragment area (cf. paper Fig. 3)")
    fig.subplots_adjust(bottom=0.22)
    return _caption(fig, [setup_line(campaign, profile), fit_line(summary)])


def _ccdf_panel(ax, campaign: xr.Dataset, times: np.ndarray, scaled: bool) -> None:
    """CCDFs with 95 % bootstrap bands at (up to 7 of) ``times``."""
    if times.size > 7:
        times = times[np.linspace(0, times.size - 1, 7).astype(int)]
    all_times = campaign["time"].values
    grid = np.linspace(0.0, float(campaign["x_hi" if scaled else "area_hi"].values[-1]), 200)
    for colour, t in zip(_colours(times.size), times, strict=True):
        k = int(np.argmin(np.abs(all_times - t)))
        c = ccdf_bands(campaign, k, grid, scaled)
        ax.fill_between(grid, _positive(c["lo"]), _positive(c["hi"]), color=colour, alpha=0.2,
                        lw=0, step="post")
        ax.step(grid, _positive(c["ccdf"]), where="post", color=colour,
                label=f"t = {t:.3g} ({c['n']} fragments)")
    ax.set_yscale("log")
    if times.size:
        ax.legend(fontsize=7)


def fig_size_distribution(campaign: xr.Dataset, summary: dict[str, Any], profile: str):
    """Fig. 4: CCDF of S at (up to 7) snapshot times of the window, 95 % bootstrap bands (a
    histogram of ~20 fragments per snapshot is noise; a cumulative curve with its band shows
    what the sample can resolve)."""
    fig, ax = plt.subplots(figsize=(6.4, 5.2))
    _ccdf_panel(ax, campaign, campaign["time"].values[window_of(campaign)["mask"]], scaled=False)
    label_axes(ax, "S [length^2]", "P(fragment area > S; t)")
    ax.set_title("Fragment-size distribution, complementary cumulative (cf. paper Fig. 4)",
                 fontsize=9)
    fig.subplots_adjust(bottom=0.22)
    return _caption(fig, [setup_line(campaign, profile),
                          "bands: 95 % bootstrap over samples; " + fit_line(summary)])


def fig_scaled_distribution(campaign: xr.Dataset, summary: dict[str, Any], profile: str):
    """Figs. 5-6: CCDF of X = S/<S>_t inside (collapse expected) and before the window (no
    collapse expected), 95 % bootstrap bands, with check 15's numbers."""
    t_all = campaign["time"].values
    window = window_of(campaign)["mask"]
    start = int(np.argmax(window)) if window.any() else t_all.size
    groups = [("inside the window (collapse expected)", t_all[window]),
              ("before the window (no collapse expected)", t_all[:start])]
    fig, axes = plt.subplots(1, 2, figsize=(11, 5.0), sharey=True)
    for ax, (title, times) in zip(axes, groups, strict=True):
        _ccdf_panel(ax, campaign, times, scaled=True)
        ax.set_xlabel("X = S / <S>_t")
        ax.set_title(title, fontsize=9)
    axes[0].set_ylabel("P(S/<S>_t > X; t)")
    fig.suptitle("Scaled fragment-size distribution, complementary cumulative "
                 "(cf. paper Figs. 5-6)")
    fig.subplots_adjust(bottom=0.24, top=0.88)
    return _caption(fig, [setup_line(campaign, profile), fit_line(summary),
                          collapse_line(summary)])


def make_figures(campaign: xr.Dataset, summary: dict[str, Any], run: xr.Dataset,
                 outputs: dict[str, str | Path], profile: str) -> list[Path]:
    """All four figures; ``outputs`` maps each name of :data:`FIGURES` to its PNG path."""
    makers = {"snapshots": partial(fig_snapshots, run), "inverse_mean_area": fig_inverse_mean_area,
              "size_distribution": fig_size_distribution,
              "scaled_distribution": fig_scaled_distribution}
    return [path for name in FIGURES
            for path in save_figure(makers[name](campaign, summary, profile), outputs[name])]


# Comparison of archived ensembles (a headline and its companions), one figure each:
# figures/drying_companions_<name>.png, their data in figures/drying_companions.json.
COMPARISON = ("inverse_mean_area", "scaled_distribution")
CHECKS_OF = {"periodic": "checks", "open": "checks_open_image"}  # summary key per labelling


def comparison_series(name: str, summary: dict[str, Any], campaigns: dict[str, xr.Dataset],
                      n_grid: int = 100) -> dict[str, Any]:
    """What the comparison figures draw of one ensemble (archived as ``name``), per labelling
    of ``campaigns``: 1/<S>_t with its standard error against t/t*, check 14's weighted fit
    1/<S>_t = b (t - t0) at its window's ends, and the CCDF of X = S/<S>_t pooled over the
    window's snapshots (JSON-ready)."""
    out = {"name": name, "profile": summary["profile"], "setting": setting(summary),
           "labellings": {}}
    for labelling, ds in campaigns.items():
        tstar, win = float(ds.attrs["t_star"]), window_of(ds)
        c14 = summary[CHECKS_OF[labelling]]["check14_inverse_mean_area_linear"]
        ends = np.array([win["start"], win["end"]] if "slope_b" in c14 else [], float)
        x = ds["fragment_scaled_area"].values[win["mask"][ds["fragment_time_index"].values]]
        x = np.sort(x[np.isfinite(x)])
        grid = np.linspace(0.0, x[-1] if x.size else 1.0, n_grid)
        out["labellings"][labelling] = {
            "t_over_t_star": ds["time"].values / tstar,
            "inverse_mean_area": ds["inverse_mean_area"].values,
            "inverse_mean_area_se": ds["inverse_mean_area_se"].values,
            "fit_t_over_t_star": ends / tstar,  # no fit: empty
            "fit_inverse_mean_area": c14.get("intercept_a", 0.0) + c14.get("slope_b", 0.0) * ends,
            "x": grid, "ccdf": 1.0 - np.searchsorted(x, grid, side="right") / max(x.size, 1),
            "n_fragments": int(x.size)}
    return json_ready(out)


def make_comparison(series: list[dict[str, Any]], outputs: dict[str, str | Path]) -> list[Path]:
    """Fig. 3 (1/<S>_t against t/t* with each ensemble's 1/t law) and Figs. 4-6 (the scaled
    distributions) of several ensembles (:func:`comparison_series`), one colour each, a panel
    per labelling; ``outputs`` maps each name of :data:`COMPARISON` to its PNG path."""
    figs = {name: plt.subplots(1, 2, figsize=(12, 6.0 + 0.2 * len(series)), sharey=True)
            for name in COMPARISON}
    for colour, s in zip(_colours(len(series)), series, strict=True):
        label = f"{s['name']} (profile {s['profile']}), {s['setting']}"
        for k, labelling in enumerate(CHECKS_OF):
            d = s["labellings"].get(labelling)
            if d is None:
                continue
            ax = figs["inverse_mean_area"][1][k]
            ax.errorbar(d["t_over_t_star"], np.array(d["inverse_mean_area"], float),
                        yerr=np.nan_to_num(np.array(d["inverse_mean_area_se"], float)),
                        fmt="o", ms=3, capsize=2, color=colour, label=label)
            ax.plot(d["fit_t_over_t_star"], d["fit_inverse_mean_area"], "-", color=colour)
            figs["scaled_distribution"][1][k].step(
                d["x"], _positive(np.array(d["ccdf"], float)), where="post", color=colour,
                label=label)
    bottom = 0.16 + 0.035 * len(series)
    for fig, axes in figs.values():
        for ax, key in zip(axes, CHECKS_OF.values(), strict=True):
            ax.set_title(LABELLING_KEYS[key], fontsize=9)
        handles, labels = axes[0].get_legend_handles_labels()
        fig.legend(handles, labels, fontsize=7, loc="lower left",
                   bbox_to_anchor=(0.01, 0.05), frameon=False)
        fig.subplots_adjust(bottom=bottom, top=0.9, wspace=0.05)
    fig, axes = figs["inverse_mean_area"]
    for ax in axes:
        label_axes(ax, "t / t*  (t* = sigma_Y / v_r)")
        ax.set_ylim(bottom=0)
    axes[0].set_ylabel("1/<S>_t [1/length^2]")
    fig.suptitle("Inverse mean fragment area of the archived ensembles (cf. paper Fig. 3)")
    _caption(fig, ["points: 1/<S>_t pooled over seeds, +- 1 SE; lines: "
                   "each ensemble's weighted fit 1/<S>_t = b (t - t0) over its window (check "
                   "14), the law <S>_t ~ 1/t"])
    fig, axes = figs["scaled_distribution"]
    for ax in axes:
        ax.set_yscale("log")
        ax.set_xlabel("X = S / <S>_t")
    axes[0].set_ylabel("P(S/<S>_t > X), pooled over the window")
    fig.suptitle("Scaled fragment-size distributions of the archived ensembles "
                 "(cf. paper Figs. 4-6)")
    _caption(fig, ["complementary cumulative distribution of X = S/<S>_t "
                   "over every fragment of the snapshots in each ensemble's window: curves "
                   "that lie on one another collapse across criteria and sizes"])
    return [path for name in COMPARISON for path in save_figure(figs[name][0], outputs[name])]


def fig_accuracy(study: xr.Dataset, profile: str):
    """Error versus wall time of the integrators (dataset of
    :func:`craquelure.drying.accuracy.error_versus_wall_time`), one line per integrator, points
    labelled by dt, with the observed orders in the legend."""
    fig, ax = plt.subplots(figsize=(6.4, 5.0))
    fig.subplots_adjust(bottom=0.24)
    names = study["integrator"].values
    for name, colour in zip(names, _colours(len(names)), strict=True):
        err, wall, order = (study[key].sel(integrator=name).values
                            for key in ("error", "wall_time", "observed_order"))
        orders = ", ".join(_fmt(float(o), ".2f") for o in order)
        ax.loglog(wall, err, "o-", color=colour,
                  label=f"{name} (observed orders between successive dt: {orders})")
        for w, e, dt in zip(wall, err, study["dt"].values, strict=True):
            ax.annotate(f"{dt:g}", (w, e), fontsize=6, xytext=(3, 3),
                        textcoords="offset points")
    if "rkc2_error" in study:  # error-controlled RKC2, labelled by its tolerance
        ax.loglog(study["rkc2_wall_time"].values, study["rkc2_error"].values, "s--",
                  color="black", label="rkc2, error-controlled (labels: tolerance)")
        for w, e, tol in zip(study["rkc2_wall_time"].values, study["rkc2_error"].values,
                             study["tolerance"].values, strict=True):
            ax.annotate(f"tol {tol:g}", (w, e), fontsize=6, xytext=(3, -8),
                        textcoords="offset points")
    label_axes(ax, "wall time of the stepping loop [s]",
               "relative L2 error of the final velocity field", legend={"fontsize": 7})
    a = study.attrs
    ax.set_title(f"Drying SPH: error vs wall time (profile {profile})", fontsize=9)
    return _caption(fig, [
        f"profile {profile}, scene {a.get('scene_name', '?')}: N = {int(a['n_particles'])}, "
        f"t = 0..{float(a['t_end']):g}, fracture off; labels are dt",
        f"reference: {a['reference']} at dt = {float(a['reference_dt']):g} "
        f"({float(a['reference_wall_time_s']):.3g} s); error {a['error_measure']}",
        f"wall time on {a.get('threads', '?')} numba thread(s), measured {a.get('start_time', '')}",
    ])


def fig_thickness(sweep: xr.Dataset, profile: str):
    """Thickness sweep: (a) <S>_t per H against t, (b) <S> against H on log-log axes at the
    late usable snapshots with the fitted exponents and the H^2 prediction."""
    fig, (ax_t, ax_h) = plt.subplots(1, 2, figsize=(11, 5.0))
    fig.subplots_adjust(bottom=0.24)
    times = sweep["time"].values
    h = sweep["thickness"].values
    for colour, value in zip(_colours(h.size), h, strict=True):
        row = sweep.sel(thickness=value)
        ax_t.errorbar(times, _positive(row["mean_area"].values),
                      yerr=np.nan_to_num(row["mean_area_se"].values), fmt="o-", ms=3,
                      color=colour, capsize=2, label=f"H = {value:g}")
    late = sweep["late"].values.astype(bool)
    ax_t.axvspan(*(times[late][[0, -1]] if late.any() else (np.nan, np.nan)), color="0.9",
                 zorder=0, label="late snapshots (exponent)")
    ax_t.set_yscale("log")
    label_axes(ax_t, "t [eta/lambda]", "<S>_t [length^2]", legend={"fontsize": 7})
    ax_t.set_title("Mean fragment area per layer thickness", fontsize=9)
    picks = np.flatnonzero(late)
    for colour, k in zip(_colours(picks.size), picks, strict=True):
        ax_h.loglog(h, sweep["mean_area"].values[:, k], "o-", color=colour,
                    label=f"t = {times[k]:.3g}: beta = {sweep['exponent'].values[k]:.2f}")
    if picks.size:
        ref = sweep["mean_area"].values[:, picks[-1]]
        guide = ref[-1] * (h / h[-1]) ** float(sweep.attrs["predicted_exponent"])
        ax_h.loglog(h, guide, "k--", lw=1, label="H^2 (prediction)")
        ax_h.legend(fontsize=7)
    else:
        ax_h.text(0.5, 0.5, "no late snapshot with every sample of every H broken",
                  ha="center", va="center", fontsize=8, transform=ax_h.transAxes)
    label_axes(ax_h, "layer thickness H", "<S> [length^2]")
    ax_h.set_title("<S> against H at the late snapshots", fontsize=9)
    a = sweep.attrs
    fig.suptitle(f"Drying paste: thickness sweep (profile {profile})")
    return _caption(fig, [
        f"profile {profile}, scene {a.get('scene_name', '?')}: H = "
        f"{', '.join(f'{v:g}' for v in h)}, seeds per H = "
        f"{', '.join(str(int(n)) for n in sweep['n_seeds'].values)}; same initial states",
        f"exponent beta of <S> ~ H^beta (mean over {int(a['n_late_times'])} late snapshots with "
        f"every sample broken): {_fmt(float(a['exponent_late_mean']))} +- "
        f"{_fmt(float(a['exponent_late_std']), '.2g')}; predicted "
        f"{float(a['predicted_exponent']):g} (dimensional analysis, spec eq. (29))",
    ])


def fig_speed(study: xr.Dataset, profile: str):
    """Drying-speed study: (a) onset in t* against Pi, (b) t0/t* and b/b*, (c) fragments per unit
    area at fixed t/t*, each with its 95 % bootstrap interval; the paper's Pi and values marked."""
    pi = study["speed"].values
    a = study.attrs
    fig, (ax_o, ax_f, ax_n) = plt.subplots(1, 3, figsize=(14, 5.0))
    fig.subplots_adjust(bottom=0.26, wspace=0.3)

    def bars(ax, key, label, colour, marker="o", data=study):
        y = data[key].values
        err = np.abs(np.stack([y - data[f"{key}_lo"].values, data[f"{key}_hi"].values - y]))
        ax.errorbar(pi, y, yerr=np.nan_to_num(err), fmt=marker + "-", color=colour, capsize=3,
                    ms=4, label=label)

    for key, label, colour in (("first_removal_median", "first removal (median)", "C0"),
                               ("first_sample_broken", "first sample broken", "C1"),
                               ("half_samples_broken", "half broken", "C2"),
                               ("all_samples_broken", "all broken", "C3")):
        bars(ax_o, key, label, colour)
    ax_o.axhline(a["paper_first_broken_over_t_star"], color="C1", ls=":", lw=1,
                 label="paper: fragments from 0.40 t*")
    ax_o.axhline(a["paper_all_broken_over_t_star"], color="C3", ls=":", lw=1,
                 label="paper: all broken before 0.8 t*")
    ax_o.set_ylabel("time / t*")
    ax_o.set_title("Onset", fontsize=9)
    bars(ax_f, "t0_over_t_star", "t0 / t*", "C4")
    bars(ax_f, "b_over_b_star", "b / b*", "C5", "s")
    ax_f.axhline(a["paper_t0_over_t_star_max"], color="C4", ls=":", lw=1,
                 label="t0 <= t* (dimensional analysis)")
    ax_f.set_title("1/<S>_t = b (t - t0) over the broken snapshots", fontsize=9)
    # An undetermined value is said, not left as a silently empty point or panel.
    def undetermined(key: str) -> str:
        return ", ".join(f"{p:.3g}" for p, v in zip(pi, study[key].values, strict=True)
                         if not np.isfinite(v))

    unfit, unbroken = undetermined("t0_over_t_star"), undetermined("all_samples_broken")
    if unfit:
        ax_f.text(0.5, 0.3, f"no fit at Pi = {unfit}:\nfewer than 4 snapshots with "
                  "every sample broken", transform=ax_f.transAxes, ha="center", fontsize=8)
    if unbroken:
        ax_o.text(0.02, 0.02, f"not all samples broken by the run's end at Pi = {unbroken}",
                  transform=ax_o.transAxes, fontsize=7)
    fixed = study["fixed_time"].values
    for colour, f in zip(_colours(fixed.size), fixed, strict=True):
        bars(ax_n, "fragments_per_area", f"t = {f:g} t*", colour, data=study.sel(fixed_time=f))
    ax_n.set_ylabel("fragments per unit area [1/length^2]")
    ax_n.set_title("Fragment density at fixed t/t*", fontsize=9)
    for ax in (ax_o, ax_f, ax_n):
        ax.set_xscale("log")
        ax.set_xlim(min(pi.min(), a["paper_pi"]) / 1.5, max(pi.max(), a["paper_pi"]) * 1.5)
        # Ticks at the study's speeds only: log-axis minor labels overlap over one decade.
        ax.set_xticks(pi, [f"{v:.3g}" for v in pi])
        ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
        ax.axvline(a["paper_pi"], color="k", ls="--", lw=0.8, label="paper's Pi = 0.022")
        label_axes(ax, "Pi = tau / t*  (tau = eta/(2 mu), t* = sigma_Y/v_r)",
                   legend={"fontsize": 6})
    fig.suptitle(f"Drying paste: drying-speed study (profile {profile})")
    seeds = ", ".join(str(int(n)) for n in study["n_seeds"].values)
    return _caption(fig, [
        f"profile {profile}, scene {a.get('scene_name', '?')}: Pi = "
        f"{', '.join(f'{v:.3g}' for v in pi)} (paper {a['paper_pi']:g}); seeds per speed {seeds};"
        f" bars: 95 % bootstrap over seeds",
        "t* = sigma_Y/v_r; onset from the snapshots (>= 2 fragments = broken); t0 and b from the "
        "weighted fit of check 14 over the snapshots with every sample broken",
    ])


def fig_kappa(study: xr.Dataset, profile: str):
    """Onset study: kappa_max at fixed F against (a) the minimum gap at h/Delta = 4 and (b)
    h/Delta at gap 0.8, per seed, with the predicted first removal t*/kappa_max."""
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.8), sharey=True)
    fig.subplots_adjust(bottom=0.25, wspace=0.08)
    gap, hd, kappa, bound = (study[key].values for key in (
        "min_gap", "h_over_spacing", "kappa_max", "kappa_initial_stress_bound"))
    method = study["mass_solve"].values.astype(str)
    series = [(axes[0], np.isclose(hd, 4.0), gap, "minimum gap [L/sqrt(N)] at h/Delta = 4"),
              (axes[1], np.isclose(gap, 0.8) & (method == "truncated_cg"), hd,
               "h/Delta at gap 0.8 (truncated CG)")]
    markers = {"truncated_cg": "o", "clamped_cg": "s"}
    for ax, sel, x, label in series:
        for name, marker in markers.items():
            pick = sel & (method == name)
            if pick.any():
                ax.errorbar(x[pick], kappa[pick], yerr=bound[pick], fmt=marker, ms=5,
                            capsize=2, label=f"{name.replace('_', ' ')} masses")
        ax.axhline(1.0, color="0.5", lw=0.8, ls=":", label="perfect lattice (kappa = 1)")
        ax.axhline(1.0 / 0.40, color="C3", lw=0.8, ls="--",
                   label="source's onset 0.40 t* needs kappa = 2.5")
        label_axes(ax, label, legend={"fontsize": 7})
    axes[0].text(0.02, 0.6, "placements the mass solve accepts only\n(spec check 13.3: Shepard "
                 "field in [0.95, 1.05]);\nrefused points have no run", fontsize=7,
                 transform=axes[0].transAxes)
    axes[0].set_ylabel("kappa_max = max sigma_bar / F")
    right = axes[1].secondary_yaxis("right", functions=(lambda k: 1 / np.maximum(k, 1e-3),
                                                        lambda p: 1 / np.maximum(p, 1e-3)))
    right.set_ylabel("predicted first removal t*/kappa_max [t*]")
    a = study.attrs
    fig.suptitle(f"Drying paste: onset set by the particles' disorder (profile {profile})")
    return _caption(fig, [
        f"profile {profile}, scene {a.get('scene_name', '?')}: L = {a.get('box_length', '?')}, "
        f"F = {float(study['drying_stress'].values[0]):.3g} held, fracture off; "
        f"{study.sizes['point']} runs; error bars: the initial stress's largest shift of kappa",
        "kappa_max: " + ", ".join(f"gap {g:g} h/D {h:.3g} {m.split('_')[0]}: {k:.2f}"
                                  for g, h, m, k in zip(gap, hd, method, kappa, strict=True)),
    ])


def fig_transition(ds: xr.Dataset, profile: str):
    """Transition study: (a) m_max, (b) its fluctuation, (c) the average fragment area without
    the largest, (d) the fragmented fraction P(m_max < 1/2), against damage d per size."""
    fig, axes = plt.subplots(1, 4, figsize=(15, 4.6))
    fig.subplots_adjust(bottom=0.27, wspace=0.3)
    sizes = ds["size"].values
    keys = [("m_max", "m_max = S_max / L^2"), ("m_max_sigma", "fluctuation of m_max"),
            ("m_2", "average area without the largest / L^2"),
            ("fragmented", "P(m_max < 1/2)")]
    d_c = float(ds.attrs["d_c"])
    for colour, (k, size) in zip(_colours(sizes.size), enumerate(sizes), strict=True):
        row = ds.isel(size=k)
        used = row["n"].values > 0
        for ax, (key, _) in zip(axes, keys, strict=True):
            ax.plot(row["damage"].values[used], row[key].values[used], "o-", ms=3,
                    color=colour, label=f"L = {size:g} ({int(row['n_seeds'])} seeds)")
    for ax, (_, label) in zip(axes, keys, strict=True):
        if np.isfinite(d_c):
            ax.axvline(d_c, color="k", ls="--", lw=0.8, label=f"d_c = {d_c:.3g}")
        label_axes(ax, "damage d (removed particles / N)", label, legend={"fontsize": 7})
    a = ds.attrs

    def est(key: str) -> str:
        ci = a.get(f"{key}_ci95", [np.nan, np.nan])
        return f"{_fmt(float(a[key]))} (95% CI {_fmt(float(ci[0]))}-{_fmt(float(ci[1]))})"

    criterion = departure_note(str(a.get("fracture_stress_measure", SOURCE_MEASURE)))
    fig.suptitle(f"Drying paste: damage-to-fragmentation transition, beyond the source "
                 f"(profile {profile})")
    return _caption(fig, [
        f"profile {profile}, scenes {a.get('scenes', '?')} runs '{a.get('variant', '')}': "
        f"v_r = {float(a['drying_rate']):.3g} (paper 2.2e-05), L = "
        f"{', '.join(f'{s:g}' for s in sizes)}"
        + (f"; {criterion}" if criterion else "; the source's criterion tr(sigma)/2"),
        f"d_c (crossing of P between sizes) = {est('d_c')}; at d_c: beta/nu = "
        f"{est('beta_over_nu')}, gamma/nu = {est('gamma_over_nu')}, 1/nu = {est('one_over_nu')}",
        f"2D Ising (named by arXiv:2503.06177): beta/nu = 0.125, gamma/nu = 1.75, 1/nu = 1; "
        f"percolation 0.104, 1.79, 0.75; with {sizes.size} sizes each exponent rests on "
        f"{sizes.size} points",
    ])
