r"""Thickness sweep: does the fragment area at a given time scale as :math:`H^2`?

Dimensional analysis of the thin-layer model (spec section 10, eqs. (25)-(29)): with stress
scale :math:`\Xi \le \sigma_Y`, the fragment size obeys

.. math:: \ell^2 = \frac{\lambda + 2\mu}{\mu}\,\frac{H^2}{F/\Xi - 1}, \qquad F = v_r t,

so at a fixed time (fixed drying stress F) the fragment area :math:`\langle S\rangle \sim \ell^2`
is proportional to :math:`H^2` (the screening length :math:`\xi = H\sqrt{(\lambda+2\mu)/\mu}`
is the only length). Experiments on drying layers find the same proportionality of fragment
size to thickness. Everything else in the scene is held fixed; the initial state (positions,
masses, initial stress) is the same for every H of a seed, so the comparison is paired.

For each thickness the pooled mean area :math:`\langle S\rangle_{H,t}` over seeds is computed as
in the campaign (:func:`craquelure.drying.campaign.pooled_mean`). At every snapshot where each
thickness has every sample broken into at least two fragments (earlier, the area is the box
and says nothing about H), the exponent :math:`\beta_t` is the least-squares slope of
:math:`\log\langle S\rangle_{H,t}` against :math:`\log H`; the prediction is
:math:`\beta = 2`. The summary exponent is the mean of :math:`\beta_t` over the usable snapshots
in the last third of the run (late times, furthest from the box-limited initial stage), with
the spread of :math:`\beta_t` there.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
import xarray as xr

from craquelure.drying.campaign import pooled_mean
from craquelure.errors import CraquelureError

PREDICTED_EXPONENT = 2.0


def thickness_sweep(fragments: Mapping[float, Sequence[xr.Dataset]]) -> xr.Dataset:
    """Sweep dataset from fragment datasets grouped by layer thickness H (dims ``thickness``,
    ``time``); the snapshot times must agree across all datasets (compared on the common
    ones)."""
    if len(fragments) < 2:
        raise CraquelureError("thickness sweep: needs at least two thicknesses, got "
                              f"{sorted(fragments)}")
    by_thickness = {float(h): list(sets) for h, sets in fragments.items()}
    thicknesses = np.array(sorted(by_thickness))
    if np.any(thicknesses <= 0):
        raise CraquelureError(f"thickness sweep: thicknesses must be > 0, got {thicknesses}")
    times = None
    for sets in by_thickness.values():
        if not sets:
            raise CraquelureError("thickness sweep: a thickness has no fragment dataset")
        for ds in sets:
            t = np.round(ds["time"].values.astype(float), 9)
            times = t if times is None else np.intersect1d(times, t)
    if times is None or times.size == 0:
        raise CraquelureError("thickness sweep: the fragment datasets share no snapshot time")
    n_h, n_t = thicknesses.size, times.size
    mean = np.full((n_h, n_t), np.nan)
    se = np.full((n_h, n_t), np.nan)
    n_frag = np.zeros((n_h, n_t))
    all_broken = np.zeros((n_h, n_t), bool)
    n_seeds = np.zeros(n_h, np.int64)
    for i, h in enumerate(thicknesses):
        sets = by_thickness[h]
        # Total fragment area and count per (seed, common time): fragment_time_index re-mapped.
        total, count = np.zeros((len(sets), n_t)), np.zeros((len(sets), n_t))
        for s, ds in enumerate(sets):
            own = np.round(ds["time"].values.astype(float), 9)
            keep = np.isin(own, times)
            remap = np.full(own.size, -1)
            remap[keep] = np.searchsorted(times, own[keep])
            f_idx = remap[ds["fragment_time_index"].values.astype(np.int64)]
            sel = f_idx >= 0
            total[s] = np.bincount(f_idx[sel], weights=ds["fragment_area"].values[sel],
                                   minlength=n_t)
            count[s] = ds["n_fragments"].values[keep]
        mean[i], se[i] = pooled_mean(total, count)
        n_frag[i] = count.sum(axis=0)
        all_broken[i] = np.all(count >= 2, axis=0)
        n_seeds[i] = len(sets)
    usable = np.all(all_broken, axis=0) & np.all(np.isfinite(mean) & (mean > 0), axis=0)
    log_h = np.log(thicknesses)
    exponent = np.full(n_t, np.nan)
    for k in np.flatnonzero(usable):
        exponent[k] = np.polyfit(log_h, np.log(mean[:, k]), 1)[0]
    late = usable & (times >= times[0] + 2.0 * (times[-1] - times[0]) / 3.0)
    late_values = exponent[late]
    summary_exponent = float(np.mean(late_values)) if late_values.size else float("nan")
    spread = float(np.std(late_values, ddof=1)) if late_values.size > 1 else float("nan")
    return xr.Dataset(
        {
            "mean_area": (("thickness", "time"), mean,
                          {"long_name": "pooled mean fragment area <S>_{H,t}"}),
            "mean_area_se": (("thickness", "time"), se,
                             {"long_name": "standard error of <S>_{H,t} over seeds"}),
            "n_fragments": (("thickness", "time"), n_frag,
                            {"long_name": "fragments summed over seeds"}),
            # the rest: long names and units from craquelure.cf's table on writing
            "all_broken": (("thickness", "time"), all_broken.astype(np.int8)),
            "n_seeds": ("thickness", n_seeds),
            "usable": ("time", usable.astype(np.int8)),
            "exponent": ("time", exponent),
            "late": ("time", late.astype(np.int8)),
        },
        coords={"thickness": thicknesses, "time": times},
        attrs={"predicted_exponent": PREDICTED_EXPONENT,
               "exponent_late_mean": summary_exponent,
               "exponent_late_std": spread,
               "n_late_times": int(late.sum())},
    )
