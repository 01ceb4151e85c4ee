"""Sweep-level checks on a reduced grid (spec checks 10, 11, 12) and the phase scan."""

import math

import numpy as np
import pytest

from craquelure.scene import load_scene
from craquelure.softdyn import studies, theory
from craquelure.softdyn.api import study

C_N = 1.5 * math.pi


def run_study(scene, batch=None):
    """A study's points one after the other, in process (what the runner advances)."""
    model = study(scene, batch)
    while not model.done():
        model.advance()
    return model.result()


def sweep(h0, force, window):
    sc = load_scene("softdyn/t1_sweep", [f"study.h0={list(h0)!r}",
                                          f"study.reduced_force={list(force)!r}",
                                          f"study.window={list(window)!r}"])
    return run_study(sc)


@pytest.fixture(scope="module")
def hertz_grid():
    """F~ in {1e-4, 1e-2} at h0/h* in {0.1, 0.05}, F~ = 1e-4 also at 0.025, 1, 10, 30."""
    hs4, hs2 = theory.h_star(1e-4, 1.0), theory.h_star(1e-2, 1.0)
    h0 = sorted({r * hs4 for r in (0.025, 0.05, 0.1, 1.0, 10.0, 30.0)}
                | {r * hs2 for r in (0.05, 0.1)})
    ds = sweep(h0, [1e-4, 1e-2], (0.02, 31.0))
    ds = ds.where(ds.computed == 1)
    return ds


def at(ds, force, ratio):
    col = ds.sel(force=force)
    i = int(np.nanargmin(np.abs(np.log(col.h0_over_h_star.values / ratio))))
    assert col.h0_over_h_star.values[i] == pytest.approx(ratio, rel=1e-6)
    return float(col.duration.values[i])


def test_poiseuille_logarithmic_growth():
    """Check 10: h0 and h0/10 >= 20 h*: T(h0/10) - T(h0) = c_n ln 10 +- 40 % (F~ = 1e-5)."""
    ds = sweep([1e-2, 1e-1], [1e-5], (20.0, 1e4))
    t = ds.duration.sel(force=1e-5).values
    assert np.all(ds.finished == 1)
    assert t[0] - t[1] == pytest.approx(C_N * math.log(10), rel=0.4)


def test_hertz_slope_prediction_and_collapse(hertz_grid):
    """Check 11: d ln T/d ln h0 in [-2.2, -1.5] between h0/h* = 0.1 and 0.05; T at 0.1 within a
    factor 2 of (c_n/2) 100 + T_P; at fixed h0/h* <= 0.1, T independent of F~ within 10 %."""
    for force in (1e-4, 1e-2):
        t1, t05 = at(hertz_grid, force, 0.1), at(hertz_grid, force, 0.05)
        slope = math.log(t05 / t1) / math.log(0.5)
        assert -2.2 <= slope <= -1.5
        hs = theory.h_star(force, 1.0)
        pred = 0.5 * C_N * 100 + theory.t_poiseuille(0.1 * hs, C_N)
        assert pred / 2 <= t1 <= 2 * pred
    for ratio in (0.1, 0.05):
        assert at(hertz_grid, 1e-4, ratio) == pytest.approx(at(hertz_grid, 1e-2, ratio),
                                                            rel=0.1)


def test_fig5_trend(hertz_grid):
    """Check 12: T/tau decreases monotonically in h0 at fixed F~ and spans >= 2 decades."""
    col = hertz_grid.sel(force=1e-4).dropna("h0", subset=["duration"])
    t = col.duration.values
    assert col.h0.size >= 6
    assert np.all(np.diff(t) < 0)
    assert math.log10(t.max() / t.min()) >= 2.0


def test_sweep_dataset_layout(hertz_grid):
    """Named dims (h0, force); predictions and regime labels alongside the durations."""
    ds = hertz_grid
    assert ds.duration.dims == ("h0", "force")
    for name in ("T_P", "T_H", "T_sep", "regime", "h0_over_h_star", "finished"):
        assert name in ds
    col = ds.sel(force=1e-4)
    lab = dict(zip(np.round(col.h0_over_h_star.values, 3), col.regime.values, strict=True))
    assert lab[0.05] == "hertz" and lab[30.0] == "poiseuille" and lab[1.0] == "crossover"


def test_phase_scan_matches_the_line():
    """Fig. 3: a T1 iff F_h < F_v/sqrt3 (two points either side of the line)."""
    sc = load_scene("softdyn/t1_phase_ci")
    ds = run_study(sc)
    assert np.array_equal(ds.occurred.values, ds.predicted.values)
    assert ds.occurred.sel(fh_over_fv=0.3).item() == 1.0
    assert ds.occurred.sel(fh_over_fv=0.8).item() == 0.0


def test_sweep_batches_partition_the_window_and_balance_the_cost():
    """Workflow batching: every point of the window in exactly one batch, deterministic, and
    the estimated costs of the default sweep's batches within 25 % of each other."""
    sc = load_scene("softdyn/t1_sweep")
    points = studies.sweep_points(sc)
    for n in (1, 2, 4, 100):
        batches = studies.sweep_batches(sc, n)
        assert len(batches) == min(n, len(points)) and all(batches)
        assert sorted(p for b in batches for p in b) == sorted(points)
        assert batches == studies.sweep_batches(sc, n)
    costs = [sum(studies.point_cost(sc, *p) for p in b) for b in studies.sweep_batches(sc, 2)]
    assert max(costs) <= 1.25 * min(costs)


def test_batched_sweep_equals_the_serial_sweep():
    """Aggregating batch datasets (dim ``point``) gives the serial sweep's dataset."""
    sc = load_scene("softdyn/t1_sweep_ci")
    serial = run_study(sc)
    batches = [run_study(sc, b) for b in studies.sweep_batches(sc, 2)]
    assert all(b.sizes["point"] >= 1 for b in batches)
    # a job beyond the number of grid points writes an empty batch, which adds nothing
    merged = studies.aggregate_sweep(sc, [*batches, studies.batch_dataset([])])
    assert merged.duration.dims == ("h0", "force")
    np.testing.assert_array_equal(merged.duration.values, serial.duration.values)
    np.testing.assert_array_equal(merged.finished.values, serial.finished.values)
    assert int(merged.computed.sum()) == len(studies.sweep_points(sc))
