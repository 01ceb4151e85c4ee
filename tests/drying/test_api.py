"""The drying model API (craquelure.drying.api): `craquelure run`, the run dataset, resume after
a kill, guards."""

from __future__ import annotations

import numba
import numpy as np
import pytest
import xarray as xr

from craquelure.drying.api import run
from craquelure.drying.initial_state import build_initial_state
from craquelure.errors import SceneError, SimulationDiverged
from craquelure.io import write_dataset
from craquelure.runner import checkpoint_path


@pytest.fixture
def small_scene(make_scene):
    return make_scene(particles={"placement": "rsa"}, material={"drying_rate": 2e-3,
                                                                  "initial_stress_amplitude": 0.01},
                        numerics={"integrator": "abm4", "checkpoint_every": 100},
                        outputs={"t_end": 3.2, "times": [1.0, 2.0, 3.2], "series_every": 20})


def _init(tmp_path, scene, seed=4):
    path = tmp_path / "state.nc"
    ds = build_initial_state(scene, seed)
    ds.attrs["seed"] = seed
    write_dataset(ds, path)
    return path


def test_run_dataset_layout_and_cracking(tmp_path, small_scene):
    """Dims time x particle, the issue's variables with units, effects listed exactly, and the
    paste cracks (sigma_dry passes sigma_Y at t = 2.5) while staying finite."""
    out = run(small_scene, tmp_path / "run.nc", init=_init(tmp_path, small_scene))
    ds = xr.open_dataset(out)
    for name in ("x", "y", "vx", "vy", "alive", "mass", "rho", "mean_stress"):
        assert ds[name].dims == ("time", "particle") and "units" in ds[name].attrs
    for name in ("n_removed", "kinetic_energy", "elastic_energy", "momentum_x", "momentum_y"):
        assert ds[name].dims == ("step_time",)
    np.testing.assert_allclose(ds.time.values, [1.0, 2.0, 3.2], atol=1e-9)
    assert ds.attrs["effects"].split(",") == list(small_scene.effects)
    assert ds.attrs["h"] == 0.2 and ds.attrs["box_length"] == 1.0 and ds.attrs["seed"] == 4
    assert int(ds.n_removed[-1]) > 0
    alive = ds.alive.isel(time=-1).values.astype(bool)
    assert (ds.mass.isel(time=-1).values[~alive] == 0).all()
    assert np.isfinite(ds.mean_stress.values).all()
    assert not checkpoint_path(out).exists()


def test_resume_is_bit_identical(tmp_path, small_scene):
    """A run stopped after a checkpoint and resumed equals an uninterrupted run bit for bit."""
    init = _init(tmp_path, small_scene)
    full = xr.open_dataset(run(small_scene, tmp_path / "full.nc", init=init))
    part = tmp_path / "part.nc"
    ck = run(small_scene, part, init=init, stop_after_checkpoints=3)
    assert ck == checkpoint_path(part) and ck.exists() and not part.exists()
    resumed = xr.open_dataset(run(small_scene, part, init=init, resume=True))
    for name in ("x", "y", "vx", "vy", "alive", "mass", "rho", "mean_stress", "n_removed",
                 "kinetic_energy"):
        np.testing.assert_array_equal(full[name].values, resumed[name].values)


def test_resume_is_bit_identical_with_rkc2(tmp_path, small_scene):
    """The same with the adaptive rkc2 integrator through the removal events: the step
    controller, spectral radius and removal-event limit are checkpointed, and the snapshots
    land exactly on the output times."""
    scene = small_scene.with_overrides(["numerics.integrator=rkc2",
                                        "numerics.checkpoint_every=20",
                                        "numerics.step_control.spectral_radius_every=15",
                                        "outputs.series_every=5"])
    init = _init(tmp_path, scene)
    full = xr.open_dataset(run(scene, tmp_path / "full.nc", init=init))
    assert int(full.n_removed[-1]) > 0 and full.attrs["rejected_steps"] > 0
    assert 40 < full.attrs["steps"] < 300
    np.testing.assert_array_equal(full.time.values, [1.0, 2.0, 3.2])
    part = tmp_path / "part.nc"
    run(scene, part, init=init, stop_after_checkpoints=2)
    resumed = xr.open_dataset(run(scene, part, init=init, resume=True))
    for name in ("x", "y", "vx", "vy", "alive", "mass", "rho", "mean_stress", "n_removed",
                 "kinetic_energy", "time_step"):
        np.testing.assert_array_equal(full[name].values, resumed[name].values)
    for key in ("steps", "rate_evaluations", "rkc_stage_evaluations", "rejected_steps",
                "spectral_radius_evaluations"):
        assert full.attrs[key] == resumed.attrs[key]


