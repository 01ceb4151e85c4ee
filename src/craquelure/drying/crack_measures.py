r"""Crack measures that do not depend on how fragments are counted, per
snapshot of a drying run, from its particles and its paste image (:mod:`.binarise`):

- damage :math:`d = n_{removed}/N`, the removed-area fraction: every particle stands for the
  area :math:`L^2/N` on average (the consistent masses vary by a factor 10, the areas the
  particles tile do not), so d is the fraction of the layer the cracks took out. It needs no
  image and no labelling.
- crack length per area :math:`\ell_c / L^2`: half the length of the paste/crack interface of
  the image (each crack has two faces), by the Cauchy-Crofton formula with four directions on
  the periodic mesh,

  .. math:: \ell_{interface} = \frac{\pi}{8}\Big[(n_0 + n_{90})\,\Delta x
            + (n_{45} + n_{135})\,\frac{\Delta x}{\sqrt 2}\Big],

  :math:`n_\theta` the number of 0/1 changes between neighbouring pixels along direction
  :math:`\theta` (lines :math:`\Delta x` apart for the axes, :math:`\Delta x/\sqrt 2` for the
  diagonals). Exact on average over orientations; for one straight interface at angle
  :math:`\varphi` it gives :math:`(\pi/8)(|\sin\varphi| + |\cos\varphi| +
  |\sin(\varphi - 45°)| + |\cos(\varphi - 45°)|)` times its length, 0.948 at 0° and 45°,
  1.026 at 22.5°: within -5.2 % / +2.6 % of the true length.
- largest fragment's area fraction :math:`m_{max} = S_{max}/L^2` (periodic labelling), the
  order parameter of the damage-to-fragmentation transition (Szatmari et al. 2025).

The fragments of the image taken as a plain rectangle (a band around the torus is one fragment
on the torus; the box edges cut it) are :func:`.binarise.fragment_areas` with ``periodic=False``."""

from __future__ import annotations

import math

import numpy as np

CROFTON_WEIGHT = math.pi / 8.0


def damage(alive: np.ndarray) -> float:
    """Removed-area fraction d = (particles removed) / N of one snapshot's ``alive`` flags."""
    alive = np.asarray(alive).astype(bool)
    return float(1.0 - alive.mean()) if alive.size else float("nan")


def interface_length(image: np.ndarray, spacing: float) -> float:
    """Length of the 0/1 interface of a periodic image (module docstring), in spacing's units."""
    a = np.asarray(image, dtype=bool)
    axis = (np.count_nonzero(a != np.roll(a, 1, axis=0))
            + np.count_nonzero(a != np.roll(a, 1, axis=1)))
    shifted = np.roll(a, 1, axis=0)
    diagonal = (np.count_nonzero(a != np.roll(shifted, 1, axis=1))
                + np.count_nonzero(a != np.roll(shifted, -1, axis=1)))
    return CROFTON_WEIGHT * spacing * (axis + diagonal / math.sqrt(2.0))


def crack_length_per_area(image: np.ndarray, spacing: float) -> float:
    """Crack length per unit area: half the interface length (two faces per crack) / area."""
    area = image.size * spacing * spacing
    return 0.5 * interface_length(image, spacing) / area


def largest_fraction(areas: np.ndarray, box_length: float) -> float:
    """m_max = S_max / L^2 (0 if the image has no fragment)."""
    areas = np.asarray(areas, float)
    return float(areas.max() / box_length**2) if areas.size else 0.0
