"""The bed effect: a particle comes to rest on the bed with the spring overlap m g / k."""

import math

import pytest

from craquelure.lattice.initial_state import probe_engine

from .free_particles import FLUID, particles


def test_particle_rests_on_bed_with_spring_overlap():
    s = particles([0.0], [0.6])
    m, g, kb = s.mass[0], 0.01, 5.0
    eng = probe_engine(s, FLUID, dict(dt=0.02, g=g, bed_level=0.0, bed_stiffness=kb,
                                bed_damping=2 * math.sqrt(kb / m)), series_every=100)
    eng.run(20000)
    assert eng.q[1, 0] == pytest.approx(0.5 - m * g / kb, rel=1e-6)
    series = eng.series_array()
    assert abs(series[-1, 10] - series[0, 10]) < 1e-3 * series[-1, 7]
