r"""Fragments: connected components of the intact-beam graph (lattice spec section 10).

Particles of one body joined by intact beams form a fragment; the largest fragment is the
main body and is excluded from the size distribution. ``n(s)`` is histogrammed on
logarithmic bins (counts divided by bin width), and its log-log slope is fitted over the
bins with at least ``min_count`` fragments (2D brittle fragmentation predicts -3/2 with a
cut-off). Only the body particles (``body == 0``) are labelled; the pad is excluded.

Decision [D]: the spec's form is a power law with an exponential cut-off, :math:`n(s) \propto
s^{-\tau} e^{-s/s_*}`. A straight line through log-binned counts ignores the cut-off (the last bins
steepen it) and weights the sparse large-size bins like the full small-size ones, so with a few
hundred fragments it is biased steep. :func:`fit_cutoff_power_law` fits both parameters by maximum
likelihood of the discrete distribution on s >= s_min (Clauset, Shalizi & Newman 2009, with the
cut-off); the binned slope is still reported next to it.
"""

import math

import numpy as np
from scipy.optimize import minimize
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components


def label(n: int, bi: np.ndarray, bj: np.ndarray, intact: np.ndarray,
          include: np.ndarray | None = None) -> np.ndarray:
    """Fragment label per particle (-1 for excluded particles), labels 0..k-1."""
    include = np.ones(n, bool) if include is None else include.astype(bool)
    keep = intact.astype(bool) & include[bi] & include[bj]
    graph = coo_matrix((np.ones(keep.sum()), (bi[keep], bj[keep])), shape=(n, n))
    _, labels = connected_components(graph, directed=False)
    labels = labels.astype(np.int64)
    labels[~include] = -1
    _, dense = np.unique(labels[include], return_inverse=True)
    labels[include] = dense
    return labels


def sizes(labels: np.ndarray) -> np.ndarray:
    """Fragment sizes (particles), largest first; sum equals the labelled particle count."""
    lab = labels[labels >= 0]
    return np.sort(np.bincount(lab))[::-1] if lab.size else np.zeros(0, np.int64)


def size_distribution(frag_sizes: np.ndarray, bins_per_decade: int = 4):
    """(bin centres, n(s) per unit size, counts) of the fragments without the main body."""
    s = np.asarray(frag_sizes)[1:]
    if s.size == 0:
        return np.zeros(0), np.zeros(0), np.zeros(0, np.int64)
    top = max(float(s.max()), 1.0)
    edges = np.logspace(-0.01, np.log10(top) + 0.01 + 1.0 / bins_per_decade,
                        int(np.ceil((np.log10(top) + 0.02) * bins_per_decade)) + 2)
    counts, _ = np.histogram(s, edges)
    centres = np.sqrt(edges[1:] * edges[:-1])
    return centres, counts / np.diff(edges), counts


def fit_slope(centres, density, counts, min_count: int = 2) -> tuple[float, float]:
    """Log-log slope of n(s) over bins with >= min_count fragments, and the decades spanned."""
    sel = counts >= min_count
    if sel.sum() < 2:
        return float("nan"), 0.0
    b = np.polyfit(np.log10(centres[sel]), np.log10(density[sel]), 1)[0]
    return float(b), float(np.log10(centres[sel].max() / centres[sel].min()))


def fit_cutoff_power_law(frag_sizes, s_min: int = 1, min_fragments: int = 10
                         ) -> tuple[float, float]:
    """Maximum-likelihood (tau, s_*) of p(s) = s^-tau exp(-s/s_*) / Z on s >= s_min (integer
    sizes, Z summed to 50 max(s)); (nan, nan) below ``min_fragments`` fragments. Pass the
    sizes without the main body."""
    s = np.asarray(frag_sizes, dtype=np.float64)
    s = s[s >= s_min]
    if s.size < min_fragments:
        return math.nan, math.nan
    grid = np.arange(s_min, max(50.0 * s.max(), 1000.0) + 1.0)
    log_grid = np.log(grid)
    sum_log, sum_s = float(np.log(s).sum()), float(s.sum())

    def nll(params):
        tau, log_cut = params
        cut = math.exp(log_cut)
        logw = -tau * log_grid - grid / cut
        top = logw.max()
        log_z = top + math.log(np.exp(logw - top).sum())
        return tau * sum_log + sum_s / cut + s.size * log_z

    start = (1.5, math.log(max(3.0 * s.mean(), 2.0)))
    res = minimize(nll, start, method="Nelder-Mead",
                   options={"xatol": 1e-6, "fatol": 1e-9, "maxiter": 4000})
    return float(res.x[0]), float(math.exp(res.x[1]))
