"""Crack counting of :mod:`craquelure.impact.measure` on synthetic damage fields."""

import numpy as np

from craquelure.impact.measure import centre_line_crossings, main_cracks
from craquelure.impact.specimen import grid

DX = 0.004


def disc():
    x, y = grid("disc", 40, 1, DX)
    return x, y


def test_fan_of_joined_cracks_is_one_cluster_but_three_crossings():
    """Three vertical cracks (x = -26, 2, 30 mm) joined by a horizontal one at the top: the
    spec's cluster rule sees one main crack, the centre row crosses three."""
    x, y = disc()
    cracked = np.zeros(x.size)
    for xc in (-0.026, 0.002, 0.030):  # grid columns
        cracked[(np.abs(x - xc) < 0.5 * DX) & (y < 0.05)] = 1.0
    cracked[(np.abs(y - 0.05) < 0.5 * DX) & (np.abs(x) <= 0.03)] = 1.0
    plastic = np.zeros(x.size)
    assert len(main_cracks(x, y, cracked, plastic, DX, 0.08)) == 1
    n, where = centre_line_crossings(x, y, cracked, plastic, DX, 0.0)
    assert n == 3
    assert [float(v) for v in where.split(",")] == [-26.0, 2.0, 30.0]  # x of the column, mm


def test_crushed_particles_are_no_crack():
    x, y = disc()
    cracked = (np.abs(x - 0.002) < 0.5 * DX).astype(float)
    plastic = np.where(cracked > 0, 0.01, 0.0)
    assert centre_line_crossings(x, y, cracked, plastic, DX, 0.0)[0] == 0
    assert centre_line_crossings(x, y, cracked, np.zeros(x.size), DX, 0.0)[0] == 1
