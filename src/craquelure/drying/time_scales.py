r"""Time scales of the drying analysis (drying spec sections 10 and 13): the paper's
constants, :math:`t^*`, :math:`\Pi` and the statistics windows of a campaign.

**Time in units of** :math:`t^* = \sigma_Y/v_r`. The paper's windows are stated in its own time
(Table I: :math:`t^* = 5\cdot10^{-3}/2.2\cdot10^{-5} = 227.3`): initial stage
:math:`t \lesssim 150`, fit and collapse window :math:`t \in [180, 300]`, collapse times
:math:`t_k \in \{180, 200, \dots, 300\}`, x-intercept of the linear fit in [50, 230]. By the
dimensional analysis (spec section 10) the drying stress :math:`v_r t` is what sets the
time scale, so in window mode ``paper`` every window is rescaled by :math:`t^*/t^*_{paper}`
[D]. That rescaling does not hold when drying is much faster than the paper's: the shear
retardation time :math:`\tau = \eta/(2\mu) = 5` (Voigt) is then no longer small against
:math:`t^*`: :math:`\Pi = \tau/t^*` is 0.022 in the paper and 0.66 at 30x its rate, where the
crack network forms later in units of :math:`t^*`. Every summary and caption states the run's
:math:`\Pi` (:func:`drying_number`). The faster profiles therefore use window mode ``all_broken``
[D], the paper's own definition of the end of the initial stage ("when some samples are still
unbroken"): the window runs from the first snapshot from which on every sample has at least two
fragments to the last snapshot, and the collapse times :math:`t_k` are 7 snapshots evenly spread
over it. The mode and the window are attributes of the campaign dataset (:func:`campaign_window`),
so the statistics and the figures read one decision; the summary and every caption state it."""

from __future__ import annotations

from typing import Any

import numpy as np
import xarray as xr

from craquelure.errors import CraquelureError

# Paper (Table I, spec section 1) and its time windows (spec sections 10 and 13).
PAPER_YIELD_STRESS = 5.0e-3
PAPER_DRYING_RATE = 2.2e-5
PAPER_WINDOW = (180.0, 300.0)
PAPER_INITIAL_STAGE_END = 150.0
PAPER_COLLAPSE_TIMES = tuple(float(t) for t in range(180, 301, 20))


def paper_t_star() -> float:
    return PAPER_YIELD_STRESS / PAPER_DRYING_RATE


def t_star(scene_or_attrs: Any) -> float:
    """:math:`\\sigma_Y / v_r` of a scene or of a dataset's attributes."""
    if hasattr(scene_or_attrs, "get") and hasattr(scene_or_attrs, "has"):
        return (float(scene_or_attrs.get("material.yield_stress"))
                / float(scene_or_attrs.get("material.drying_rate")))
    return float(scene_or_attrs["yield_stress"]) / float(scene_or_attrs["drying_rate"])


def drying_number(attrs: Any) -> dict[str, float | None]:
    r""":math:`\tau = \eta/(2\mu)` (Voigt shear retardation time), :math:`t^*` and
    :math:`\Pi = \tau/t^*` of a campaign's attributes (paper: 5, 227.3, 0.022); None where the
    dataset predates the viscosity attribute."""
    tstar = t_star(attrs)
    tau = (float(attrs["viscosity"]) / (2.0 * float(attrs["lame_mu"]))
           if "viscosity" in attrs else None)
    return {"tau": tau, "t_star": tstar, "pi": None if tau is None else tau / tstar,
            "pi_paper": paper_pi()}


PAPER_RETARDATION_TIME = 1.0 / (2.0 * 0.1)  # eta/(2 mu), Table I


def paper_pi() -> float:
    return PAPER_RETARDATION_TIME / paper_t_star()


def time_scale(tstar: float) -> float:
    """Factor from the paper's times to this campaign's times."""
    return tstar / paper_t_star()


def collapse_times(times: np.ndarray, tstar: float) -> np.ndarray:
    """Snapshot times nearest to the rescaled :math:`t_k` (within half a snapshot interval)."""
    times = np.asarray(times, float)
    if times.size == 0:
        return times
    spacing = np.min(np.diff(times)) if times.size > 1 else np.inf
    chosen = []
    for target in np.asarray(PAPER_COLLAPSE_TIMES) * time_scale(tstar):
        k = int(np.argmin(np.abs(times - target)))
        if abs(times[k] - target) <= 0.5 * spacing + 1e-9 and times[k] not in chosen:
            chosen.append(times[k])
    return np.asarray(chosen)


def broken_from(n_fragments: np.ndarray) -> np.ndarray:
    """Mask of the snapshots from which on every sample (dim 0) has >= 2 fragments."""
    return holds_from(np.all(np.asarray(n_fragments) >= 2, axis=0))


def holds_from(flags: np.ndarray) -> np.ndarray:
    """Mask of the positions from which on every flag is true."""
    return np.flip(np.logical_and.accumulate(np.flip(np.asarray(flags, bool))))


WINDOW_MODES = ("paper", "all_broken")
N_COLLAPSE_TIMES = len(PAPER_COLLAPSE_TIMES)


def campaign_window(times: np.ndarray, n_fragments: np.ndarray, tstar: float,
                    mode: str = "paper") -> dict[str, Any]:
    """The statistics window of a campaign: bounds, initial-stage end, collapse times and the
    mask of snapshots inside. ``n_fragments`` has dims (seed, time)."""
    times = np.asarray(times, float)
    if mode == "paper":
        lo, hi = (t * time_scale(tstar) for t in PAPER_WINDOW)
        initial_end = PAPER_INITIAL_STAGE_END * time_scale(tstar)
        tk = collapse_times(times, tstar)
        description = (f"the paper's windows (fit/collapse t in [{PAPER_WINDOW[0]:g}, "
                       f"{PAPER_WINDOW[1]:g}], initial stage t < {PAPER_INITIAL_STAGE_END:g}) "
                       f"rescaled by t*/t*_paper = {time_scale(tstar):.4g}")
    elif mode == "all_broken":
        stays = broken_from(n_fragments)
        if stays.any():
            k0 = int(np.argmax(stays))
            lo, hi = float(times[k0]), float(times[-1])
            inside = np.arange(k0, times.size)
            pick = np.unique(np.linspace(0, inside.size - 1, N_COLLAPSE_TIMES).astype(int))
            tk = times[inside[pick]]
        else:
            lo = hi = float("nan")
            tk = np.zeros(0)
        initial_end = lo
        description = ("window from the first snapshot from which on every sample has >= 2 "
                       "fragments to the last snapshot (the paper's end of the initial stage; "
                       "its rescaled window does not apply at this drying rate)")
    else:
        raise CraquelureError(f"window mode {mode!r} is not allowed; allowed values: "
                              f"{', '.join(WINDOW_MODES)}")
    # Snapshots are taken at the first step past the requested time (within half a step),
    # so the bounds get a tolerance of 0.1 % of the window length (NaN bounds: no snapshot).
    tol = 1e-3 * max(hi - lo, 1e-12)
    mask = (times >= lo - tol) & (times <= hi + tol)
    return {"mode": mode, "start": float(lo), "end": float(hi),
            "initial_stage_end": float(initial_end), "collapse_times": np.asarray(tk, float),
            "mask": mask, "description": description}


def window_of(campaign: xr.Dataset) -> dict[str, Any]:
    """The window recorded in a campaign dataset (mode ``paper`` for older files)."""
    times = campaign["time"].values.astype(float)
    return campaign_window(times, campaign["n_fragments"].values, float(campaign.attrs["t_star"]),
                           str(campaign.attrs.get("window_mode", "paper")))
