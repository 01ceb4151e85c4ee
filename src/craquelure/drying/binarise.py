r"""Binarisation of a drying-paste snapshot (drying spec section 9).

The paste indicator is the SPH Shepard field on a periodic square mesh of spacing :math:`\Delta x`:

.. math:: \phi(\mathbf x) = \sum_J \frac{m_J}{\rho_J}\, W(|\mathbf x - \mathbf r_J|; h),

summed over the particles still alive, and a mesh point is paste (pixel 1) where
:math:`\phi \ge \phi_0` (paper: :math:`\phi_0 = 0.8`, :math:`\Delta x = 0.01 h`), crack (0)
otherwise. The image is :func:`craquelure.drying.field.mesh_image`: the direct sum (neighbour
search), not the FFT deposition the spec also allows [D: exact].

Edge bias: at a straight free edge of uniform paste :math:`\phi` falls to 1/2, and reaches
:math:`\phi_0` only a depth :math:`d^*` inside the material, with

.. math:: \phi(d) = \tfrac12 + \int_0^d w_1(u)\,du, \qquad
          w_1(u) = \int_{-\infty}^{\infty} W\big(\sqrt{u^2 + v^2}; h\big)\, dv,

so every crack looks :math:`2 d^*` wider than the particle-free band and every fragment loses
about perimeter x :math:`d^*`. :func:`edge_depth` computes :math:`d^*` by quadrature
(0.199 h for the quintic kernel and :math:`\phi_0 = 0.8`).

Fragments (spec section 9): a fragment is a 4-connected component of paste pixels of the
periodic image. scikit-image labels the components of the image as a plain rectangle
(``skimage.measure.label``, ``connectivity=1``), then the labels of facing edge pixels (column
0 with column n-1, row 0 with row n-1) are joined (connected components of the graph of
facing labels, ``scipy.sparse.csgraph``), so a fragment cut by one edge, or by both (a blob
around a corner), counts once. Pixels touching only diagonally are separate fragments
(4-connectivity), across the edges as well. The area of a fragment is its pixel count times
:math:`\Delta x^2`; no minimum size is applied [D, spec section 9] (the summary reports the
sensitivity to :math:`S_{min} = \pi h^2` separately)."""

from __future__ import annotations

from functools import cache

import numpy as np
import xarray as xr
from scipy import integrate, optimize
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from skimage.measure import label as sk_label

from craquelure.drying.field import mesh_image, mesh_spacing
from craquelure.sph.kernels import w as kernel_w


def snapshot_image(run: xr.Dataset, time_index: int, spacing_h: float, phi0: float,
                   kernel: str) -> tuple[np.ndarray, float]:
    """Paste image of snapshot ``time_index`` of a run dataset (the live particles,
    :math:`V_J = m_J/\\rho_J` at that time), and the mesh spacing used (``spacing_h``,
    ``phi0``, ``kernel``: the scene's, :func:`.analysis.analyse_run`)."""
    snap = run.isel(time=time_index)
    h = float(run.attrs["h"])
    length = float(run.attrs["box_length"])
    spacing = mesh_spacing(length, spacing_h * h)
    alive = snap["alive"].values.astype(bool)
    volume = snap["mass"].values / snap["rho"].values
    image = mesh_image(snap["x"].values, snap["y"].values, np.where(alive, volume, 0.0), length,
                       h, spacing, kernel, phi0, active=alive)
    return image, spacing


@cache
def edge_depth(phi0: float, kernel: str, h: float) -> float:
    """Depth :math:`d^*` inside a straight free edge of uniform paste where
    :math:`\\phi = \\phi_0` (module docstring), in the units of ``h``."""
    if not 0.5 < phi0 < 1.0:
        raise ValueError(f"phi0 must lie in (0.5, 1) for an edge depth, got {phi0}")

    def marginal(u: float) -> float:
        if u >= 1.0:
            return 0.0
        top = np.sqrt(1.0 - u * u)
        value, _ = integrate.quad(lambda v: float(kernel_w(kernel, np.hypot(u, v), 1.0)[()]),
                                  -top, top, epsabs=1e-13, epsrel=1e-12, limit=200,
                                  points=[0.0])
        return value

    def phi(d: float) -> float:
        value, _ = integrate.quad(marginal, 0.0, d, epsabs=1e-12, epsrel=1e-11, limit=200,
                                  points=[p for p in (1 / 3, 2 / 3) if p < d])
        return 0.5 + value

    return h * optimize.brentq(lambda d: phi(d) - phi0, 0.0, 1.0, xtol=1e-12)


def _periodic_numbers(image: np.ndarray) -> tuple[np.ndarray, np.ndarray, int]:
    """``(labels, number, n)``: scikit-image's labels of the image as a plain rectangle and the
    map label -> fragment number (0 on background, 1..n)."""
    image = np.asarray(image, dtype=bool)
    if image.ndim != 2:
        raise ValueError(f"expected a 2D image, got shape {image.shape}")
    labels, n = sk_label(image, connectivity=1, background=0, return_num=True)
    if n == 0:
        return labels, np.zeros(1, labels.dtype), 0
    # The labels facing each other across the periodic edges, joined: root[label] is the
    # smallest label of its group (0 stays 0).
    pairs = np.stack([np.r_[labels[:, 0], labels[0, :]], np.r_[labels[:, -1], labels[-1, :]]], 1)
    pairs = pairs[(pairs[:, 0] > 0) & (pairs[:, 1] > 0) & (pairs[:, 0] != pairs[:, 1])]
    graph = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(n + 1, n + 1))
    _, group = connected_components(graph, directed=False)
    root = np.full(group.max() + 1, n + 1)
    np.minimum.at(root, group, np.arange(n + 1))
    root = root[group]
    # scikit-image numbers components in raster order of their first pixel, and each root is
    # the smallest label of its group, so numbering the roots in increasing order keeps the
    # raster order of first appearance (no pass over the pixels needed).
    ordered = np.unique(root[1:])
    number = np.zeros(n + 1, dtype=labels.dtype)
    number[ordered] = np.arange(1, ordered.size + 1)
    return labels, number[root], int(ordered.size)


def label_periodic(image: np.ndarray) -> tuple[np.ndarray, int]:
    """``(labels, n)``: 4-connected labels of the 1-pixels of a periodic 2D image, 0 on
    background and 1..n on fragments, numbered in raster order of their first pixel."""
    labels, number, n = _periodic_numbers(image)
    return number[labels], n


def fragment_areas(image: np.ndarray, spacing: float, periodic: bool = True) -> np.ndarray:
    """Areas of the fragments of a paste image (pixel count x spacing^2): on the torus, in the
    numbering of :func:`label_periodic` (pixels counted per plain label, then per fragment), or
    (``periodic=False``) of the image as a plain rectangle, where the box edges cut fragments
    into pieces, in scikit-image's raster order."""
    if not periodic:
        labels, n = sk_label(np.asarray(image, dtype=bool), connectivity=1, background=0,
                             return_num=True)
        return np.bincount(labels.ravel(), minlength=n + 1)[1:] * float(spacing) ** 2
    labels, number, n = _periodic_numbers(image)
    counts = np.bincount(labels.ravel(), minlength=number.size)
    return np.bincount(number, weights=counts, minlength=n + 1)[1:] * float(spacing) ** 2
