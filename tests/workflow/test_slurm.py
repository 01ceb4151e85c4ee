"""The SLURM profile for real: the CI config through ``--workflow-profile profiles/slurm`` on
the one-node cluster of ``.ci/slurm-cluster`` (``make test-slurm`` starts it and runs this).

Jobs must go through sbatch, finish, and every dataset they write must hold the same numbers
as a local run of the same config (the runs are deterministic for a seed and a thread count;
only wall times differ). Skipped when no SLURM node is up. Runs the CI workflow twice (local,
then SLURM), about half an hour on 2 cores, hence not part of ``make test``.
"""

from __future__ import annotations

import re
import shutil
import subprocess
from pathlib import Path

import pytest
import xarray as xr

from tests.workflow.test_conventions import LOCAL_RULES
from tests.workflow.test_snakemake import job_stats, snakemake, workflow_copy

pytestmark = pytest.mark.slurm

# Options for the test cluster only: no accounting database, so job states come from squeue.
TEST_CLUSTER = ("--slurm-status-command", "squeue")


def cluster_up() -> bool:
    if shutil.which("sinfo") is None:
        return False
    try:  # with no controller running, sinfo retries for a while: do not wait for it
        proc = subprocess.run(["sinfo", "-h", "-N", "-o", "%T"], capture_output=True, text=True,
                              timeout=15)
    except subprocess.TimeoutExpired:
        return False
    return proc.returncode == 0 and any(
        state.strip() in ("idle", "mixed", "allocated") for state in proc.stdout.splitlines())


@pytest.fixture(scope="module", autouse=True)
def _cluster():
    # A fixture, not an import-time check: `make test` deselects these tests and must not wait
    # for sinfo to give up on a controller that is not running.
    if not cluster_up():
        pytest.skip("no SLURM node up (start one with .ci/slurm-cluster start)")


@pytest.fixture(scope="module")
def local_run(tmp_path_factory) -> Path:
    work = workflow_copy(tmp_path_factory.mktemp("local"))
    proc = snakemake(work, "--cores", "2", "--configfile", "config/ci.yaml", timeout=3600)
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    return work


@pytest.fixture(scope="module")
def slurm_run(tmp_path_factory) -> tuple[Path, subprocess.CompletedProcess]:
    work = workflow_copy(tmp_path_factory.mktemp("slurm"))
    proc = snakemake(work, "--workflow-profile", "profiles/slurm", "--configfile",
                     "config/ci.yaml", *TEST_CLUSTER, timeout=5400)
    (work / "snakemake-slurm.log").write_text(proc.stdout + proc.stderr)
    return work, proc


def test_jobs_go_through_sbatch_and_finish(slurm_run):
    work, proc = slurm_run
    text = proc.stdout + proc.stderr
    assert proc.returncode == 0, text[-5000:]
    assert "Using workflow specific profile profiles/slurm" in text
    submitted = re.findall(r"has been submitted with SLURM jobid (\d+)", text)
    stats = job_stats(text)
    remote = sum(n for rule, n in stats.items() if rule not in LOCAL_RULES | {"total"})
    assert remote > 20 and len(set(submitted)) == remote, (remote, submitted)
    # Aggregation, figure and report jobs ran in the Snakemake process, not in the queue.
    ran_locally = set(re.findall(r"^localrule (\w+):", text, flags=re.M))
    assert ran_locally == {rule for rule in stats if rule in LOCAL_RULES}
    again = snakemake(work, "-n", "--configfile", "config/ci.yaml")
    assert "Nothing to be done" in again.stdout + again.stderr


def comparable(ds: xr.Dataset) -> xr.Dataset:
    """Data and coordinates without what depends on the machine's load (wall times)."""
    return ds.drop_vars([n for n in ds.variables if "wall_time" in str(n)]).drop_attrs()


def test_outputs_equal_a_local_run(local_run, slurm_run):
    work, proc = slurm_run
    assert proc.returncode == 0
    local = sorted(p.relative_to(local_run) for p in (local_run / "results").rglob("*")
                   if p.is_file())
    remote = sorted(p.relative_to(work) for p in (work / "results").rglob("*") if p.is_file())
    assert local == remote
    datasets = [p for p in local if p.suffix == ".nc"]
    assert len(datasets) > 30
    for rel in datasets:
        with xr.open_dataset(local_run / rel) as a, xr.open_dataset(work / rel) as b:
            xr.testing.assert_equal(comparable(a), comparable(b))
            assert a.attrs["scene"] == b.attrs["scene"], rel
