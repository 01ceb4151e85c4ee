"""The drag effect: the velocity decays as exp(-rate t) and the energy balance stays closed."""

import math

import pytest

from craquelure.lattice.initial_state import probe_engine

from .free_particles import FLUID, particles


def test_drag_decays_velocity_exponentially():
    s = particles([0.0], [-1.0])
    rate = 0.05
    eng = probe_engine(s, FLUID, dict(dt=0.05, drag_rate=rate, water_level=0.0), series_every=10)
    eng.set_velocity([1.0], [0.0])
    eng.run(400)
    v = (eng.q[0, 0] - eng.qm[0, 0]) / eng.dt
    assert v == pytest.approx(math.exp(-rate * eng.time), rel=1e-2)
    series = eng.series_array()
    assert series[-1, 10] == pytest.approx(series[0, 10], rel=1e-3)
