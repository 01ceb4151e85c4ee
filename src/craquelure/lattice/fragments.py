"""Fragments: connected components of the intact-beam graph (lattice spec section 10).

Particles of one body joined by intact beams form a fragment; the largest fragment is the
main body and is excluded from the size distribution. ``n(s)`` is histogrammed on
logarithmic bins (counts divided by bin width), and its log-log slope is fitted over the
bins with at least ``min_count`` fragments (2D brittle fragmentation predicts -3/2 with a
cut-off). Only the body particles (``body == 0``) are labelled; the pad is excluded.
"""

from __future__ import annotations

import numpy as np
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
