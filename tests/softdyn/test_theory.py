"""Two spheres (companion paper limits): spec checks 4 and 5."""

import math

import numpy as np
import pytest

from craquelure.scene import load_scene
from craquelure.softdyn import theory
from craquelure.softdyn.engine import run
from craquelure.softdyn.initial_state import build, series_dataset

C_N = 1.5 * math.pi


@pytest.fixture(scope="module")
def approach():
    """F~ = 1e-6 (h* = 1e-4 R) from h0 = 0.1 R down to h = 1e-7 R = h*/1000."""
    setup = build(load_scene("softdyn/two_sphere_approach",
                             ["outputs.gap_end=1.0e-7", "outputs.t_end=1.0e+7"]))
    res = run(setup, sample_times_tau=np.geomspace(1e-3, 1e7, 1000))
    return setup, series_dataset(setup, res), res


def test_poiseuille_approach_is_exponential(approach):
    """Check 4: for h >= 100 h*, h(t) = h0 exp(-t/(c_n tau)) within 1 % (fitted rate)."""
    setup, ds, _ = approach
    t, h = ds.time.values, ds.gap.values[:, 0]
    hs = theory.h_star(1e-6, 1.0)
    window = (h >= 100 * hs) & (t > 1.0)
    assert window.sum() > 20
    rate = -np.polyfit(t[window], np.log(h[window]), 1)[0]
    assert rate == pytest.approx(1.0 / C_N, rel=1e-2)
    # and the amplitude: h(t) against h0 exp(-t/(c_n tau)) pointwise, after the 0.01 tau ramp
    pred = 0.1 * np.exp(-t[window] / C_N)
    assert np.abs(h[window] / pred - 1).max() < 1e-2


def test_hertz_approach_and_deflection(approach):
    """Check 4: for h <= h*/100, h^-2 - h_ref^-2 = 2 (t - t_ref)/(c_n tau h*^2) within 2 %,
    and s -> h* = (F~/k_n)^(2/3) R."""
    setup, ds, res = approach
    t, h = ds.time.values, ds.gap.values[:, 0]
    hs = theory.h_star(1e-6, 1.0)
    window = h <= hs / 100
    assert window.sum() > 20
    t_w, h_w = t[window], h[window]
    measured = (h_w[-1] ** -2 - h_w[0] ** -2) / (t_w[-1] - t_w[0])
    assert measured == pytest.approx(2.0 / (C_N * hs**2), rel=2e-2)
    assert ds.deflection_normal.values[-1, 0] == pytest.approx(hs, rel=1e-2)
    assert res.stopped and ds.gap.values[-1, 0] == pytest.approx(1e-7, rel=1e-2)


@pytest.mark.parametrize("h0", [1e-3, 1e-4])
def test_separation_time_matches_quadrature(h0):
    """Check 5: opening from h0 to R under tension F within 2 % of the quadrature of section 7;
    for h0 <= h*/100 also within 10 % of (c_n/2) tau (h*/h0)^2."""
    force = 1e-3
    setup = build(load_scene("softdyn/two_sphere_separation", [
        f"particles.h0={h0!r}", f"loads.reduced_force={force!r}", "outputs.t_end=1.0e+6"]))
    res = run(setup, sample_times_tau=np.array([]))
    assert res.stopped
    t_open = res.t_stop / setup.tau
    assert t_open == pytest.approx(theory.t_separation(h0, force, 1.0, C_N), rel=2e-2)
    if h0 <= theory.h_star(force, 1.0) / 100:
        assert t_open == pytest.approx(0.5 * C_N * (theory.h_star(force, 1.0) / h0) ** 2,
                                       rel=0.1)
