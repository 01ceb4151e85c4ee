"""Crack measures that do not depend on how fragments are counted (issue 32, item 5), on
synthetic cases with known answers: a clean split, a tiling of fragments and a fan of cracks,
for each measure (damage d, crack length per area, m_max, fragment counts with and without
periodic wrap-around)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from craquelure.drying import crack_measures as cm
from craquelure.drying.analysis import analyse_run
from craquelure.drying.binarise import fragment_areas, label_periodic

from .synthetic_run import lattice_run


def crofton_factor(angle_deg: float) -> float:
    """Estimated over true length of one straight interface at ``angle_deg``:
    (pi/8)(|sin phi| + |cos phi| + |sin(phi - 45)| + |cos(phi - 45)|)."""
    phi = math.radians(angle_deg)
    q = math.radians(45.0)
    return cm.CROFTON_WEIGHT * (abs(math.sin(phi)) + abs(math.cos(phi))
                                + abs(math.sin(phi - q)) + abs(math.cos(phi - q)))

N = 400  # pixels per side
L = 4.0  # box side
DX = L / N


def _split() -> np.ndarray:
    """Two full crack bands (rows 100-103 and 300-303): two periodic fragments of 196 rows."""
    image = np.ones((N, N), bool)
    image[100:104] = False
    image[300:304] = False
    return image


def _tiling(k: int = 4, width: int = 4, offset: int = 10) -> np.ndarray:
    """k x k blocks separated by crack lines ``width`` pixels wide, shifted off the edges."""
    image = np.ones((N, N), bool)
    for j in range(k):
        lo = offset + j * N // k
        image[lo:lo + width] = False
        image[:, lo:lo + width] = False
    return image


def _fan(n_rays: int = 6, length: float = 1.5, width: float = 0.03) -> np.ndarray:
    """Cracks radiating from near the box centre at angles 15 + 30 j degrees (none along the
    mesh axes), each ``length`` long and ``width`` wide, starting 0.1 from the centre (where
    rays meet at an apex, pixel islands between them would count as fragments)."""
    c = (np.arange(N) + 0.5) * DX
    x, y = np.meshgrid(c, c)
    image = np.ones((N, N), bool)
    for j in range(n_rays):
        a = math.radians(15.0 + 180.0 / n_rays * j)
        u, v = math.cos(a), math.sin(a)
        along = (x - L / 2) * u + (y - L / 2) * v
        across = -(x - L / 2) * v + (y - L / 2) * u
        image &= ~((np.abs(across) < width / 2) & (along > 0.1) & (along < 0.1 + length))
    return image


def test_clean_split():
    image = _split()
    areas = fragment_areas(image, DX)
    assert label_periodic(image)[1] == 2
    # Without wrap-around the fragment cut by the box edge counts twice.
    open_areas = fragment_areas(image, DX, periodic=False)
    assert open_areas.size == 3
    # the same paste pixels: the edge-cut pieces add up to the periodic fragment
    assert open_areas.sum() == pytest.approx(areas.sum(), rel=1e-12)
    assert sorted(open_areas)[-1] == pytest.approx(max(areas), rel=1e-12)
    assert cm.largest_fraction(areas, L) == pytest.approx(196 / N, rel=1e-12)
    # Two cracks of length L across an L x L box: 2/L per area. Axis-aligned interfaces are
    # where the four-direction Crofton estimate is lowest, 0.948 of the true length.
    assert crofton_factor(0.0) == pytest.approx(0.948, abs=1e-3)
    assert cm.crack_length_per_area(image, DX) == pytest.approx(
        crofton_factor(0.0) * 2 / L, rel=1e-9)


def test_tiling_of_fragments():
    image = _tiling()
    areas = fragment_areas(image, DX)
    assert label_periodic(image)[1] == 16
    # the edge rows and columns split 9 blocks
    assert fragment_areas(image, DX, periodic=False).size == 25
    assert cm.largest_fraction(areas, L) == pytest.approx(96**2 / N**2, rel=1e-12)
    # Eight cracks (four rows, four columns); between crossings each face of each is
    # L - 4 w long (w = 4 pixels): 8 (L - 4 w) / L^2, at the Crofton factor of 0 degrees
    # (the corners of the crossings add < 1 %).
    w = 4 * DX
    assert cm.crack_length_per_area(image, DX) == pytest.approx(
        crofton_factor(0.0) * 8 * (L - 4 * w) / L**2, rel=0.01)


def test_fan_of_cracks():
    image = _fan()
    # Cracks from one point cut no fragment off: one fragment either way.
    assert label_periodic(image)[1] == 1
    assert fragment_areas(image, DX, periodic=False).size == 1
    assert cm.largest_fraction(fragment_areas(image, DX), L) == pytest.approx(
        image.mean(), rel=1e-12)
    # Six rays 1.5 long at 15-165 degrees: the Crofton factors average over those angles.
    # (The ray ends add about a width per ray: < 2 %.)
    expected = np.mean([crofton_factor(15.0 + 30.0 * j) for j in range(6)]) * 6 * 1.5
    assert cm.crack_length_per_area(image, DX) * L**2 == pytest.approx(expected, rel=0.03)
    # and the estimate is within 3 % of the true length, as orientations average out
    assert cm.crack_length_per_area(image, DX) * L**2 == pytest.approx(9.0, rel=0.03)


def test_crofton_factor_bounds():
    factors = [crofton_factor(a) for a in np.linspace(0.0, 90.0, 91)]
    assert min(factors) == pytest.approx(0.948, abs=1e-3)
    assert max(factors) == pytest.approx(1.026, abs=1e-3)
    # The average over orientations is exact.
    assert np.mean([crofton_factor(a) for a in np.linspace(0, 90, 9001)]) == pytest.approx(
        1.0, abs=2e-4)


def test_damage_of_a_removed_band_and_the_run_measures():
    """A lattice run (40 x 40 particles, L = 2) with a band of 4 particle rows removed at the
    second snapshot and a column band at the third: d = removed / N, the counts and m_max."""
    run = lattice_run(40, 2.0, bands_per_time=((), (("y", 0.5, 0.7),),
                                               (("y", 0.5, 0.7), ("x", 1.0, 1.2))))
    ds = analyse_run(run, progress=False)
    assert ds["damage"].values == pytest.approx([0.0, 4 / 40, 4 / 40 + 4 / 40 - 16 / 1600])
    assert cm.damage(np.ones(10)) == 0.0
    assert cm.damage(np.r_[np.zeros(3), np.ones(7)]) == pytest.approx(0.3, rel=1e-12)
    # intact: one fragment, m_max = 1, no cracks
    assert ds["n_fragments"].values[0] == 1 and ds["n_fragments_open"].values[0] == 1
    assert ds["largest_fragment_fraction"].values[0] == pytest.approx(1.0)
    assert ds["crack_length_per_area"].values[0] == 0.0
    # one band: still one periodic fragment (an annulus), two without wrap-around
    assert ds["n_fragments"].values[1] == 1 and ds["n_fragments_open"].values[1] == 2
    # crack length ~ the band's two faces / 2 = L per L^2 (Crofton at 0 degrees)
    assert ds["crack_length_per_area"].values[1] == pytest.approx(0.948 / 2.0, rel=0.03)
    # the image's crack is the band widened by 2 d* (spec check 12): m_max accordingly
    width = 0.2 + 2 * float(ds.attrs["edge_depth"])
    assert ds["largest_fragment_fraction"].values[1] == pytest.approx(1 - width / 2.0, abs=0.02)
    # band and column: one periodic fragment still, four without wrap-around
    assert ds["n_fragments"].values[2] == 1 and ds["n_fragments_open"].values[2] == 4
    # the open-image areas are recorded per snapshot and tile the same paste as the periodic
    open_index = ds["fragment_time_index_open"].values
    assert np.bincount(open_index) == pytest.approx(ds["n_fragments_open"].values)
    for k in range(3):
        assert ds["fragment_area_open"].values[open_index == k].sum() == pytest.approx(
            ds["fragment_area"].values[ds["fragment_time_index"].values == k].sum(), rel=1e-12)
