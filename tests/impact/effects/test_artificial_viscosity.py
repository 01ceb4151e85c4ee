"""Monaghan's artificial viscosity (impact spec section 3) at one pair: it acts only on
approaching pairs and is then positive (it dissipates, never feeds, kinetic energy), linear in
the approach speed for slow approaches and quadratic for fast ones, and the 0.01 h^2 term keeps
mu finite as the pair closes (|mu| <= 5 |v| h/h, the maximum at r = 0.1 h)."""

import numpy as np
import pytest

from craquelure.impact.effects.artificial_viscosity import monaghan_pi

H, RHO, C, ALPHA, BETA = 2.4e-3, 2400.0, 3616.0, 1.0, 2.0


def pair(speed, r):
    """(Pi, mu) for a pair at distance r approaching head-on at ``speed`` (v_ij . r_ij < 0)."""
    return monaghan_pi(-speed * r, r * r, H, RHO, C, ALPHA, BETA)


@pytest.mark.parametrize("vdotr", [0.0, 1e-9, 3.0])
def test_receding_or_sliding_pairs_feel_nothing(vdotr):
    assert monaghan_pi(vdotr, 1e-6, H, RHO, C, ALPHA, BETA) == (0.0, 0.0)


def test_approaching_pairs_dissipate_linearly_then_quadratically():
    r = 0.8 * H
    # the crossover: alpha c |mu| = beta mu^2 at |mu| = alpha c / beta, i.e. at the speed
    mu_star = ALPHA * C / BETA
    v_star = mu_star * (r * r + 0.01 * H * H) / (H * r)
    assert pair(v_star, r)[0] == pytest.approx(2 * ALPHA * C * mu_star / RHO, rel=1e-12)
    speeds = v_star * np.geomspace(1e-5, 1e5, 41)
    pis = np.array([pair(v, r)[0] for v in speeds])
    assert (pis > 0).all()  # -alpha c mu > 0 and beta mu^2 > 0 with mu < 0
    # local exponent d ln Pi / d ln v = 1 + x/(1 + x), x = v/v*: 1 for slow, 2 for fast pairs
    slope = np.diff(np.log(pis)) / np.diff(np.log(speeds))
    mid = np.sqrt(speeds[1:] * speeds[:-1]) / v_star
    np.testing.assert_allclose(slope, 1 + mid / (1 + mid), atol=2e-2)
    assert slope[0] == pytest.approx(1.0, abs=1e-4)
    assert slope[-1] == pytest.approx(2.0, abs=1e-4)


def test_mu_stays_finite_as_the_pair_closes():
    speed = 10.0
    r = np.geomspace(1e-6 * H, 2 * H, 4001)
    mu = np.array([pair(speed, x)[1] for x in r])
    # mu = -v h r^2 / (r (r^2 + 0.01 h^2)) = -v h r / (r^2 + 0.01 h^2): max |mu| = 5 v at r = h/10
    assert np.abs(mu).max() <= 5.0 * speed * (1 + 1e-12)
    assert r[np.argmax(np.abs(mu))] == pytest.approx(0.1 * H, rel=5e-3)
    assert abs(mu[0]) < 1e-4 * 5.0 * speed  # vanishes at contact instead of diverging
