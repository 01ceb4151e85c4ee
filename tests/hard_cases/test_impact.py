"""Impact hard cases on the CI disc (about 200 particles, 0.2 ms): supports kappa = 0.5 and
2.0, five times the source's 15 m/s, zero and near-zero (1e-12 of the mean) masses in the bulk
and on a pre-crack line, and an absurd 1e7 m/s. Each run must finish with finite fields and
an energy budget that closes (the engine books kinetic, internal, viscous, artificial-stress,
penalty and kinematic energies; measured errors 3e-4 to 4e-3 of E(0)), or, for the absurd
speed, finish or stop with the guard's SimulationDiverged, never another exception."""

from __future__ import annotations

import numpy as np
import pytest

import craquelure.impact.api as impact_api
from craquelure.errors import SimulationDiverged
from craquelure.scene import load_scene
from tests.impact.runs import simulate as simulate_run

BALANCE = 0.02  # largest |E(t) - E(0)|/E(0) allowed: 5x the largest measured (4e-3)


def simulate(overrides, masses=None, monkeypatch=None):
    scene = load_scene("impact/ci", [*overrides, "outputs.snapshot_times=[]"])
    if masses is not None:
        build = impact_api.build_specimen

        def modified(scene, seed):
            sp = build(scene, seed)
            masses(sp)
            return sp

        monkeypatch.setattr(impact_api, "build_specimen", modified)
    return simulate_run(scene, 1, progress=False)


def assert_sound(sp, eng, series):
    st = eng.state
    for name in ("x", "y", "vx", "vy", "rho", "h"):
        assert np.isfinite(getattr(st, name)).all(), name
    assert np.isfinite(st.sig).all()
    assert np.abs(series["balance_error"]).max() < BALANCE
    assert eng.t == pytest.approx(2.0e-4, rel=1e-9)


@pytest.fixture(scope="module")
def baseline():
    sp, eng, series, _ = simulate([])
    return series


@pytest.mark.parametrize("kappa", [0.5, 2.0])
def test_support_multiplier_extremes(kappa):
    sp, eng, series, _ = simulate([f"numerics.kappa={kappa}"])
    assert_sound(sp, eng, series)


def test_five_times_the_source_speed_cracks_more(baseline):
    sp, eng, series, _ = simulate(["particles.impact_velocity=75.0"])
    assert_sound(sp, eng, series)
    # 25x the kinetic energy: more of the disc is cracked than at 15 m/s
    assert series["cracked_fraction"][-1] > baseline["cracked_fraction"][-1]


@pytest.mark.parametrize("where", ["bulk", "precrack"])
@pytest.mark.parametrize("fraction", [0.0, 1e-12])
def test_zero_and_near_zero_masses(where, fraction, monkeypatch):
    """Masses 0 or 1e-12 of the mean on 10 % of the particles (bulk) or on the particles of
    the pre-crack line pf1 (which the scene would set to 0)."""
    def masses(sp):
        mean = sp.mass[sp.mass > 0].mean()
        if where == "bulk":
            pick = np.random.default_rng(5).random(sp.n) < 0.1
        else:
            pick = sp.precrack
            assert pick.sum() > 5
        sp.mass[pick] = fraction * mean

    overrides = ["particles.precrack=pf1"] if where == "precrack" else []
    sp, eng, series, _ = simulate(overrides, masses, monkeypatch)
    assert_sound(sp, eng, series)
    light = sp.mass < 1e-6 * sp.mass.max()
    assert light.any()
    # light particles ride along with their neighbours: no runaway speeds
    speed = np.hypot(eng.state.vx, eng.state.vy)
    assert speed.max() < 10 * 15.0


def test_absurd_speed_finishes_or_stops_with_the_guard():
    """1e7 m/s (3000x the P-wave speed); it used to end in a ZeroDivisionError inside a kernel
    (numba raises Python errors): arithmetic failures are now the guard's stop."""
    try:
        sp, eng, series, _ = simulate(["particles.impact_velocity=1.0e7", "outputs.t_end=1.0e-6"])
    except SimulationDiverged as exc:
        assert "t = " in str(exc)
        return
    assert np.isfinite(eng.state.x).all() and np.isfinite(eng.state.sig).all()


@pytest.mark.hard_slow
def test_absurd_speed_longer():
    try:
        simulate(["particles.impact_velocity=1.0e7", "outputs.t_end=2.0e-5"])
    except SimulationDiverged as exc:
        assert "t = " in str(exc)


def min_pair_distance(s, st) -> float:
    dx = st.x[:, None] - st.x[None, :]
    dy = st.y[:, None] - st.y[None, :]
    dx -= s.periodic_box[0] * np.rint(dx / s.periodic_box[0])
    dy -= s.periodic_box[1] * np.rint(dy / s.periodic_box[1])
    d = np.hypot(dx, dy)
    np.fill_diagonal(d, np.inf)
    return float(d.min() / s.spacing)


def stretched_block(as_epsilon, steps=8000):
    """Periodic 16 x 16 block held in biaxial tension 10 f_t (elastic, no damage, no
    artificial viscosity), h(0) = 0.84 Delta (kappa 0.7, the fastest linear growth of the
    tensile instability in the table of craquelure.impact.effects.artificial_stress), 1 %
    position noise: the smallest pair distance over the run, in units of Delta."""
    from craquelure.impact.engine import Engine
    from tests.impact.test_engine import MAT, periodic_block

    s, st = periodic_block(16, 16, effects=("elasticity", "artificial_stress"),
                           as_epsilon=as_epsilon, noise=0.01, kappa=0.7)
    st.sig[:, 0] = st.nom[:, 0] = st.sig[:, 1] = st.nom[:, 1] = 10 * MAT.f_t
    eng = Engine(s, st)
    smallest = np.inf
    for n in range(steps):
        eng.step()
        if n % 100 == 99:
            eng.check_health()
            smallest = min(smallest, min_pair_distance(s, st))
    return smallest


@pytest.mark.hard_slow
def test_stretched_block_with_and_without_artificial_stress(capsys):
    """With the project's artificial stress (auto: eps_AS = 0.2 at kappa 0.7) no clumping:
    pairs stay >= 0.7 Delta. Without it the issue expects clumping; measured 2026-12-01: the
    smallest distance only drops to 0.93 Delta in 8000 steps (0.93 with eps_AS too), so this
    SPH does not clump in this test: reported, not asserted (an honest miss)."""
    from craquelure.impact.effects.artificial_stress import auto_epsilon

    without = stretched_block(0.0)
    with_as = stretched_block(auto_epsilon(0.84))
    with capsys.disabled():
        print(f"\n[stretched block] smallest pair distance: without AS {without:.3f} Delta, "
              f"with AS {with_as:.3f} Delta")
    assert with_as >= 0.7
