"""Soft Dynamics analysis numbers on synthetic datasets with known answers: the sweep's local
Hertz slope d ln T / d ln h0 and its span, with unfinished points left out."""

import math

import pytest

from craquelure.softdyn import analysis

from .test_claims import sweep


@pytest.mark.parametrize("exponent", [-2.0, -0.5])
def test_sweep_slope_and_span_of_a_power_law(exponent):
    out = analysis.sweep_numbers(sweep(exponent))
    assert out["finished"] == 13 and out["forces"] == 1
    assert out["monotone"] == [True]
    (force, slope, r_lo, r_hi), = out["slopes"]
    assert slope == pytest.approx(exponent, rel=1e-12)
    assert r_lo < r_hi <= 0.1  # the two grid points nearest below h0/h* = 0.1
    assert out["span_decades"] == pytest.approx(-exponent * math.log10(30 / 0.02), rel=1e-12)


def test_unfinished_points_are_left_out():
    ds = sweep(-2.0)
    ds["finished"][12, 0] = 0  # the largest h0 (shortest T) did not finish
    ds["duration"][12, 0] = 1e-30  # whatever it holds is not read
    out = analysis.sweep_numbers(ds)
    assert out["finished"] == 12
    assert out["span_decades"] == pytest.approx(2 * math.log10(ds.h0_over_h_star.values[11, 0]
                                                               / 0.02), rel=1e-12)
