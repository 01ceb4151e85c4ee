"""Impact runs checkpoint through the runner: a killed run resumes bit-identically."""

from ..killed_run import kill_and_resume, same_dataset


def test_killed_cli_run_resumes_bit_identically(tmp_path):
    full, resumed, err = kill_and_resume(tmp_path, [
        "impact/ci", "--seed", "1", "--set", "outputs.t_end=1.0e-4",
        "--set", "outputs.snapshot_times=[5.0e-5]", "--checkpoint-every", "40"])
    assert "resumed from" in err
    assert resumed.attrs["run_resumed_at_step"] > 0
    same_dataset(full, resumed)
