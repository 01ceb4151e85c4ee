"""Threads of a run: after an engine loads its kernels no BLAS pool has more than one thread,
and numba's OpenMP workers are told to sleep while waiting; per-thread CPU accounting for the
benchmarks."""

import os
import subprocess
import sys
import threading
import time

import pytest
from threadpoolctl import threadpool_info

from craquelure.impact.engine import kernels_for
from craquelure.threads import set_threads, thread_cpu


def test_engine_kernels_hold_the_blas_pools_to_one_thread():
    # every engine's code generator goes through codegen
    kernels_for(("elasticity",), periodic=False, plane_stress=False, dim=2)
    blas = [p for p in threadpool_info() if p["user_api"] == "blas"]
    assert blas, "numpy's BLAS should be loaded"
    assert all(p["num_threads"] == 1 for p in blas)


def test_set_threads_sets_numba_and_keeps_blas_single():
    assert set_threads(1) == 1
    assert all(p["num_threads"] == 1 for p in threadpool_info() if p["user_api"] == "blas")


def test_importing_the_package_makes_openmp_workers_wait_passively():
    env = {k: v for k, v in os.environ.items() if k != "OMP_WAIT_POLICY"}
    out = subprocess.run([sys.executable, "-c", "import os, craquelure; "
                          "print(os.environ['OMP_WAIT_POLICY'])"], env=env,
                         capture_output=True, text=True, check=True).stdout.strip()
    assert out == "PASSIVE"


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="per-thread schedstat is Linux's")
def test_thread_cpu_counts_the_calling_threads_work():
    """thread_cpu attributes CPU time to the thread that did the work: a busy loop of the
    calling thread shows up in its own entry (at least half its process CPU time), not in an
    idle thread's."""
    idle = threading.Event()
    waiter = threading.Thread(target=idle.wait)
    waiter.start()
    try:
        before = thread_cpu()
        c0 = time.process_time()
        while time.process_time() - c0 < 0.05:
            pass
        after = thread_cpu()
    finally:
        idle.set()
        waiter.join()
    me = str(threading.get_native_id())
    own = (after[me] - before[me]) * 1e-9
    assert own >= 0.025
    others = [after[t] - before.get(t, 0) for t in after if t != me]
    assert max(others, default=0) * 1e-9 < 0.5 * own
