r"""The damage-to-fragmentation transition (beyond the source), after Szatmari, Nakahara,
Kitsunezaki & Kun, arXiv:2503.06177 (2025): in a discrete-element model of shrinking layers on a
substrate a dominant piece persists up to a critical damage :math:`d_c` (damage phase), beyond which
the layer breaks into many pieces (fragmentation phase), a continuous transition with finite-size
scaling of the largest and the average fragment.

Per sample s and snapshot t of each box size L (fragment datasets of
:mod:`craquelure.drying.analysis`, measures of :mod:`craquelure.drying.crack_measures`):
damage :math:`d` (removed particles / N), :math:`m_{max} = S_{max}/L^2`, and the average
fragment area without the largest, :math:`m_2 = \sum' S^2 / (L^2 \sum' S)` (0 when the largest
is the only fragment; the second-moment average of percolation's mean cluster size).
Records are binned in d (common bins for all sizes) and per bin and size: the mean of
:math:`m_{max}`, its sample-to-sample fluctuation
:math:`\sigma_m = \sqrt{\langle m_{max}^2\rangle - \langle m_{max}\rangle^2}`, the mean of
:math:`m_2`, and the fraction of fragmented records :math:`P = P(m_{max} < 1/2)`.

Finite-size scaling [D], with sizes :math:`L_1 < \dots < L_k`:

- :math:`d_c`: the crossing of :math:`P_L(d)` between sizes (P is scale invariant at the
  critical point; linear interpolation between bins; mean over pairs of sizes);
- at :math:`d_c`: :math:`m_{max} \propto L^{-\beta/\nu}`, :math:`m_2 L^2 \propto L^{\gamma/\nu}`
  (a cluster-size moment in units of area), :math:`dP/dd \propto L^{1/\nu}` (slope of P at the
  transition: a line through the bins with 0.15 <= P <= 0.85): exponents as log-log slopes
  over the sizes;
- 95 % intervals from a bootstrap over samples (within each size, whole samples).

The slope of P needs the transition to span bins: it underestimates :math:`1/\nu` once the
largest size's transition is narrower than about two bins.

The validation rows (:mod:`craquelure.drying.claims`) compare the exponents with the 2D Ising
values the paper's abstract says they agree with "to a reasonable accuracy" (:data:`ISING`)
and with 2D percolation's (:data:`PERCOLATION`); its own fitted values and :math:`d_c` are not
in the sources available to us."""

from __future__ import annotations

import itertools
import math
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
import xarray as xr

from craquelure.validation import bootstrap_interval

N_BINS = 12
N_BOOT = 200
BOOT_SEED = 20250308
FRAGMENTED_BELOW = 0.5  # m_max below this: the record is in the fragmentation phase
SLOPE_BAND = (0.15, 0.85)  # P range whose line gives dP/dd at the transition
ISING = {"beta_over_nu": 1 / 8, "gamma_over_nu": 7 / 4, "one_over_nu": 1.0}
PERCOLATION = {"beta_over_nu": 5 / 48, "gamma_over_nu": 43 / 24, "one_over_nu": 3 / 4}
PAPER_URL = "https://arxiv.org/html/2503.06177v2"


def sample_records(fragments: xr.Dataset) -> dict[str, np.ndarray]:
    """d, m_max and m_2 per snapshot of one fragment dataset (dim time)."""
    length = float(fragments.attrs["box_length"])
    area = fragments["fragment_area"].values
    index = fragments["fragment_time_index"].values
    n_t = fragments.sizes["time"]
    m_max, m_2 = np.zeros((2, n_t))
    order = np.lexsort((area, index))  # by snapshot, then size
    area, index = area[order], index[order]
    bounds = np.searchsorted(index, np.arange(n_t + 1))
    for k in range(n_t):
        a = area[bounds[k]:bounds[k + 1]]
        if a.size:
            m_max[k] = a[-1] / length**2
            rest = a[:-1]
            m_2[k] = float(np.sum(rest**2) / np.sum(rest) / length**2) if rest.size else 0.0
    return {"damage": fragments["damage"].values.astype(float), "m_max": m_max, "m_2": m_2}


