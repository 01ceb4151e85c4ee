"""Impact runs checkpoint through the runner: a killed run resumes bit-identically."""

from ..killed_run import check_message, kill_and_resume, same_dataset, stop_and_resume


def test_killed_cli_run_resumes_bit_identically(tmp_path):
    full, resumed, err = kill_and_resume(tmp_path, [
        "impact/ci", "--seed", "1", "--set", "outputs.t_end=1.0e-4",
        "--set", "outputs.snapshot_times=[5.0e-5]", "--checkpoint-every", "40"])
    assert "resumed from" in err
    assert resumed.attrs["run_resumed_at_step"] > 0
    same_dataset(full, resumed)


def test_killed_3d_run_resumes_bit_identically(tmp_path):
    """The 3D state (z, v_z, six stress components, the k-d tree's neighbour list) goes
    through the same checkpoint: the tiny 3D CI disc (336 particles)."""
    full, resumed, err = kill_and_resume(tmp_path, [
        "impact/ci3d", "--seed", "1", "--set", "particles.masses.distribution=uniform",
        "--checkpoint-every", "40"])
    assert "resumed from" in err
    assert resumed.attrs["run_resumed_at_step"] > 0 and resumed.attrs["dim"] == 3
    same_dataset(full, resumed)


def test_sigterm_run_checkpoints_and_resumes_bit_identically(tmp_path):
    """SIGTERM (a scheduler's time limit): a checkpoint at the next step, exit 3 with one
    line naming it; --resume gives the uninterrupted dataset (shared with the test above)."""
    stopped = stop_and_resume(tmp_path, [
        "impact/ci", "--seed", "1", "--set", "outputs.t_end=1.0e-4",
        "--set", "outputs.snapshot_times=[5.0e-5]", "--checkpoint-every", "40"])
    step = check_message(stopped, tmp_path)
    assert step > 0 and int(stopped.checkpoint["engine_step_count"]) == step
    assert stopped.resumed.attrs["run_resumed_at_step"] == step
    same_dataset(stopped.full, stopped.resumed)
