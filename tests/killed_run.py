"""A real interruption for the resume tests of every model: ``craquelure run`` is killed
(SIGKILL) once its first checkpoint exists, or stopped (SIGTERM/SIGINT) once it has checkpointed
or printed its first progress line; ``--resume`` completes it, and the dataset must equal that
of an uninterrupted run bit for bit (computed once per command line and test session)."""

from __future__ import annotations

import os
import re
import signal
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from craquelure.errors import INTERRUPTED_EXIT
from craquelure.io import open_dataset
from craquelure.runner import checkpoint_path, read_checkpoint

# attributes that differ between any two runs of the same scene and seed
VOLATILE = {"wall_time_s", "start_time", "run_particle_steps_per_s", "run_resumed_at_step",
            "history"}  # history: UTC time and command line of the write (CF)


def same_dataset(a, b) -> None:
    assert set(a.data_vars) == set(b.data_vars)
    for name in [*a.data_vars, *a.coords]:
        np.testing.assert_array_equal(a[name].values, b[name].values, err_msg=name)
    keep = set(a.attrs) - VOLATILE
    np.testing.assert_equal({k: a.attrs[k] for k in keep}, {k: b.attrs[k] for k in keep})


ENV = {**os.environ, "NUMBA_NUM_THREADS": "1"}
# uninterrupted runs by command line: shared by the SIGKILL and SIGTERM tests of a model
_FULL: dict[tuple[str, ...], Path] = {}


def cli(args: list[str], out: Path, *extra: str) -> list[str]:
    return [sys.executable, "-m", "craquelure", "run", *args, "--out", str(out), *extra]


def uninterrupted(tmp_path, args: list[str]):
    """The dataset of ``craquelure run *args`` run through."""
    key = tuple(args)
    if key not in _FULL or not _FULL[key].exists():
        full = tmp_path / "full.nc"
        subprocess.run(cli(args, full), env=ENV, check=True, capture_output=True)
        _FULL[key] = full
    return open_dataset(_FULL[key])


def _wait(proc, ready, what: str) -> None:
    deadline = time.monotonic() + 600
    while not ready() and proc.poll() is None and time.monotonic() < deadline:
        time.sleep(0.02)
    assert proc.poll() is None, f"the run ended (exit {proc.returncode}) before {what}"


def kill_and_resume(tmp_path, args: list[str]) -> tuple:
    """(uninterrupted dataset, killed-and-resumed dataset, resume's stderr) of
    ``craquelure run *args``."""
    out = tmp_path / "killed.nc"
    ck = checkpoint_path(out)
    proc = subprocess.Popen(cli(args, out), env=ENV, stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL)
    _wait(proc, ck.exists, "a checkpoint")
    os.kill(proc.pid, signal.SIGKILL)
    proc.wait()
    assert ck.exists() and not out.exists()  # killed after a checkpoint, before the end
    resumed = subprocess.run(cli(args, out, "--resume"), env=ENV, check=True,
                             capture_output=True, text=True)
    assert out.exists() and not ck.exists()
    return uninterrupted(tmp_path, args), open_dataset(out), resumed.stderr


@dataclass
class Stopped:
    full: object  # the uninterrupted dataset
    resumed: object  # the dataset of the stopped run resumed with --resume
    message: str  # the stopped run's last stderr line
    checkpoint: dict  # the checkpoint it wrote
    resume_err: str  # stderr of the resume


def stop_and_resume(tmp_path, args: list[str], sig=signal.SIGTERM,
                    after: str = "checkpoint") -> Stopped:
    """``craquelure run *args`` sent ``sig`` once its first checkpoint exists (``after=
    "checkpoint"``) or once it printed its first progress line (``"progress"``); it must exit
    with status 3 leaving a checkpoint and no dataset; then ``--resume``."""
    out = tmp_path / "stopped.nc"
    ck, log = checkpoint_path(out), tmp_path / "stopped.err"
    with open(log, "w") as err:
        proc = subprocess.Popen(cli(args, out), env=ENV, stdout=subprocess.DEVNULL, stderr=err)
        if after == "checkpoint":
            _wait(proc, ck.exists, "a checkpoint")
        else:
            _wait(proc, lambda: "elapsed" in log.read_text(), "its first progress line")
        os.kill(proc.pid, sig)
        proc.wait(timeout=120)
    lines = log.read_text().splitlines()
    assert proc.returncode == INTERRUPTED_EXIT, lines[-5:]
    assert ck.exists() and not out.exists()
    assert not list(tmp_path.glob(".*.tmp-*"))  # no temporary left
    state = read_checkpoint(ck)
    resumed = subprocess.run(cli(args, out, "--resume"), env=ENV, check=True,
                             capture_output=True, text=True)
    assert out.exists() and not ck.exists()
    return Stopped(uninterrupted(tmp_path, args), open_dataset(out), lines[-1], state,
                   resumed.stderr)


def check_message(stopped: Stopped, tmp_path, sig=signal.SIGTERM) -> int:
    """The stopped run's one line names the signal, the step and the checkpoint; the resumed
    run starts at that step. Returns the step."""
    m = re.fullmatch(rf"craquelure run: interrupted: {sig.name} at t = \S+ (?:\S+ )?\(step "
                     rf"(\d+)\): checkpoint written to (\S+); run again with --resume to "
                     rf"continue", stopped.message)
    assert m, stopped.message
    assert Path(m.group(2)) == checkpoint_path(tmp_path / "stopped.nc")
    assert f"(step {m.group(1)})" in stopped.resume_err
    return int(m.group(1))
