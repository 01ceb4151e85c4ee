"""Integrators and guards: spec check 13 and the SimulationDiverged stops."""

import numpy as np
import pytest

from craquelure.errors import CraquelureError, SimulationDiverged
from craquelure.scene import load_scene
from craquelure.softdyn.engine import run
from craquelure.softdyn.initial_state import build

# Short T1 on the Poiseuille side: h0 = 0.1 R, F~ = 1e-2, T ~ 28 tau.
CASE = ["particles.h0=0.1", "loads.reduced_force=1.0e-2", "outputs.run_past_stop=false"]


def duration(*overrides):
    return run_case(*overrides)[0]


def run_case(*overrides, probe_tau=5.0):
    """(T1 duration / tau, state at t = probe_tau)."""
    setup = build(load_scene("softdyn/t1_single", CASE + list(overrides)))
    res = run(setup, sample_times_tau=np.array([probe_tau]))
    assert res.stopped
    k = int(np.argmin(np.abs(res.t / setup.tau - probe_tau)))
    assert res.t[k] / setup.tau == pytest.approx(probe_tau, rel=1e-12)
    return res.t_stop / setup.tau, res.y[k] / setup.system.radius


def test_rtol_convergence():
    """Check 13: T changes by < 1 % when rtol is cut 10x (LSODA, and BDF agrees)."""
    t8, t9 = duration("numerics.rtol=1.0e-8"), duration("numerics.rtol=1.0e-9")
    assert abs(t8 - t9) < 1e-2 * t9
    assert duration("numerics.integrator=BDF") == pytest.approx(t9, rel=1e-2)


HEUN = ("numerics.integrator=heun", "numerics.drift_tolerance=1.0",
        "numerics.baumgarte_time=0.1")


def test_fixed_step_heun_converges_at_second_order():
    """Check 13: heun runs converge to the adaptive reference (LSODA, rtol 1e-11) at 2nd order,
    on a smooth observable (the whole state at t = 5 tau) and on the T1 duration (the CD-force
    crossing, located between steps).

    Before the fix the order was 1.0: the last step of the load ramp evaluated its second stage
    at t = t_r on the right-hand side of the jump of dF/dt (O(dt) local error); the step grid now
    lands on t_r and the stage is taken on the left. Measured (dt = 0.02 ... 0.0025 tau): state
    errors 1.9e-6 -> 3.0e-8 R (orders 1.97, 1.98, 1.99), duration errors 9.8e-5 -> 1.7e-6 tau
    (orders 1.87, 2.11, 1.92). Tolerance 2 +- 0.3 on each halving (the spec's target), the
    least-squares order within 2 +- 0.15. The explicit step must resolve the Baumgarte rate
    1/tau_B, so tau_B = 0.1 tau here (the exact solution does not depend on tau_B), and its
    balance residual is O(dt^2) without error control: the drift guard is loosened for it."""
    t_ref, y_ref = run_case("numerics.rtol=1.0e-11", "numerics.atol=1.0e-14",
                            "numerics.baumgarte_time=0.1")
    dts = [0.02, 0.01, 0.005, 0.0025]
    err_t, err_y = [], []
    for dt in dts:
        t_h, y_h = run_case(*HEUN, f"numerics.dt={dt!r}")
        err_t.append(abs(t_h - t_ref))
        err_y.append(float(np.abs(y_h - y_ref).max()))
    for errs in (np.array(err_t), np.array(err_y)):
        orders = np.log2(errs[:-1] / errs[1:])
        assert np.all(np.abs(orders - 2.0) < 0.3), (errs, orders)
        fit = np.polyfit(np.log(dts), np.log(errs), 1)[0]
        assert fit == pytest.approx(2.0, abs=0.15), (errs, fit)
    assert err_t[-1] < 1e-4 * t_ref  # measured 6e-8 relative at dt = 0.0025 tau


def test_heun_needs_a_step():
    with pytest.raises(CraquelureError, match="dt"):
        duration("numerics.integrator=heun")


def test_drift_guard_stops_with_a_message():
    with pytest.raises(SimulationDiverged, match=r"force balance check failed at step \d+, "
                                                 r"t = .* tau: drifted: .*\(worst particle \d+\)"):
        duration("numerics.drift_tolerance=1.0e-30")


def test_gap_closing_heun_step_is_caught():
    """An explicit step far above the stability limit closes a gap or blows up: clear stop."""
    with pytest.raises(SimulationDiverged, match="gap closed|not finite|drifted"):
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
        run(setup, sample_times_tau=np.array([]))
