"""The gravity effect along a slope: the acceleration components g sin(beta), -g cos(beta)."""

import math

import numpy as np
import pytest

from craquelure.lattice.initial_state import probe_engine

from .free_particles import FLUID, particles


def test_gravity_along_a_slope():
    x0, y0 = np.array([0.0]), np.array([5.0])
    s = particles(x0, y0)
    g, beta = 0.01, math.radians(70.0)
    eng = probe_engine(s, FLUID, dict(dt=0.1, g=g, slope_angle=beta), series_every=1)
    eng.run(10)
    t = eng.time
    factor = 0.5 * (t * t + t * eng.dt)
    assert (eng.q[0, 0] - x0[0]) / factor == pytest.approx(g * math.sin(beta), rel=1e-9)
    assert (eng.q[1, 0] - y0[0]) / factor == pytest.approx(-g * math.cos(beta), rel=1e-9)
    e = eng.series_array()[:, 10]
    assert np.abs(e - e[0]).max() < 1e-9 * eng.series_array()[-1, 1]
