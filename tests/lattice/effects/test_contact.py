"""Effects on demand: the contact effect (a head-on collision conserves energy and momentum,
friction dissipates the sliding energy, the contact list is every unbonded pair within reach)."""


import numpy as np
import pytest

from craquelure.lattice.engine import (
    lattice_system,
)
from craquelure.lattice.geometry import INTACT, REMOVED, triangular_block
from craquelure.lattice.initial_state import probe_engine

from .free_particles import particles


def test_contact_head_on_collision_conserves_energy_and_momentum():
    s = particles([0.0, 1.5], [0.0, 0.0])
    eng = probe_engine(s, ("contact",), dict(dt=0.01, contact_stiffness=10.0, skin=0.5),
                 series_every=10)
    eng.set_velocity([0.05, -0.05], [0.0, 0.0])
    eng.run(4000)
    series = eng.series_array()
    assert series[:, 4].max() > 0  # they did touch
    e = series[:, 10]
    assert np.abs(e - e[0]).max() < 1e-3 * e[0]
    v = (eng.q[0] - eng.qm[0]) / eng.dt
    assert v[0] == pytest.approx(-0.05, rel=1e-3) and v[1] == pytest.approx(0.05, rel=1e-3)


def test_friction_dissipates_sliding_energy():
    s = particles([0.0, 0.0], [0.0, 0.95])
    s.fix[:, 0] = 1
    s.load[1, 1] = -0.01
    eng = probe_engine(s, ("contact",), dict(dt=0.01, contact_stiffness=10.0, friction=0.5,
                                       friction_viscosity=5.0, skin=0.5), series_every=10)
    eng.set_velocity([0.0, 0.02], [0.0, 0.0])
    eng.run(2000)
    series = eng.series_array()
    assert series[-1, 7] > 0  # dissipated by friction
    e = series[:, 10]
    assert np.abs(e - e[0]).max() < 2e-3 * max(series[:, 7].max(), abs(series[:, 6]).max())


def test_contact_list_is_every_unbonded_pair_within_reach():
    """The contact list (built in compiled code) holds exactly the pairs i < j closer than
    d_max + skin that no intact bond joins (broken and removed bonds count as unbonded), in
    ascending i; here against a brute-force search on a jittered block."""
    rng = np.random.default_rng(3)
    x, y, _ = triangular_block(9, 8)
    s = lattice_system(x + 0.05 * rng.normal(size=x.size), y + 0.05 * rng.normal(size=x.size),
                       kn=1.0, ka=0.1, kb=0.0)
    s.state[rng.choice(s.bi.size, 12, replace=False)] = 0
    s.state[rng.choice(s.bi.size, 5, replace=False)] = REMOVED
    eng = probe_engine(s, ("beams", "contact"), dict(dt=0.01, skin=0.3), series_every=10)
    reach = 1.0 + 0.3
    d = np.hypot(s.x[:, None] - s.x[None, :], s.y[:, None] - s.y[None, :])
    near = {(i, j) for i, j in zip(*np.nonzero(d < reach), strict=True) if i < j}
    intact = set(zip(s.bi[s.state == INTACT].tolist(), s.bj[s.state == INTACT].tolist(),
                     strict=True))
    listed = list(zip(eng.cpi.tolist(), eng.cpj.tolist(), strict=True))
    assert len(listed) == len(set(listed))
    assert set(listed) == near - intact
    assert np.all(np.diff(eng.cpi) >= 0)
    assert len(near - intact) > 17  # the broken and removed bonds and the second neighbours