def test_unknown_integrator_is_rejected_with_the_allowed_values(small_scene):
    with pytest.raises(SceneError, match=r"numerics.integrator.*abm4.*rk4.*rk2.*rkc2"):
        small_scene.with_overrides(["numerics.integrator=rkc4"])
    with pytest.raises(SceneError, match=r"numerics.step_control.tolerance"):
        small_scene.with_overrides(["numerics.step_control.tolerance=0"])


def test_stale_checkpoint_is_ignored(tmp_path, small_scene):
    """A checkpoint made from another scene is not resumed."""
    init = _init(tmp_path, small_scene)
    out = tmp_path / "run.nc"
    run(small_scene, out, init=init, stop_after_checkpoints=1)
    other = small_scene.with_overrides(["material.drying_rate=1e-3"])
    resumed = xr.open_dataset(run(other, out, init=init, resume=True))
    fresh = xr.open_dataset(run(other, tmp_path / "fresh.nc", init=init))
    np.testing.assert_array_equal(resumed.x.values, fresh.x.values)


def test_divergence_leaves_no_finished_file(tmp_path, small_scene):
    """With dt control off, dt = 0.2 (12x the RK4 viscous limit) blows up: the run stops with
    SimulationDiverged and neither the run file nor a checkpoint claims to be finished."""
    bad = small_scene.with_overrides(["numerics.dt=0.2", "numerics.integrator=rk4",
                                      "numerics.adapt_dt=false"])
    out = tmp_path / "run.nc"
    with pytest.raises(SimulationDiverged):
        run(bad, out, init=_init(tmp_path, small_scene))
    assert not out.exists()


@pytest.mark.skipif(numba.config.NUMBA_NUM_THREADS < 2, reason="needs 2 numba threads")
def test_run_is_independent_of_the_thread_count(tmp_path, small_scene):
    """Same scene, initial state and seed with 1 and 2 numba threads: bit-identical datasets
    (the rate function only reads the state and writes per-particle derivatives, every pair
    sum runs over the particle's own neighbour row in a fixed order), removals included."""
    init = _init(tmp_path, small_scene)
    out = {}
    old = numba.get_num_threads()
    try:
        for threads in (1, 2):
            numba.set_num_threads(threads)
            out[threads] = xr.open_dataset(run(small_scene, tmp_path / f"t{threads}.nc",
                                               init=init))
    finally:
        numba.set_num_threads(old)
    assert int(out[1].n_removed.values[-1]) > 0  # fracture happened within the run
    for name in ("x", "y", "vx", "vy", "alive", "mass", "rho", "mean_stress", "n_removed"):
        np.testing.assert_array_equal(out[1][name].values, out[2][name].values)


@pytest.mark.slow
def test_killed_cli_run_resumes_bit_identically(tmp_path):
    """SIGKILL after the first checkpoint, then ``--resume``: the uninterrupted dataset."""
    from ..killed_run import kill_and_resume, same_dataset

    full, resumed, err = kill_and_resume(tmp_path, KILLED_RUN)
    assert "resumed from" in err
    assert resumed.attrs["run_resumed_at_step"] > 0
    same_dataset(full, resumed)


KILLED_RUN = ["drying/ci", "--seed", "2", "--set", "outputs.t_end=1.0",
              "--set", "outputs.times=[0.5, 1.0]", "--set", "domain.box_length=1.0",
              "--set", "particles.n=400", "--set", "numerics.checkpoint_every=25"]


@pytest.mark.slow
def test_sigterm_run_checkpoints_and_resumes_bit_identically(tmp_path):
    """SIGTERM: a checkpoint at the next step (not the last periodic one), exit 3 with one
    line naming it; --resume gives the uninterrupted dataset (shared with the test above)."""
    from ..killed_run import check_message, same_dataset, stop_and_resume

    stopped = stop_and_resume(tmp_path, KILLED_RUN)
    step = check_message(stopped, tmp_path)
    assert int(stopped.checkpoint["engine_step_count"]) == step >= 25
    assert stopped.resumed.attrs["run_resumed_at_step"] == step
    same_dataset(stopped.full, stopped.resumed)
