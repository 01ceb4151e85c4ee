"""Column-mode accuracy study (error-versus-wall-time figure): the measured period converges
to the continuum period 4H/c_P at second order, as the fixed-free chain predicts."""

import pytest

from craquelure.lattice import accuracy


def test_column_period_converges_at_second_order_to_the_continuum():
    results = accuracy.study([4, 8, 16])
    for r in results:
        # discrete-chain dispersion is the whole error (the time-step error of the slow mode
        # is ~(omega dt)^2/24 ~ 1e-6 here): within 5 % of sin x / x - 1
        assert r["relative_error"] == pytest.approx(r["chain_prediction"], rel=0.05)
        assert r["period"] > r["reference_period"]  # dispersion slows the lattice wave
        assert r["wall_s"] > 0 and r["steps"] > 0
    assert accuracy.convergence_order(results) == pytest.approx(-2.0, abs=0.15)


def test_smaller_time_step_does_not_change_the_error_much():
    """At N = 8 the error is set by the resolution: dt factor 0.05 changes it by < 5 %."""
    a = accuracy.column_period(8, dt_factor=0.2)
    b = accuracy.column_period(8, dt_factor=0.05)
    assert b["relative_error"] == pytest.approx(a["relative_error"], rel=0.05)
    assert b["steps"] > 3.5 * a["steps"]
