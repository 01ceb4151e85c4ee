"""Effects on demand: contact, gravity, buoyancy, drag, bed; kernel specialisation; spec check
11 (determinism of the calving and fretting scenes, fragment labelling)."""

import math

import numpy as np
import pytest

from craquelure import codegen
from craquelure.lattice import fragments
from craquelure.lattice.engine import (
    KERNEL_TEMPLATE,
    LatticeState,
    kernel_flags,
    lattice_system,
)
from craquelure.lattice.geometry import INTACT, REMOVED, triangular_block
from craquelure.lattice.initial_state import make_engine, probe_engine
from craquelure.scene import load_scene


def particles(x, y, vx=None):
    n = len(x)
    m = math.pi / 4
    return LatticeState(x=np.asarray(x, float), y=np.asarray(y, float), mass=np.full(n, m),
                  inertia=np.full(n, m / 8), diameter=np.ones(n), bi=np.zeros(0, np.int64),
                  bj=np.zeros(0, np.int64), kn=np.zeros(0), ka=np.zeros(0), kb=np.zeros(0))


def test_generated_kernels_differ_only_in_flags():
    options = dict(periodic_x=False, node_averaged=False, bending=False, parallel=True)
    a, _ = codegen.generate(KERNEL_TEMPLATE, kernel_flags(("beams",), **options))
    b, _ = codegen.generate(KERNEL_TEMPLATE, kernel_flags(("beams", "contact"), **options))
    assert "CONTACT = False" in a and "CONTACT = True" in b
    diff = [(x, y) for x, y in zip(a.splitlines(), b.splitlines(), strict=True) if x != y]
    assert diff == [("CONTACT = False", "CONTACT = True")]


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


FLUID = ("gravity", "buoyancy", "drag", "bed")  # one compiled kernel for the three tests


def test_particle_rests_on_bed_with_spring_overlap():
    s = particles([0.0], [0.6])
    m, g, kb = s.mass[0], 0.01, 5.0
    eng = probe_engine(s, FLUID, dict(dt=0.02, g=g, bed_level=0.0, bed_stiffness=kb,
                                bed_damping=2 * math.sqrt(kb / m)), series_every=100)
    eng.run(20000)
    assert eng.q[1, 0] == pytest.approx(0.5 - m * g / kb, rel=1e-6)
    series = eng.series_array()
    assert abs(series[-1, 10] - series[0, 10]) < 1e-3 * series[-1, 7]


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


TINY = {
    "calving": ["domain.nx=24", "domain.ny=6", "domain.water_level=3.8", "material.g=6.0e-3",
                "fracture.start_time=30.0", "numerics.mass_damping_until=30.0",
                "outputs.t_end=100.0"],
    "fretting": ["domain.nx=30", "domain.ny=8", "domain.pad.radius=4.0",
                 "domain.pad.period=40.0", "domain.pad.press_time=20.0",
                 "fracture.start_time=20.0", "numerics.mass_damping_until=20.0",
                 "outputs.t_end=70.0"],
}


@pytest.mark.parametrize("name", ["calving", "fretting"])
def test_scene_is_deterministic_and_labelling_conserves_particles(name):
    scene = load_scene(f"lattice/{name}", TINY[name])
    runs = []
    for _ in range(2):
        eng, labels = make_engine(scene, seed=7)
        eng.run(int(scene.get("outputs.t_end") / eng.dt))
        runs.append((eng.q.copy(), eng.system.state.copy(), eng.series_array(), labels))
    np.testing.assert_array_equal(runs[0][0], runs[1][0])
    np.testing.assert_array_equal(runs[0][1], runs[1][1])
    np.testing.assert_array_equal(runs[0][2], runs[1][2])
    body = runs[0][3]["body"] == 0
    lab = fragments.label(body.size, eng.system.bi, eng.system.bj, runs[0][1] == 1, body)
    assert fragments.sizes(lab).sum() == body.sum()
    assert (runs[0][1] == 0).sum() > 0  # something broke


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
