"""Accuracy-versus-cost study (the workflow's error/wall-time figure) on the CI scene."""

import numpy as np
import pytest

from craquelure.scene import load_scene
from craquelure.softdyn.accuracy import heun_order, run_accuracy


@pytest.fixture(scope="module")
def study():
    return run_accuracy(load_scene("softdyn/t1_accuracy_ci"))


def test_reference_duration(study):
    """Reference LSODA rtol 1e-10: T = 28.0556 tau (the rtol 1e-11 reference gives 28.05556)."""
    assert study.attrs["reference_duration"] == pytest.approx(28.05556, abs=1e-4)


def test_adaptive_errors_shrink_with_rtol(study):
    """Each adaptive integrator: cutting rtol 100x cuts the T1 duration error (measured 10-100x)
    and both stay below 1e-2 relative (check 13's 1 %)."""
    err = study.adaptive_error.values
    assert np.all(err[:, 1] < err[:, 0])
    assert np.all(err < 1e-2 * study.attrs["reference_duration"])
    assert np.all(study.adaptive_wall_time_s.values > 0)
    assert np.all(study.adaptive_n_rhs.values[:, 1] >= study.adaptive_n_rhs.values[:, 0])


def test_heun_second_order_and_cost(study):
    """heun: halving dt cuts the error by 4 (order 2 +- 0.3; measured 1.87 on the duration,
    1.97 on the state between dt = 0.02 and 0.01 tau) and doubles the right-hand sides."""
    assert np.all(study.heun_stable.values == 1)
    order_t, order_y = heun_order(study)
    assert order_t == pytest.approx(2.0, abs=0.3)
    assert order_y == pytest.approx(2.0, abs=0.3)
    n = study.heun_n_rhs.values
    assert n[1] == pytest.approx(2 * n[0], rel=0.01)