def _binned(records: Sequence[dict[str, np.ndarray]], edges: np.ndarray) -> dict[str, np.ndarray]:
    d, m, m2 = (np.concatenate([r[key] for r in records]) for key in ("damage", "m_max", "m_2"))
    k = np.clip(np.digitize(d, edges) - 1, 0, edges.size - 2)
    n = np.bincount(k, minlength=edges.size - 1).astype(float)

    def per_bin(values: np.ndarray) -> np.ndarray:  # mean over each bin's records
        return np.bincount(k, values, edges.size - 1) / n

    with np.errstate(invalid="ignore", divide="ignore"):
        mean = per_bin(m)
        return {"n": n, "m_max": mean,
                "m_max_sigma": np.sqrt(np.maximum(per_bin(m**2) - mean**2, 0.0)),
                "m_2": per_bin(m2), "fragmented": per_bin((m < FRAGMENTED_BELOW).astype(float)),
                "damage": per_bin(d)}


def _crossing(x: np.ndarray, a: np.ndarray, b: np.ndarray) -> float:
    """First d where curve b - a changes sign (linear interpolation between the bins where
    the curves differ: where both are 0, or both 1, they do not cross; NaN if none)."""
    ok = np.isfinite(x) & np.isfinite(a) & np.isfinite(b) & (a != b)
    x, diff = x[ok], (b - a)[ok]
    for i in range(x.size - 1):
        if diff[i] * diff[i + 1] < 0:
            return float(x[i] - diff[i] * (x[i + 1] - x[i]) / (diff[i + 1] - diff[i]))
    return float("nan")


def _at(x: np.ndarray, y: np.ndarray, x0: float) -> float:
    ok = np.isfinite(x) & np.isfinite(y)
    inside = math.isfinite(x0) and ok.sum() >= 2 and x[ok][0] <= x0 <= x[ok][-1]
    return float(np.interp(x0, x[ok], y[ok])) if inside else float("nan")


def _slope_at(x: np.ndarray, y: np.ndarray, x0: float) -> float:
    """Slope of P(d) through the transition: least squares over the bins with P inside
    SLOPE_BAND (a band in P, so the same part of the curve at every size: the bias of a line
    through a sigmoid is the same factor for every width, and cancels in the exponent); the
    secant of the bins around x0 if fewer than 3 bins lie in the band."""
    ok = np.flatnonzero(np.isfinite(x) & np.isfinite(y))
    if not math.isfinite(x0) or ok.size < 2:
        return float("nan")
    band = ok[(y[ok] >= SLOPE_BAND[0]) & (y[ok] <= SLOPE_BAND[1])]
    if band.size >= 3:
        return float(np.polyfit(x[band], y[band], 1)[0])
    i = int(np.clip(np.searchsorted(x[ok], x0) - 1, 0, ok.size - 2))
    a, b = ok[i], ok[i + 1]
    return float((y[b] - y[a]) / (x[b] - x[a]))


def _log_slope(lengths: np.ndarray, values: np.ndarray) -> float:
    ok = np.isfinite(values) & (values > 0)
    return (float(np.polyfit(np.log(lengths[ok]), np.log(values[ok]), 1)[0]) if ok.sum() >= 2
            else float("nan"))


def scaling(lengths: np.ndarray, curves: Sequence[dict[str, np.ndarray]]) -> dict[str, float]:
    """d_c and the exponents from binned curves of each size (module docstring)."""
    crossings = [_crossing(curves[i]["damage"], curves[i]["fragmented"],
                           curves[j]["fragmented"])
                 for i, j in itertools.combinations(range(len(curves)), 2)]
    crossings = [c for c in crossings if math.isfinite(c)]
    d_c = float(np.mean(crossings)) if crossings else float("nan")
    m_max, m_2 = (np.array([_at(c["damage"], c[key], d_c) for c in curves])
                  for key in ("m_max", "m_2"))
    slope = np.array([_slope_at(c["damage"], c["fragmented"], d_c) for c in curves])
    return {"d_c": d_c, "beta_over_nu": -_log_slope(lengths, m_max),
            "gamma_over_nu": _log_slope(lengths, m_2 * lengths**2),
            "one_over_nu": _log_slope(lengths, slope)}


