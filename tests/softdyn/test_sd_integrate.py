"""Integrators and guards: spec check 13 and the SimulationDiverged stops."""

import numpy as np
import pytest

from craquelure.errors import CraquelureError, SimulationDiverged
from craquelure.scene import load_scene
from craquelure.softdyn.scenarios import build

# Short T1 on the Poiseuille side: h0 = 0.1 R, F~ = 1e-2, T ~ 28 tau.
CASE = ["particles.h0=0.1", "loads.reduced_force=1.0e-2", "outputs.run_past_stop=false"]


def duration(*overrides):
    setup = build(load_scene("softdyn/t1_single", CASE + list(overrides)))
    res = setup.run(sample_times_tau=np.array([]))
    assert res.stopped
    return res.t_stop / setup.tau


def test_rtol_convergence():
    """Check 13: T changes by < 1 % when rtol is cut 10x (LSODA, and BDF agrees)."""
    t8, t9 = duration("numerics.rtol=1.0e-8"), duration("numerics.rtol=1.0e-9")
    assert abs(t8 - t9) < 1e-2 * t9
    assert duration("numerics.integrator=BDF") == pytest.approx(t9, rel=1e-2)


def test_fixed_step_heun_converges():
    """Check 13 (PARTLY MISSED): heun durations converge to the adaptive one, but at observed
    order 1.0, not 2 (suspected cause: the right-hand side jumps with sgn(s) where a pair's
    deflection crosses 0, e.g. the far CD pair; not resolved).
    The explicit step must resolve the Baumgarte rate 1/tau_B, so tau_B = 0.1 tau here, and its
    balance residual is O(dt^2) without error control: the drift guard is loosened for it."""
    ref = duration("numerics.rtol=1.0e-10", "numerics.atol=1.0e-13")
    errs = [abs(duration("numerics.integrator=heun", f"numerics.dt={dt!r}",
                         "numerics.drift_tolerance=1.0", "numerics.baumgarte_time=0.1") - ref)
            for dt in (0.01, 0.005, 0.0025)]
    orders = np.log2(np.array(errs[:-1]) / np.array(errs[1:]))
    assert np.all(orders > 0.9), (errs, orders)
    assert errs[-1] < 1e-3 * ref


def test_heun_needs_a_step():
    with pytest.raises(CraquelureError, match="dt"):
        duration("numerics.integrator=heun")


def test_drift_guard_stops_with_a_message():
    with pytest.raises(SimulationDiverged, match="force balance drifted at t = .* tau"):
        duration("numerics.drift_tolerance=1.0e-30")


def test_gap_closing_heun_step_is_caught():
    """An explicit step far above the stability limit closes a gap or blows up: clear stop."""
    with pytest.raises(SimulationDiverged, match="gap closed|non-finite|drifted"):
        duration("numerics.integrator=heun", "numerics.dt=5.0")


def test_nan_in_the_rhs_is_caught():
    setup = build(load_scene("softdyn/t1_single", CASE))
    rhs, calls = setup.system.rhs, [0]

    def poisoned(t, y):
        calls[0] += 1
        out = rhs(t, y)
        return out * np.nan if calls[0] > 200 else out

    setup.system.rhs = poisoned
    with pytest.raises(SimulationDiverged):
        setup.run(sample_times_tau=np.array([]))
