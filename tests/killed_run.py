"""A real interruption for the resume tests of every model: ``craquelure run`` is killed
(SIGKILL) once its first checkpoint exists, ``--resume`` completes it, and the dataset must
equal that of an uninterrupted run bit for bit."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time

import numpy as np

from craquelure.io import open_dataset
from craquelure.runner import checkpoint_path

# attributes that differ between any two runs of the same scene and seed
VOLATILE = {"wall_time_s", "start_time", "run_particle_steps_per_s", "run_resumed_at_step",
            "history"}  # history: UTC time and command line of the write (CF)


def same_dataset(a, b) -> None:
    assert set(a.data_vars) == set(b.data_vars)
    for name in [*a.data_vars, *a.coords]:
        np.testing.assert_array_equal(a[name].values, b[name].values, err_msg=name)
    keep = set(a.attrs) - VOLATILE
    np.testing.assert_equal({k: a.attrs[k] for k in keep}, {k: b.attrs[k] for k in keep})


def kill_and_resume(tmp_path, args: list[str]) -> tuple:
    """(uninterrupted dataset, killed-and-resumed dataset, resume's stderr) of
    ``craquelure run *args``."""
    env = {**os.environ, "NUMBA_NUM_THREADS": "1"}

    def cli(out, *extra):
        return [sys.executable, "-m", "craquelure", "run", *args, "--out", str(out), *extra]

    out = tmp_path / "killed.nc"
    ck = checkpoint_path(out)
    proc = subprocess.Popen(cli(out), env=env, stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL)
    deadline = time.monotonic() + 600
    while not ck.exists() and proc.poll() is None and time.monotonic() < deadline:
        time.sleep(0.02)
    assert proc.poll() is None, f"the run ended (exit {proc.returncode}) before a checkpoint"
    os.kill(proc.pid, signal.SIGKILL)
    proc.wait()
    assert ck.exists() and not out.exists()  # killed after a checkpoint, before the end
    resumed = subprocess.run(cli(out, "--resume"), env=env, check=True, capture_output=True,
                             text=True)
    assert out.exists() and not ck.exists()
    full = tmp_path / "full.nc"
    subprocess.run(cli(full), env=env, check=True, capture_output=True)
    return open_dataset(full), open_dataset(out), resumed.stderr
