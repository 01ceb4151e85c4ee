r"""Drying-speed study: how far is each profile from the paper's regime, and do its statistics
converge toward the paper's as the drying slows down?

The dimensionless drying speed is :math:`\Pi = \tau/t^*` with the Voigt shear retardation time
:math:`\tau = \eta/(2\mu)` and :math:`t^* = \sigma_Y/v_r` (paper: :math:`\Pi = 5/227.3 =
0.022`). Each speed is a campaign of the same scene with :math:`v_r = \Pi\sigma_Y/\tau`,
snapshots at fixed fractions of :math:`t^*`. Per speed, in units of :math:`t^*` and each with
its 95 % bootstrap interval over seeds (:mod:`craquelure.drying.ensemble`'s checks 16 and 14):

- onset: earliest and median first removal, first / half / all samples broken (>= 2 fragments);
- the 1/t law over the snapshots with every sample broken: :math:`t_0/t^*` and :math:`b/b^*`
  (:math:`b^* = \mu v_r/((\lambda+2\mu)H^2\sigma_Y)`);
- fragments per unit area at fixed :math:`t/t^*` (the snapshot nearest to it; bootstrap over
  seeds of the mean count divided by :math:`L^2`).

The paper's values for comparison (source: fragments from 0.40 t*, all samples broken before
0.8 t*; dimensional analysis: :math:`t_0 \le t^*`) are attributes of the dataset."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
import xarray as xr

from craquelure.drying import ensemble
from craquelure.drying.campaign import build_campaign, per_sample_totals
from craquelure.drying.summary import b_star_of
from craquelure.drying.time_scales import broken_from, drying_number
from craquelure.errors import CraquelureError
from craquelure.scene import Scene
from craquelure.validation import bootstrap_interval

ONSET_ITEMS = ("first_removal_earliest", "first_removal_median", "first_sample_broken",
               "half_samples_broken", "all_samples_broken")
PAPER = {"paper_pi": 0.022, "paper_first_broken_over_t_star": 0.40,
         "paper_all_broken_over_t_star": 0.8, "paper_t0_over_t_star_max": 1.0}
ENDS = ("", "_lo", "_hi")  # a value and its 95 % bootstrap interval
N_BOOT = 1000
SEED = 20261201


def speed_run_settings(scene: Scene, pi: float, end_over_t_star: float,
                       times_over_t_star: Sequence[float]) -> dict[str, Any]:
    r"""Settings of the drying-speed run of ``scene`` at :math:`\Pi`: :math:`\tau =
    \eta/(2\mu)`, :math:`t^* = \tau/\Pi`, the drying rate :math:`v_r = \Pi\sigma_Y/\tau`, the
    end ``end_over_t_star`` :math:`t^*` and the snapshots at the fractions
    ``times_over_t_star`` of :math:`t^*` up to that end. ``set`` holds the three as scene
    overrides (6 significant digits), what the run applies (``craquelure run --set-file``)."""
    tau = scene.get("material.eta") / (2.0 * scene.get("material.lame_mu"))
    sigma_y = scene.get("material.yield_stress")
    t_star = tau / pi
    times = [f * t_star for f in times_over_t_star if f <= end_over_t_star * (1 + 1e-9)]
    rate, t_end = pi * sigma_y / tau, end_over_t_star * t_star
    return {
        "pi": pi, "tau": tau, "t_star": t_star, "drying_rate": rate, "t_end": t_end,
        "times": times,
        "set": [f"material.drying_rate={rate:.6g}", f"outputs.t_end={t_end:.6g}",
                f"outputs.times=[{', '.join(f'{t:.6g}' for t in times)}]"],
    }


def _one_speed(fragments: Sequence[xr.Dataset], fixed: np.ndarray, n_boot: int
               ) -> dict[str, float]:
    campaign = build_campaign(list(fragments), window_mode="all_broken")
    a = campaign.attrs
    pi = drying_number(a)
    tstar = pi["t_star"]
    times = campaign["time"].values.astype(float)
    out: dict[str, float] = {"pi": pi["pi"], "t_star": tstar,
                             "drying_rate": float(a["drying_rate"]),
                             "n_seeds": campaign.sizes["seed"]}
    onset = ensemble.check_onset(times, campaign["n_fragments"].values,
                               campaign["first_removal_time"].values, tstar, pi["pi"], n_boot)
    for item in ONSET_ITEMS:
        v = onset[item]
        for end, value in zip(ENDS, (v["over_t_star"], *v["ci95_over_t_star"]), strict=True):
            out[item + end] = np.nan if value is None else value
    b_star = b_star_of(a)
    seeds = campaign["seed"].values
    total, count = per_sample_totals(campaign)
    window = broken_from(campaign["n_fragments"].values)
    fit = ensemble.check_inverse_area(times[window], total[:, window], count[:, window], tstar,
                                    b_star, n_boot, n_power=200)
    for key, value, ci, scale in (("t0_over_t_star", "x_intercept_t0", "t0_ci95", tstar),
                                  ("b_over_b_star", "slope_b", "slope_b_ci95", b_star)):
        out[key] = fit[value] / scale if "error" not in fit else np.nan
        bounds = fit.get(ci) or [np.nan, np.nan]
        out[f"{key}_lo"], out[f"{key}_hi"] = (v / scale for v in bounds)
    rng = np.random.default_rng(SEED)
    picks = rng.integers(0, seeds.size, size=(n_boot, seeds.size))
    area_box = float(a["box_length"]) ** 2
    density = np.full((3, fixed.size), np.nan)
    for j, f in enumerate(fixed):
        k = int(np.argmin(np.abs(times / tstar - f)))
        if abs(times[k] / tstar - f) > 0.05 * f:
            continue  # no snapshot near this t/t*
        per_seed = count[:, k] / area_box
        boot = per_seed[picks].mean(axis=1)
        density[:, j] = per_seed.mean(), *bootstrap_interval(boot)
    out.update({f"fragments_per_area{end}": row for end, row in zip(ENDS, density, strict=True)})
    return out


def speed_study(fragments: Mapping[Any, Sequence[xr.Dataset]],
                fixed_over_t_star: Sequence[float], n_boot: int = N_BOOT) -> xr.Dataset:
    """Study dataset (dims ``speed``, ``fixed_time``) from fragment datasets grouped by drying speed
    (any key; each group one campaign: same scene, its own seeds; Pi is read from the data)."""
    if len(fragments) < 2:
        raise CraquelureError(f"speed study: needs at least two drying speeds, got "
                              f"{sorted(fragments)}")
    fixed = np.asarray(fixed_over_t_star, float)
    rows = [_one_speed(sets, fixed, n_boot) for sets in fragments.values()]
    rows.sort(key=lambda r: r["pi"])
    long = {"t_star": "t* = sigma_Y/v_r", "drying_rate": "drying rate v_r",
            "n_seeds": "samples (seeds)", "t0_over_t_star": "x-intercept t0 of 1/<S>_t, in t*",
            "b_over_b_star": "slope b of 1/<S>_t, in b*",
            "fragments_per_area": "mean fragments per unit area at fixed t/t*"}
    bound = {"_lo": " (2.5 % bootstrap)", "_hi": " (97.5 % bootstrap)"}
    data = {}
    for key in (k for k in rows[0] if k != "pi"):
        base = key.removesuffix("_lo").removesuffix("_hi")
        attrs = {"long_name": long.get(base, base.replace("_", " ") + ", in t*")
                 + bound.get(key[len(base):], "")}
        if base == "fragments_per_area":
            data[key] = (("speed", "fixed_time"), np.stack([r[key] for r in rows]),
                         {**attrs, "units": "1/length^2"})
        else:
            data[key] = ("speed", np.array([r[key] for r in rows], float), attrs)
    return xr.Dataset(
        data,
        coords={"speed": np.array([r["pi"] for r in rows], float), "fixed_time": fixed},
        attrs={**PAPER, "n_bootstrap": n_boot},
    )
