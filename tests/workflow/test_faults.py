"""The CI workflow under faults, on a subset of its targets (a drying, a lattice and an
impact run and the mass-consistency dataset the drying run reads): stopped by SIGTERM (as a
scheduler stops a job at its time limit: every process of it), one random simulation job
killed (SIGKILL), Snakemake itself killed (SIGKILL). After a restart every dataset must equal
that of the uninterrupted CI run (the session's ``ci_run``, also used by test_snakemake), no
temporary or checkpoint may be left, and an output whose job was cut short is never used:
Snakemake redoes it.
"""

from __future__ import annotations

import os
import random
import signal
import subprocess
import sys
import time
from pathlib import Path

import yaml

from craquelure.io import open_dataset
from tests.killed_run import same_dataset
from tests.workflow.test_snakemake import snakemake, workflow_copy

# the drying run is the longest job of the CI profile: SIGTERM finds it in its loop (softdyn's
# runs are covered by its own SIGINT test, tests/softdyn)
TARGETS = ("results/drying/ci/run/seed1.nc", "results/lattice/calving/run.nc",
           "results/impact/ci/uniform_none/kappa1.0/seed1.nc")
COMPARED = (*TARGETS, "results/mass/ci/seed1.nc")
ARGS = (*TARGETS, "--cores", "2", "--configfile", "config/ci.yaml")


def start(work: Path) -> subprocess.Popen:
    """Snakemake on the subset, in a session of its own (its jobs are in it too)."""
    env = {**os.environ, "PATH": f"{Path(sys.executable).parent}{os.pathsep}{os.environ['PATH']}"}
    log = open(work / "snakemake.out", "w")  # noqa: SIM115 - closed with the process
    return subprocess.Popen([sys.executable, "-m", "snakemake", *ARGS], cwd=work, env=env,
                            stdout=log, stderr=subprocess.STDOUT, start_new_session=True)


def session(sid: int) -> list[int]:
    """The processes of session ``sid`` (Snakemake, its shells and jobs)."""
    pids = []
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat.read_text().rsplit(")", 1)[1].split()
        except OSError:
            continue
        if int(fields[3]) == sid:
            pids.append(int(stat.parent.name))
    return pids


def running_runs(sid: int) -> dict[int, str]:
    """{pid: --out} of the ``craquelure run`` processes of the session."""
    runs = {}
    for pid in session(sid):
        try:
            argv = (Path("/proc") / str(pid) / "cmdline").read_bytes().decode().split("\0")
        except OSError:
            continue
        if "craquelure" in argv and "run" in argv and "--out" in argv:
            runs[pid] = argv[argv.index("--out") + 1]
    return runs


def wait_for(ready, what: str, timeout: float = 900) -> None:
    deadline = time.monotonic() + timeout
    while not ready():
        assert time.monotonic() < deadline, f"timed out waiting for {what}"
        time.sleep(0.05)


def restart(work: Path) -> subprocess.CompletedProcess:
    proc = snakemake(work, *ARGS, timeout=1500)
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    return proc


def assert_as_uninterrupted(work: Path, ci_run) -> None:
    ref, proc = ci_run
    assert proc.returncode == 0
    for rel in COMPARED:
        same_dataset(open_dataset(ref / rel), open_dataset(work / rel))
    left = [p for p in (work / "results").rglob("*")
            if ".tmp-" in p.name or p.name.endswith(".checkpoint.npz")]
    assert left == []


def test_sigterm_to_the_workflow_then_restart_resumes(ci_run, tmp_path):
    """SIGTERM to every process (Snakemake and its jobs) while the drying run is in its loop:
    that run writes its checkpoint and exits 3; the restart resumes it (its command line
    passes --resume)."""
    work = workflow_copy(tmp_path)
    proc = start(work)
    log = work / "logs/drying_run/ci/seed1.log"
    wait_for(lambda: log.exists() and "elapsed" in log.read_text(), "the drying run's progress")
    os.killpg(proc.pid, signal.SIGTERM)
    proc.wait(timeout=300)
    wait_for(lambda: not session(proc.pid), "the jobs to end", timeout=300)
    assert "craquelure run: interrupted: SIGTERM" in log.read_text(), log.read_text()[-2000:]
    assert (work / "results/drying/ci/run/seed1.nc.checkpoint.npz").exists()
    assert not (work / TARGETS[0]).exists()
    restart(work)
    assert "resumed from" in log.read_text()
    assert_as_uninterrupted(work, ci_run)


def test_a_random_job_killed_then_restart(ci_run, tmp_path):
    """SIGKILL to one running simulation chosen at random: Snakemake records the failure (the
    output is not there or is removed); the restart redoes that job."""
    work = workflow_copy(tmp_path)
    proc = start(work)
    wait_for(lambda: running_runs(proc.pid) or proc.poll() is not None, "a simulation job")
    runs = running_runs(proc.pid)
    seed = random.randrange(2**32)
    victim = random.Random(seed).choice(sorted(runs))
    os.kill(victim, signal.SIGKILL)
    proc.wait(timeout=1500)
    assert proc.returncode != 0, f"job {runs[victim]} killed (seed {seed}), yet no failure"
    again = restart(work)
    assert f"output: {runs[victim]}" in again.stdout + again.stderr, (seed, runs[victim])
    assert_as_uninterrupted(work, ci_run)


def test_snakemake_killed_then_restart(ci_run, tmp_path):
    """SIGKILL to Snakemake alone while jobs run: the orphaned jobs go on (and may finish
    their outputs), but Snakemake never saw them finish: after ``--unlock`` the restart redoes
    every output that was in progress (Snakemake's incomplete markers)."""
    work = workflow_copy(tmp_path)
    proc = start(work)
    wait_for(lambda: running_runs(proc.pid) or proc.poll() is not None, "a simulation job")
    in_progress = set(running_runs(proc.pid).values())
    os.kill(proc.pid, signal.SIGKILL)
    proc.wait()
    wait_for(lambda: not session(proc.pid), "the orphaned jobs to end", timeout=600)
    assert any((work / ".snakemake" / "incomplete").iterdir())
    unlock = snakemake(work, "--unlock", "--configfile", "config/ci.yaml")
    assert unlock.returncode == 0, unlock.stderr[-2000:]
    again = restart(work)
    for out in in_progress:
        assert f"output: {out}" in again.stdout + again.stderr, out
    assert_as_uninterrupted(work, ci_run)


def test_slurm_jobs_get_a_grace_signal_and_resume(tmp_path):
    """Through the SLURM profile every job's sbatch gets ``--signal=TERM@<s>`` (slurm_extra)
    and is retried; every simulation job's command line passes --resume (dry run of the CI
    DAG, all jobs forced)."""
    work = workflow_copy(tmp_path)
    proc = snakemake(work, "-n", "-F", "--workflow-profile", "profiles/slurm", "--configfile",
                     "config/ci.yaml")
    text = proc.stdout + proc.stderr
    assert proc.returncode == 0, text[-3000:]
    resources = [line for line in text.splitlines() if line.strip().startswith("resources:")]
    assert resources and all("slurm_extra=--signal=TERM@120" in r for r in resources)
    runs = [line for line in text.splitlines() if "-m craquelure run " in line]
    assert len(runs) >= 20 and all(" --resume " in line for line in runs), runs[:3]
    settings = yaml.safe_load((work / "profiles" / "slurm" / "config.yaml").read_text())
    assert settings["retries"] >= 1
