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
the spread of :math:`\beta_t` there."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from functools import reduce

import numpy as np
import xarray as xr

from craquelure.drying.campaign import pooled_mean
from craquelure.errors import CraquelureError

PREDICTED_EXPONENT = 2.0


def _times(ds: xr.Dataset) -> np.ndarray:
    return np.round(ds["time"].values.astype(float), 9)


def _totals_at(ds: xr.Dataset, times: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Total fragment area and count of one sample at ``times`` (a subset of its own)."""
    own = _times(ds)
    keep = np.isin(own, times)
    remap = np.full(own.size, -1)
    remap[keep] = np.searchsorted(times, own[keep])
    index = remap[ds["fragment_time_index"].values.astype(np.int64)]
    sel = index >= 0
    total = np.bincount(index[sel], weights=ds["fragment_area"].values[sel], minlength=times.size)
    return total, ds["n_fragments"].values[keep]


def thickness_sweep(fragments: Mapping[float, Sequence[xr.Dataset]]) -> xr.Dataset:
    """Sweep dataset from fragment datasets grouped by layer thickness H (dims ``thickness``,
    ``time``); the snapshot times must agree across all datasets (compared on the common ones)."""
    if len(fragments) < 2:
        raise CraquelureError("thickness sweep: needs at least two thicknesses, got "
                              f"{sorted(fragments)}")
    by_thickness = {float(h): list(sets) for h, sets in fragments.items()}
    thicknesses = np.array(sorted(by_thickness))
    if np.any(thicknesses <= 0):
        raise CraquelureError(f"thickness sweep: thicknesses must be > 0, got {thicknesses}")
    if not all(by_thickness.values()):
        raise CraquelureError("thickness sweep: a thickness has no fragment dataset")
    times = reduce(np.intersect1d, (_times(ds) for sets in by_thickness.values() for ds in sets))
    if times.size == 0:
        raise CraquelureError("thickness sweep: the fragment datasets share no snapshot time")
    # (seed, total area / count, common time) per thickness
    totals = [np.array([_totals_at(ds, times) for ds in by_thickness[h]]) for h in thicknesses]
    mean, se = np.array([pooled_mean(t[:, 0], t[:, 1]) for t in totals]).transpose(1, 0, 2)
    n_frag = np.array([t[:, 1].sum(axis=0) for t in totals])
    all_broken = np.array([np.all(t[:, 1] >= 2, axis=0) for t in totals])
    n_seeds = np.array([len(t) for t in totals], np.int64)
    usable = np.all(all_broken, axis=0) & np.all(np.isfinite(mean) & (mean > 0), axis=0)
    log_h = np.log(thicknesses)
    exponent = np.full(times.size, np.nan)
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
            "n_seeds": ("thickness", n_seeds), "usable": ("time", usable.astype(np.int8)),
            "exponent": ("time", exponent), "late": ("time", late.astype(np.int8)),
        },
        coords={"thickness": thicknesses, "time": times},
        attrs={"predicted_exponent": PREDICTED_EXPONENT, "exponent_late_mean": summary_exponent,
               "exponent_late_std": spread, "n_late_times": int(late.sum())},
    )
