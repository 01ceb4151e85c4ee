"""Crack counting of :mod:`craquelure.impact.measure` on synthetic damage fields."""

import numpy as np

from craquelure.impact.initial_state import grid
from craquelure.impact.measure import centre_line_crossings, main_cracks

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


def test_revised_main_crack_starts_at_the_contact_zone():
    """A vertical crack from the lowest rows to the top is one main crack at x = 2 mm; the same
    crack cut off from the contact zone is none (it does not start there), and a short crack
    beside it is a secondary crack no longer than half the main one."""
    from craquelure.impact.measure import revised_cracks

    x, y = disc()
    plastic = np.zeros(x.size)
    cracked = np.zeros(x.size)
    cracked[np.abs(x - 0.002) < 0.5 * DX] = 1.0
    cracked[(np.abs(x + 0.042) < 0.5 * DX) & (np.abs(y) < 0.02)] = 1.0  # 40 mm, off the base
    out = revised_cracks(x, y, cracked, plastic, DX, 0.0)
    assert out["n_main_cracks_revised"] == 1
    assert out["main_crack_x_mid"] == np.float64(0.002)
    assert abs(out["main_crack_theta_deg"]) < 1.0
    assert out["n_secondary_cracks"] == 1
    assert out["second_crack_length"] <= 0.5 * out["main_crack_length_revised"]
    cut = cracked.copy()
    cut[y < y.min() + 3 * DX] = 0.0
    assert revised_cracks(x, y, cut, plastic, DX, 0.0)["n_main_cracks_revised"] == 0


def test_revised_fan_from_the_contact_counts_each_branch():
    from craquelure.impact.measure import revised_cracks

    x, y = disc()
    cracked = np.zeros(x.size)
    for xc in (-0.026, 0.002, 0.030):
        cracked[(np.abs(x - xc) < 0.5 * DX) & (y < 0.05)] = 1.0
    cracked[(y < y.min() + 1.5 * DX) & (np.abs(x) <= 0.03)] = 1.0  # joined at the base
    out = revised_cracks(x, y, cracked, np.zeros(x.size), DX, 0.0)
    assert out["n_main_cracks_revised"] == 3


def test_precrack_following_coverage_and_tips():
    from craquelure.impact.measure import precrack_following

    x, y = disc()
    line = (np.abs(x + 0.002) < 0.5 * DX) & (np.abs(y) <= 0.04)  # one column, length R
    cracked = np.zeros(x.size)
    cracked[np.abs(x - 0.002) < 0.5 * DX] = 1.0  # the next column, bottom to top
    out = precrack_following(x, y, cracked, np.zeros(x.size), line, DX, 0.0)
    assert out["precrack_coverage"] == 1.0
    assert min(out["precrack_tip_extension_low"], out["precrack_tip_extension_high"]) > 0.03
    assert out["main_cracks_elsewhere"] == 0
    half = cracked * (y < 0.0)  # only the lower half: half the line, no upper tip
    out = precrack_following(x, y, half, np.zeros(x.size), line, DX, 0.0)
    assert 0.4 < out["precrack_coverage"] < 0.6
    assert out["precrack_tip_extension_high"] == 0.0
