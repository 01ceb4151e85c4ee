"""Crack counting of :mod:`craquelure.impact.measure` on synthetic damage fields."""

import math

import numpy as np
import pytest

from craquelure.impact.initial_state import grid
from craquelure.impact.measure import (
    centre_line_crossings,
    full_softening_opening,
    main_cracks,
    opening_cracks,
)

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


# -- opening -------------------------------------------------------------------------------
# Cracks measured by their opening (:func:`craquelure.impact.measure.opening_cracks`, spec
# section 6 revised 2026-12-02) on synthetic displacement fields of the 2D disc grid: nothing is
# softened in any of them, the measure sees positions only.

W_C = full_softening_opening(83.25, 3.216e6)  # 0.052 mm


def opening_disc():
    x, y = grid("disc", 40, 1, DX)
    return x, y, 0.5 * (y.min() + y.max())


def measure(x0, y0, x, y, mass=None, precrack=None, plastic=None):
    return opening_cracks(x0, y0, x, y, np.ones(x0.size) if mass is None else mass,
                          np.zeros(x0.size) if plastic is None else plastic, DX, W_C,
                          0.5 * (y0.min() + y0.max()), precrack=precrack)


def test_w_c_is_the_full_softening_opening():
    assert W_C == pytest.approx(2 * 83.25 / 3.216e6)
    assert W_C * 1e3 == pytest.approx(0.0518, abs=1e-4)


def test_rigid_motion_opens_nothing():
    x0, y0, _ = opening_disc()
    a = 0.3
    x = math.cos(a) * x0 - math.sin(a) * y0 + 0.01
    y = math.sin(a) * x0 + math.cos(a) * y0 - 0.02
    out = measure(x0, y0, x, y)
    assert out["n_cracks_opening"] == 0
    assert out["n_main_cracks_opening"] == 0
    assert out["max_opening"] == pytest.approx(0.0, abs=1e-12)


def test_rigid_split_at_x0_is_one_main_crack_with_full_coverage():
    """Two halves moved apart by 1 mm at x = 0, a zero-mass column (x = 2 mm) along the middle
    half of the line moving with the right half: one main crack, N_main = 1, it carries the
    whole centre row's opening, and the pre-crack line is opened over its whole length."""
    x0, y0, yc = opening_disc()
    right = x0 > 0
    x = x0 + np.where(right, 0.5e-3, -0.5e-3)
    column = (np.abs(x0 - 0.002) < 0.5 * DX) & (np.abs(y0 - yc) <= 0.04)
    mass = np.where(column, 0.0, 1.0)
    out = measure(x0, y0, x, y0.copy(), mass=mass, precrack=column)
    assert out["n_cracks_opening"] == 1
    assert out["n_main_cracks_opening"] == 1
    assert out["main_run_x_mid"] == pytest.approx(0.0, abs=0.5 * DX)
    assert out["main_run_share"] == pytest.approx(1.0)
    assert out["main_run_opening"] == pytest.approx(1e-3, rel=1e-9)
    assert out["main_crack_theta_opening_deg"] == pytest.approx(0.0, abs=1.0)
    assert out["precrack_coverage_opening"] == pytest.approx(1.0)
    assert out["precrack_largest_opening_on_line"]
    assert out["main_crack_length_opening"] == pytest.approx(0.16, abs=2 * DX)


def test_opening_below_w_c_is_no_crack():
    x0, y0, _ = opening_disc()
    x = x0 + np.where(x0 > 0, 0.4 * W_C, -0.4 * W_C)  # 0.8 w_c
    assert measure(x0, y0, x, y0.copy())["n_cracks_opening"] == 0


