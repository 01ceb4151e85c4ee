"""Engine checks: spec section 12 items 2 (nonlinear kernel), 4, 5 and 6."""

import math

import numpy as np
import pytest
import scipy.linalg

from craquelure.errors import SimulationDiverged
from craquelure.lattice import beam
from craquelure.lattice.engine import LatticeState, lattice_system, stable_step_estimate
from craquelure.lattice.geometry import triangular_block
from craquelure.lattice.initial_state import probe_engine

from . import linear_beam


def small_block(nx=8, ny=8, model="shear_beam"):
    x, y, _ = triangular_block(nx, ny)
    c = beam.shear_beam(1.0, 0.2) if model == "shear_beam" else beam.euler_bernoulli(1.0, 0.7)
    return lattice_system(x, y, kn=c.kn, ka=c.a, kb=c.b), c


def true_critical_step(s: LatticeState) -> float:
    """2/sqrt(lambda_max(M^-1 K)) from a dense eigen-solve at rest."""
    K = linear_beam.assemble_global(s.x, s.y, s.bi, s.bj, s.kn, s.ka, s.kb).toarray()  # noqa: N806
    m = np.column_stack([s.mass, s.mass, s.inertia]).ravel()
    w2 = scipy.linalg.eigvalsh(K / np.sqrt(np.outer(m, m)))[-1]
    return 2.0 / math.sqrt(w2)


@pytest.mark.parametrize("model", ["shear_beam", "euler_bernoulli"])
def test_quick_step_estimate_is_safe(model):
    s, _ = small_block(model=model)
    ratio = true_critical_step(s) / stable_step_estimate(s)
    assert 1.0 < ratio < 1.6  # spec: safe by 1.16-1.37 for the infinite lattice


def momentum(eng) -> tuple[float, float, float]:
    """Discrete linear (x, y) and angular momentum at t - dt/2:
    m (x - x-)/dt and sum m r- x (r - r-)/dt + J (theta - theta-)/dt."""
    s = eng.system
    v = (eng.q - eng.qm) / eng.dt
    px, py = float(np.sum(s.mass * v[0])), float(np.sum(s.mass * v[1]))
    lz = float(np.sum(s.mass * (eng.qm[0] * v[1] - eng.qm[1] * v[0])) + np.sum(s.inertia * v[2]))
    return px, py, lz


@pytest.mark.parametrize("model", ["shear_beam", "euler_bernoulli"])
def test_energy_conserved_undamped_and_momentum_to_round_off(model):
    s, _ = small_block(model=model)
    dt = 0.2 * true_critical_step(s)
    eng = probe_engine(s, ("beams",), dict(dt=dt), series_every=50)
    rng = np.random.default_rng(3)
    # large enough for geometric nonlinearity: rotations of order 0.05 rad
    eng.set_velocity(*(0.02 * rng.normal(size=(3, s.n))))
    p0 = np.array(momentum(eng))
    eng.run(10_000)
    e = eng.series_array()[:, 10]
    drift = np.abs(e - e[0]) / e[0]
    assert drift.max() < 1e-3
    # no secular growth: last tenth not systematically above the first tenth
    assert abs(e[-100:].mean() - e[:100].mean()) / e[0] < 2e-4
    p1 = np.array(momentum(eng))
    scale = np.abs(p0).max() + 1e-3
    np.testing.assert_allclose(p1, p0, rtol=0, atol=1e-11 * scale * 1e3)


def test_blow_up_above_critical_step_is_detected():
    s, _ = small_block(5, 5)
    dt = 1.1 * true_critical_step(s)
    eng = probe_engine(s, ("beams",), dict(dt=dt), series_every=5)
    eng.set_velocity(*(1e-6 * np.random.default_rng(0).normal(size=(3, s.n))))
    with pytest.raises(SimulationDiverged, match=r"(finite|runaway) check failed at step \d+, "
                                                 r"t = .*\(worst particle \d+\)"):
        eng.run(5000)
    # and the same system just below the critical step stays bounded
    eng = probe_engine(s, ("beams",), dict(dt=0.95 * true_critical_step(s)), series_every=5)
    eng.set_velocity(*(1e-6 * np.random.default_rng(0).normal(size=(3, s.n))))
    eng.run(2000)


