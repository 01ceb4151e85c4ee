"""The beams effect: a rigid rotation gives no force, and a tumbling fragment keeps a continuous
(unwrapped) bond rotation."""

import math

import numpy as np

from craquelure.lattice import beam
from craquelure.lattice.engine import lattice_system, stable_step_estimate
from craquelure.lattice.geometry import triangular_block
from craquelure.lattice.initial_state import probe_engine

from ..test_engine import small_block


def test_rigid_rotation_gives_no_force():
    s, _ = small_block(6, 6, model="euler_bernoulli")
    eng = probe_engine(s, ("beams",), dict(dt=0.1), series_every=1)
    phi = 0.9
    c, sn = math.cos(phi), math.sin(phi)
    rot = np.vstack([c * s.x - sn * s.y, sn * s.x + c * s.y, np.full(s.n, phi)])
    eng.q[:] = rot
    eng.qm[:] = rot
    eng.set_velocity(0.0, 0.0, 0.0)
    eng.run(3)
    assert np.abs(eng.q - rot).max() < 1e-13
    assert eng.series_array()[-1, 3] < 1e-28  # elastic energy


def test_tumbling_fragment_keeps_continuous_bond_rotation():
    """A spinning triangle turns by several pi: the chord rotation is unwrapped, so the
    elastic energy stays small (a 2 pi jump in phi' would release ~k_r (2 pi)^2)."""
    x, y, _ = triangular_block(2, 2)
    c = beam.euler_bernoulli(1.0, 0.7)
    s = lattice_system(x, y, kn=c.kn, ka=c.a, kb=c.b)
    eng = probe_engine(s, ("beams",), dict(dt=0.2 * stable_step_estimate(s)), series_every=10)
    omega = 0.05
    xc, yc = s.x.mean(), s.y.mean()
    eng.set_velocity(-omega * (s.y - yc), omega * (s.x - xc), np.full(s.n, omega))
    turns = 3.0 * 2 * math.pi / omega
    eng.run(int(turns / eng.dt))
    series = eng.series_array()
    assert abs(eng.q[2].mean()) > 5 * math.pi  # it really tumbled
    assert series[:, 3].max() < 2e-2 * series[0, 1]  # elastic << kinetic (centrifugal)
    e = series[:, 10]
    assert np.abs(e - e[0]).max() < 1e-3 * e[0]
