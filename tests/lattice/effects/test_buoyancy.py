"""The buoyancy effect: the acceleration below the water line is g (rho_w/rho - 1), above it -g."""


import numpy as np
import pytest

from craquelure.lattice.initial_state import probe_engine

from .free_particles import FLUID, particles


def test_buoyancy_acceleration_below_the_water_line():
    y0 = np.array([-3.0, 3.0])
    s = particles([0.0, 5.0], y0)
    g, rho_w = 0.01, 1.1
    eng = probe_engine(s, FLUID, dict(dt=0.1, g=g, rho=1.0, rho_w=rho_w, water_level=0.0),
                 series_every=1)
    eng.run(10)
    # central differences from rest under constant a: x_n - x_0 = a (t^2 + t dt)/2 exactly
    t = eng.time
    a = (eng.q[1] - y0) / (0.5 * (t * t + t * eng.dt))
    assert a[0] == pytest.approx(g * (rho_w - 1.0), rel=1e-9)
    assert a[1] == pytest.approx(-g, rel=1e-9)