def test_nonlinear_cantilever_matches_beam_theory():
    """Kernel (co-rotational form) damped to rest under a small tip load: P l^3/(3 E I)."""
    c = beam.euler_bernoulli(1.0, 0.7)
    n = 10
    s = lattice_system(np.arange(n, dtype=float), np.zeros(n), kn=c.kn, ka=c.a, kb=c.b)
    s.fix[:, 0] = 1
    p = 1e-5
    s.load[1, -1] = p
    ell = 9.0
    rho_line = s.mass[0]
    w1 = 3.516 * math.sqrt(c.inertia / (rho_line * ell**4))
    eng = probe_engine(s, ("beams",), dict(dt=0.3 * stable_step_estimate(s), gamma=2 * w1),
                 series_every=1000)
    eng.run(int(12 / w1 / eng.dt))
    want = p * ell**3 / (3 * c.inertia)
    assert eng.q[1, -1] == pytest.approx(want, rel=1e-2)


def test_p_wave_speed_within_5_percent():
    nx, ny = 8, 150
    x, y, row = triangular_block(nx, ny)
    c = beam.shear_beam(1.0, 0.2)
    s = lattice_system(x, y, kn=c.kn, ka=c.a, kb=c.b, period_x=float(nx))
    v0 = 1e-4
    s.drive[1, row == 0] = 1
    s.fix[0, row == 0] = 1
    eng = probe_engine(s, ("beams",), dict(dt=0.2 * stable_step_estimate(s), drive_vy=v0),
                 series_every=1000)
    rows = (40, 110)
    arrival = {}
    chunk = 2
    while len(arrival) < 2:
        eng.run(chunk)
        vy = (eng.q[1] - eng.qm[1]) / eng.dt
        for r in rows:
            if r not in arrival and vy[row == r].mean() > 0.5 * v0:
                arrival[r] = eng.time - 0.5 * eng.dt
    m = beam.lattice_moduli(c.kn, c.ks)
    rho2 = s.mass[0] / beam.cell_area()
    want = math.sqrt(m["M"] / rho2)
    speed = (rows[1] - rows[0]) * math.sqrt(3) / 2 / (arrival[rows[1]] - arrival[rows[0]])
    assert speed == pytest.approx(want, rel=0.05)


def test_parallel_kernel_is_bit_identical_to_serial():
    """Fixed work chunks and ordered partial sums: the parallel kernel (any thread count)
    reproduces the serial trajectory and energy series exactly, with fracture on."""
    results = []
    for parallel in (False, True):
        s, c = small_block(12, 10)
        eng = probe_engine(s, ("beams", "fracture"), dict(dt=0.2 * stable_step_estimate(s),
                     beta=0.05, area=c.area, inertia=c.inertia, width=c.width, sigma0=0.02,
                     tau0=0.02), series_every=10, parallel=parallel)
        assert eng.flags["PARALLEL"] is parallel
        eng.set_velocity(*(0.01 * np.random.default_rng(5).normal(size=(3, s.n))))
        eng.run(400)
        results.append((eng.q.copy(), eng.series_array(), s.state.copy()))
    (q0, e0, b0), (q1, e1, b1) = results
    assert (b0 == 0).sum() > 0  # some beams broke
    np.testing.assert_array_equal(q0, q1)
    np.testing.assert_array_equal(e0, e1)
    np.testing.assert_array_equal(b0, b1)


def test_schema_owned_parameters_come_from_the_schema_and_nowhere_else():
    """The energy tolerance, the contact skin and the friction regularisation have one default,
    the schema's: a probe takes it from there, and an engine given none stops by name."""
    from craquelure.lattice.engine import PARAMS, Engine, schema_owned
    from craquelure.scene import schema_default

    s, _ = small_block(4, 4)
    eng = probe_engine(s, ("beams", "contact"), dict(dt=0.01, contact_stiffness=1.0))
    for name, path in schema_owned().items():
        assert eng.p[PARAMS.index(name)] == schema_default("lattice", path)
    assert probe_engine(s, ("beams",), dict(dt=0.01, energy_tolerance=0.5)).p[
        PARAMS.index("energy_tolerance")] == 0.5
    options = dict(series_every=1, node_averaged=False, bending=True, freeze_every=0,
                   refreeze_radius=math.nan)
    with pytest.raises(ValueError, match="energy_tolerance"):
        Engine(s, ("beams",), dict(dt=0.01), **options)
    with pytest.raises(ValueError, match="skin, friction_viscosity"):
        Engine(s, ("beams", "contact"), dict(dt=0.01, energy_tolerance=0.05), **options)