def transition(fragments: Mapping[str, Sequence[xr.Dataset]], variant: str = "",
               n_bins: int = N_BINS, n_boot: int = N_BOOT) -> xr.Dataset:
    """The transition dataset (dims ``size``, ``bin``) from fragment datasets grouped by scene
    (one box size per scene), with d_c and the exponents and their bootstrap intervals."""
    from craquelure.drying.analysis import run_scene  # the run's modules: not for the claims

    groups = sorted(((float(ds[0].attrs["box_length"]), name, [sample_records(f) for f in ds],
                      ds) for name, ds in fragments.items()), key=lambda g: g[0])
    if len(groups) < 2:
        raise ValueError(f"the transition needs >= 2 box sizes, got {len(groups)}")
    lengths = np.array([g[0] for g in groups])
    if np.unique(lengths).size != lengths.size:
        raise ValueError(f"the transition's scenes need distinct box sizes, got {lengths}")
    d_all = np.concatenate([r["damage"] for g in groups for r in g[2]])
    edges = np.linspace(0.0, float(np.nanmax(d_all)) * (1 + 1e-9), n_bins + 1)
    curves = [_binned(g[2], edges) for g in groups]
    point = scaling(lengths, curves)
    rng = np.random.default_rng(BOOT_SEED)  # whole samples, within each size
    boot = [scaling(lengths, [_binned([g[2][i] for i in rng.integers(0, len(g[2]), len(g[2]))],
                                      edges) for g in groups]) for _ in range(n_boot)]
    names = {"n": ("records (sample x snapshot) in the bin", "1"),
             "damage": ("mean damage d of the bin's records", "1"),
             "m_max": ("mean largest-fragment fraction m_max = S_max/L^2", "1"),
             "m_max_sigma": ("sample-to-sample fluctuation of m_max", "1"),
             "m_2": ("average fragment area without the largest, sum' S^2/(L^2 sum' S)", "1"),
             "fragmented": ("fraction of records with m_max < 1/2", "1")}
    data: dict[str, Any] = {
        key: (("size", "bin"), np.stack([c[key] for c in curves]),
              {"long_name": long_name, "units": units})
        for key, (long_name, units) in names.items()}
    data["n_seeds"] = ("size", np.array([len(g[2]) for g in groups]),
                       {"long_name": "samples per size", "units": "1"})
    ds = xr.Dataset(data, coords={
        "size": ("size", lengths, {"long_name": "box side L", "units": "length"}),
        "bin": ("bin", np.arange(n_bins)),
        "damage_lo": ("bin", edges[:-1], {"long_name": "bin's lower damage", "units": "1"}),
        "damage_hi": ("bin", edges[1:], {"long_name": "bin's upper damage", "units": "1"})})
    for key, value in point.items():
        values = np.array([b[key] for b in boot])
        values = values[np.isfinite(values)]
        ds.attrs[key] = value
        ds.attrs[f"{key}_ci95"] = (bootstrap_interval(values) if values.size >= 10
                                   else [math.nan, math.nan])
        ds.attrs[f"{key}_n_bootstrap"] = int(values.size)
    first = groups[0][3][0]
    scene = run_scene(first)
    ds.attrs.update({
        "scenes": ",".join(g[1] for g in groups), "variant": variant,
        "fragmented_below": FRAGMENTED_BELOW, "n_bootstrap": n_boot,
        "fracture_stress_measure": str(first.attrs.get("fracture_stress_measure", "half_trace")),
        "drying_rate": float(scene.get("material.drying_rate")),
        "yield_stress": float(scene.get("material.yield_stress")), "reference": PAPER_URL,
        "ising_exponents": ", ".join(f"{k} = {v:.4g}" for k, v in ISING.items()),
        "percolation_exponents": ", ".join(f"{k} = {v:.4g}" for k, v in PERCOLATION.items()),
    })
    return ds
