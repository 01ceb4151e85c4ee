"""Checkpoint / resume of lattice runs: an interrupted run resumed from its last checkpoint
gives the dataset of the uninterrupted run, bit for bit."""

import numpy as np
import pytest

from craquelure.io import open_dataset
from craquelure.lattice.api import run as lattice_run
from craquelure.runner import checkpoint_path, fingerprint, read_checkpoint
from craquelure.scene import load_scene

# small versions of two scenes that exercise every piece of evolving state: contact lists,
# fracture and the bed / buoyancy (calving), melting with re-forming bonds on a periodic
# lattice (glen)
SCENES = {
    "calving": ["domain.nx=24", "domain.ny=8", "domain.water_level=5.0", "material.g=0.02",
                "fracture.start_time=30.0", "numerics.mass_damping_until=30.0",
                "numerics.series_every=20", "outputs.t_end=150.0", "outputs.frames=8",
                "numerics.checkpoint_every=2"],
    "glen": ["domain.nx=8", "domain.ny=6", "melting.freeze_every=200", "outputs.t_end=120.0",
             "outputs.frames=6", "numerics.checkpoint_every=2", "loads.top_shear_stress=0.05"],
}
# provenance attributes that differ between any two runs
VOLATILE = {"wall_time_s", "start_time", "scene_overrides", "run_particle_steps_per_s",
            "run_resumed_at_step", "history"}


def same_dataset(a, b):
    assert set(a.data_vars) == set(b.data_vars)
    for name in a.data_vars:
        np.testing.assert_array_equal(a[name].values, b[name].values, err_msg=name)
    for name in a.coords:
        np.testing.assert_array_equal(a[name].values, b[name].values, err_msg=name)
    keep = set(a.attrs) - VOLATILE
    np.testing.assert_equal({k: a.attrs[k] for k in keep}, {k: b.attrs[k] for k in keep})


@pytest.mark.parametrize("name", sorted(SCENES))
def test_interrupted_run_resumes_bit_identically(name, tmp_path):
    scene = load_scene(f"lattice/{name}", SCENES[name])
    full = lattice_run(scene, tmp_path / "full.nc", seed=3)
    assert not checkpoint_path(full).exists()  # removed once the dataset is written
    out = tmp_path / "part.nc"
    ck = lattice_run(scene, out, seed=3, stop_after_checkpoints=2)
    assert ck == checkpoint_path(out) and ck.exists() and not out.exists()
    ck_state = read_checkpoint(ck)
    assert 0 < ck_state["engine_step"]
    assert str(ck_state["runner_fingerprint"]) == fingerprint(scene, 3)
    lattice_run(scene, out, seed=3, resume=True)
    assert not ck.exists()
    a, b = open_dataset(full), open_dataset(out)
    same_dataset(a, b)
    if name == "calving":
        assert int((a.bond_state == 0).sum()) > 0  # beams broke after the checkpoint too
        assert float(a.bond_break_time.max()) > ck_state["engine_step"] * a.attrs["dt"]
    else:
        assert a.melted.values[-1] > 0


def test_checkpoint_of_another_seed_is_ignored(tmp_path, capsys):
    scene = load_scene("lattice/glen", SCENES["glen"])
    out = tmp_path / "run.nc"
    lattice_run(scene, out, seed=1, stop_after_checkpoints=1)
    lattice_run(scene, out, seed=2, resume=True)
    assert "refusing checkpoint" in capsys.readouterr().err
    fresh = lattice_run(scene, tmp_path / "fresh.nc", seed=2)
    same_dataset(open_dataset(out), open_dataset(fresh))


@pytest.mark.slow
def test_killed_cli_run_resumes_bit_identically(tmp_path):
    """A real interruption: ``craquelure run`` is killed (SIGKILL) once its first checkpoint
    exists; ``--resume`` completes it to the dataset of an uninterrupted run."""
    from ..killed_run import kill_and_resume

    sets = ["domain.nx=24", "domain.ny=8", "domain.water_level=5.0", "material.g=0.02",
            "fracture.start_time=30.0", "numerics.mass_damping_until=30.0",
            "outputs.t_end=1500.0", "outputs.frames=30", "numerics.checkpoint_every=1"]
    full, resumed, err = kill_and_resume(
        tmp_path, ["lattice/calving", "--seed", "4", *[a for s in sets for a in ("--set", s)]])
    assert "resumed from" in err and resumed.attrs["run_resumed_at_step"] > 0
    same_dataset(full, resumed)


@pytest.mark.slow
def test_sigterm_inside_a_long_frame_checkpoints_and_resumes(tmp_path):
    """One frame of ~140,000 steps (about 7 s on an idle core; dt_factor 0.03 so that the
    frame outlasts the first progress line, which comes after 2 s): SIGTERM once the first
    progress line is out (it comes from inside the frame) stops the run inside the frame with
    a checkpoint at the step it reached, exit 3; --resume gives the uninterrupted dataset."""
    from ..killed_run import check_message, stop_and_resume

    sets = ["domain.nx=48", "domain.ny=12", "domain.water_level=7.0", "material.g=0.02",
            "fracture.start_time=30.0", "numerics.mass_damping_until=30.0",
            "outputs.t_end=2000.0", "outputs.frames=1", "numerics.dt_factor=0.03"]
    stopped = stop_and_resume(tmp_path, ["lattice/calving", "--seed", "4",
                                         "--checkpoint-minutes", "0",
                                         *[a for s in sets for a in ("--set", s)]],
                              after="progress")
    step = check_message(stopped, tmp_path)
    # inside the one frame: past its start (frame 0 only recorded), before its end
    assert len(stopped.checkpoint["model_frames.time"]) == 1
    assert 0 < int(stopped.checkpoint["engine_step"]) == step < stopped.full.attrs["steps"]
    same_dataset(stopped.full, stopped.resumed)