def test_fully_cracked_lower_half_is_not_one_crack():
    """Every pair of the lower half (centre row included) stretched by 5 %: an opened zone, not
    a crack: N_main is not 1, and no run carries most of the row's opening alone."""
    x0, y0, yc = opening_disc()
    low = y0 <= yc
    x = np.where(low, x0 * 1.05, x0)
    y = np.where(low, yc + (y0 - yc) * 1.05, y0)
    out = measure(x0, y0, x, y)
    assert out["n_main_cracks_opening"] != 1
    assert out["n_main_cracks_opening"] >= 10
    assert [int(c) for c in out["row_runs_cracks"].split(",")] == [out["n_main_cracks_opening"]]


def test_fan_of_three_opened_lines_gives_three():
    """Four wedges rotated apart about the contact point (rays at -30, 0, +30 deg from the
    vertical): three cracks from the contact zone, three centre-row crossings."""
    x0, y0, yc = opening_disc()
    apex = np.array([0.0, y0.min() - 0.5 * DX])
    ang = np.degrees(np.arctan2(x0 - apex[0], y0 - apex[1]))  # from the vertical
    sector = np.digitize(ang, [-30.0 + 1e-6, 0.0 + 1e-6, 30.0 + 1e-6])  # 0..3, rays on grid?
    delta = 0.02 * (sector - 1.5)
    rx, ry = x0 - apex[0], y0 - apex[1]
    x = apex[0] + np.cos(delta) * rx + np.sin(delta) * ry
    y = apex[1] - np.sin(delta) * rx + np.cos(delta) * ry
    out = measure(x0, y0, x, y)
    assert out["n_main_cracks_opening"] == 3
    xs = [float(v) for v in out["row_runs_x_mm"].split(",")]
    expected = [1e3 * (yc - apex[1]) * math.tan(math.radians(a)) for a in (-30, 0, 30)]
    assert xs == pytest.approx(expected, abs=1e3 * DX)
    # the largest run carries about a third, not most, of the row's opening
    assert out["row_largest_run_share"] < 0.5


def test_two_adjacent_opened_gaps_are_one_crack_three_are_two():
    x0, y0, _ = opening_disc()
    one = x0 + np.where(x0 > 0, 0.25e-3, -0.25e-3) + np.where(x0 > DX, 0.5e-3, 0.0)
    assert measure(x0, y0, one, y0.copy())["row_runs_cracks"] == "1"
    two = one + np.where(x0 > 2 * DX, 0.5e-3, 0.0)
    assert measure(x0, y0, two, y0.copy())["row_runs_cracks"] == "2"


def test_a_crack_through_a_crushed_block_is_one_main_crack():
    """A crushed column 48 mm wide from the contact to 12 mm above the centre row (the
    issue's crushed block), split rigidly through its middle at x = 0 (halves 1 mm apart):
    the pairs across the split are crushed on both sides and count, so the split is one main
    crack crossing the centre row at x = 0; the same block unsplit opens nothing."""
    x0, y0, yc = opening_disc()
    block = (np.abs(x0) <= 0.024) & (y0 <= yc + 0.012)
    plastic = np.where(block, 0.02, 0.0)
    x = x0 + np.where(x0 > 0, 0.5e-3, -0.5e-3)
    out = measure(x0, y0, x, y0.copy(), plastic=plastic)
    assert out["n_main_cracks_opening"] == 1
    assert out["row_runs_x_mm"] == "0"
    assert out["row_runs_opening_mm"] == "1.000"
    assert out["main_run_share"] == pytest.approx(1.0)
    assert measure(x0, y0, x0.copy(), y0.copy(), plastic=plastic)["n_cracks_opening"] == 0


def test_a_crack_away_from_the_line_counts_elsewhere():
    x0, y0, yc = opening_disc()
    x = x0 + np.where(x0 > 0.03, 0.5e-3, 0.0)  # split at x = 32 mm
    column = (np.abs(x0 - 0.002) < 0.5 * DX) & (np.abs(y0 - yc) <= 0.04)
    out = measure(x0, y0, x, y0.copy(), mass=np.where(column, 0.0, 1.0), precrack=column)
    assert out["main_cracks_elsewhere_opening"] == 1
    assert not out["precrack_largest_opening_on_line"]
    assert out["precrack_coverage_opening"] == 0.0
