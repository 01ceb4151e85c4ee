"""Threads of a run: after an engine loads its kernels no BLAS pool has more than one thread,
and numba's OpenMP workers are told to sleep while waiting."""

import os
import subprocess
import sys

from craquelure.impact.engine import kernels_for
from craquelure.threads import library_pools, set_threads


def test_engine_kernels_hold_the_blas_pools_to_one_thread():
    kernels_for(("elasticity",))  # every engine's code generator goes through codegen
    blas = [p for p in library_pools() if p["user_api"] == "blas"]
    assert blas, "numpy's BLAS should be loaded"
    assert all(p["num_threads"] == 1 for p in blas)


def test_set_threads_sets_numba_and_keeps_blas_single():
    assert set_threads(1) == 1
    assert all(p["num_threads"] == 1 for p in library_pools() if p["user_api"] == "blas")


def test_importing_the_package_makes_openmp_workers_wait_passively():
    env = {k: v for k, v in os.environ.items() if k != "OMP_WAIT_POLICY"}
    out = subprocess.run([sys.executable, "-c", "import os, craquelure; "
                          "print(os.environ['OMP_WAIT_POLICY'])"], env=env,
                         capture_output=True, text=True, check=True).stdout.strip()
    assert out == "PASSIVE"
