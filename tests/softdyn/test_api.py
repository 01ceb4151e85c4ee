"""Soft Dynamics studies checkpoint through the runner (one study point per advance): a killed
phase scan resumes from its finished points to the uninterrupted dataset."""

import signal

import pytest

from ..killed_run import check_message, kill_and_resume, same_dataset, stop_and_resume


@pytest.mark.slow
def test_killed_cli_run_resumes_bit_identically(tmp_path):
    full, resumed, err = kill_and_resume(tmp_path, ["softdyn/t1_phase_ci",
                                                    "--checkpoint-every", "1"])
    assert "resumed from" in err
    assert resumed.attrs["run_resumed_at_step"] >= 1
    same_dataset(full, resumed)


@pytest.mark.slow
def test_sigint_run_checkpoints_and_resumes_bit_identically(tmp_path):
    """SIGINT (Ctrl-C) as SIGTERM: the finished points are checkpointed, the point in progress
    is redone on resume; exit 3, one line naming the checkpoint; the uninterrupted dataset."""
    stopped = stop_and_resume(tmp_path, ["softdyn/t1_phase_ci", "--checkpoint-every", "1"],
                              sig=signal.SIGINT)
    points = check_message(stopped, tmp_path, signal.SIGINT)
    assert points >= 1 and sum(k.startswith("point_") for k in stopped.checkpoint) == points
    same_dataset(stopped.full, stopped.resumed)
