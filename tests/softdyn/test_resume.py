"""Soft Dynamics studies checkpoint through the runner (one study point per advance): a killed
phase scan resumes from its finished points to the uninterrupted dataset."""

from ..killed_run import kill_and_resume, same_dataset


def test_killed_cli_run_resumes_bit_identically(tmp_path):
    full, resumed, err = kill_and_resume(tmp_path, ["softdyn/t1_phase_ci",
                                                    "--checkpoint-every", "1"])
    assert "resumed from" in err
    assert resumed.attrs["run_resumed_at_step"] >= 1
    same_dataset(full, resumed)
