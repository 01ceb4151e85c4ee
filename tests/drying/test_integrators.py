"""Runge-Kutta-Chebyshev (rkc2) and its step controller on model problems (no physics)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from craquelure.drying.integrators import (
    StepController,
    Stepper,
    abm4_step,
    rkc2_error_norm,
    rkc2_step,
    rkc_coefficients,
    rkc_stability,
    rkc_stages,
)


def rkc2_error(y0, y1, f0, f1, dt):
    """Local error estimate of an RKC2 step, (12 (y0 - y1) + 6 dt (f0 + f1)) / 15: the numpy
    form of what rkc2_error_norm fuses."""
    return 0.8 * (y0 - y1) + (0.4 * dt) * (f0 + f1)


def _real_stability_interval(s: int) -> float:
    x = -np.linspace(0.0, 1.2 * s * s, 400001)
    unstable = np.abs(rkc_stability(x, s)) > 1.0 + 1e-12
    return float(-x[np.argmax(unstable)])


@pytest.mark.parametrize("s", [3, 6, 10, 20])
def test_real_stability_interval_grows_as_s_squared(s):
    """beta(s) -> (2/3)(s^2 - 1)(1 - 2 eps/15), eps = 2/13 (Verwer et al.): within 2 % from
    s = 6 on, above it for fewer stages (6.18 at s = 3)."""
    beta = _real_stability_interval(s)
    expected = (2.0 / 3.0) * (s * s - 1) * (1.0 - 2.0 / 15.0 * 2.0 / 13.0)
    if s >= 6:
        assert beta == pytest.approx(expected, rel=0.02)
    else:
        assert expected <= beta <= 1.25 * expected


@pytest.mark.parametrize("s", [2, 5, 12])
def test_stability_polynomial_is_second_order(s):
    """R_s(z) = 1 + z + z^2/2 + O(z^3): the stage recursion and the closed form agree."""
    z = 1e-3
    assert rkc_stability(z, s) == pytest.approx(1 + z + z * z / 2, abs=1e-8)
    # the scalar recursion reproduces R_s(z) for y' = lambda y
    lam, dt = -3.7, 0.9
    y1 = rkc2_step(np.array([1.0]), np.array([lam]), 0.0, dt, lambda y, t: lam * y, s)[0]
    assert y1 == pytest.approx(float(rkc_stability(lam * dt, s)), rel=1e-12)


def test_stage_count_covers_the_spectrum():
    for dt, radius in [(0.004, 200.0), (0.2, 200.0), (1.0, 1000.0), (0.01, 0.0)]:
        s = rkc_stages(dt, radius)
        assert s >= 2
        assert _real_stability_interval(s) >= dt * radius
    assert rkc_coefficients(7)[4][7] == 1.0  # c_s = 1


def _stiff_problem():
    """y' = A y + g(t), A = diag of a real spectrum in [-1000, -1] plus a lightly damped
    oscillator (omega = 1): exact solution known."""
    lam = -np.geomspace(1.0, 1000.0, 12)
    omega, gamma = 1.0, 0.05

    def rate(y, t):
        out = np.empty_like(y)
        out[:12] = lam * (y[:12] - np.sin(t)) + np.cos(t)  # exact y = sin t (+ decaying)
        out[12] = y[13]
        out[13] = -omega**2 * y[12] - 2 * gamma * y[13]
        return out

    y0 = np.zeros(14)
    y0[12] = 1.0

    def exact(t):
        wd = math.sqrt(omega**2 - gamma**2)
        osc = math.exp(-gamma * t) * (math.cos(wd * t) + gamma / wd * math.sin(wd * t))
        return np.concatenate([np.sin(t) * np.ones(12) - 0.0, [osc]]), lam

    return rate, y0, exact


def _integrate(dt, t_end=4.0):
    rate, y, exact = _stiff_problem()
    t, f0 = 0.0, rate(y, 0.0)
    s = rkc_stages(dt, 1000.0)
    for _ in range(int(round(t_end / dt))):
        y = rkc2_step(y, f0, t, dt, rate, s)
        t += dt
        f0 = rate(y, t)
    return np.abs(y[:13] - exact(t)[0]).max(), s


def test_second_order_far_beyond_the_explicit_limit():
    """Steps 50-200x the forward-Euler limit 2/1000: stable, error / 4 per halving (+-30 %)."""
    errors = [_integrate(dt) for dt in (0.4, 0.2, 0.1)]
    for (coarse, _), (fine, _) in zip(errors, errors[1:], strict=False):
        assert coarse / fine == pytest.approx(4.0, rel=0.3)
    assert errors[0][1] <= 1 + int(math.sqrt(1 + 1.54 * 400))


def test_error_estimate_is_second_order_and_tracks_the_true_error():
    rate, y0, _ = _stiff_problem()
    f0 = rate(y0, 0.0)
    estimates = []
    for dt in (0.2, 0.1):
        y1 = rkc2_step(y0, f0, 0.0, dt, rate, rkc_stages(dt, 1000.0))
        estimates.append(np.abs(rkc2_error(y0, y1, f0, rate(y1, dt), dt)).max())
    # local error O(dt^3): 8x per halving (+-50 %, the stiff components are not asymptotic)
    assert estimates[0] / estimates[1] == pytest.approx(8.0, rel=0.5)


def test_controller_rejects_shrinks_and_grows_back():
    ctrl = StepController(dt=0.1, dt_max=0.5)
    assert not ctrl.propose(8.0, 0.1)  # error 8x the tolerance: rejected, dt halved or less
    assert ctrl.dt_next == pytest.approx(0.1 * 0.8 / 2.0)
    assert ctrl.propose(0.5, ctrl.dt_next)
    assert ctrl.dt_next <= 0.04 * (1 + 1e-12)  # no growth right after a rejection
    dt = ctrl.dt_next
    for _ in range(20):
        assert ctrl.propose(1e-3, dt)
        dt = ctrl.dt_next
    assert dt == 0.5  # small errors let it grow up to dt_max
    assert not ctrl.propose(math.nan, dt) and ctrl.dt_next == pytest.approx(0.05)
    assert ctrl.rejected == 2


def test_unknown_integrator_names_the_allowed_values():
    with pytest.raises(ValueError, match="abm4, rk4, rk2, rkc2"):
        Stepper("rkc4")


# -- the fused vector loops are the numpy expressions they replace, to the last bit -----------
def _states(seed: int, n: int = 3001):
    rng = np.random.default_rng(seed)
    return [rng.standard_normal((8, n)) * 10.0 ** rng.uniform(-3, 3, (8, 1)) for _ in range(6)]


def test_rkc2_step_equals_its_numpy_stage_formula_bitwise():
    y, f0, *_ = _states(1)
    lam = -np.linspace(0.1, 300.0, y.size).reshape(y.shape)

    def rate(state, t):
        return lam * state + np.sin(t)

    dt, s = 0.2, 8
    mu, nu, mu_t, gamma_t, c, *_ = rkc_coefficients(s)
    previous, current = y, y + (mu_t[1] * dt) * f0
    for j in range(2, s + 1):
        r = rate(current, c[j - 1] * dt)
        following = ((1.0 - mu[j] - nu[j]) * y + mu[j] * current + nu[j] * previous
                     + (mu_t[j] * dt) * r + (gamma_t[j] * dt) * f0)
        previous, current = current, following
    assert np.array_equal(rkc2_step(y, f0, 0.0, dt, rate, s), current)


def test_abm4_step_equals_its_numpy_formula_bitwise():
    y, fn, f1, f2, f3, fp = _states(2)
    dt = 0.004
    expected = y + (dt / 24.0) * (9.0 * fp + 19.0 * fn - 5.0 * f1 + f2)
    predicted = y + (dt / 24.0) * (55.0 * fn - 59.0 * f1 + 37.0 * f2 - 9.0 * f3)
    seen = []

    def rate(state, t):
        seen.append(state.copy())
        return fp

    assert np.array_equal(abm4_step(y, (fn, f1, f2, f3), 0.0, dt, rate), expected)
    assert np.array_equal(seen[0], predicted)


def test_rkc2_error_norm_equals_the_masked_numpy_norm_and_ignores_removed_particles():
    y0, y1, f0, f1, *_ = _states(3)
    scale = np.linspace(0.5, 4.0, 8)
    alive = np.random.default_rng(4).random(y0.shape[1]) > 0.3
    estimate = rkc2_error(y0, y1, f0, f1, 0.37)
    expected = float((np.abs(estimate[:, alive]) / scale[:, None]).max())
    assert rkc2_error_norm(y0, y1, f0, f1, 0.37, scale, alive) == expected
    # a removed particle's entries do not count, a present one's NaN or inf makes the norm inf
    dead, live = np.flatnonzero(~alive)[0], np.flatnonzero(alive)[0]
    y1[3, dead] = np.nan
    assert rkc2_error_norm(y0, y1, f0, f1, 0.37, scale, alive) == expected
    y1[5, live] = np.inf
    assert rkc2_error_norm(y0, y1, f0, f1, 0.37, scale, alive) == math.inf
    assert rkc2_error_norm(y0, y1, f0, f1, 0.37, scale, np.zeros_like(alive)) == 0.0
