"""Threads of a run: numba's workers and nothing else.

A library call that starts its own thread pool inside a step (an OpenBLAS ``dot`` or ``solve``,
an OpenMP section) would put a second set of busy threads on the cores of numba's ``prange``
workers. So every engine, on importing its generated kernels
(:func:`craquelure.codegen.import_generated`), calls :func:`single_threaded_libraries`, and
numba's OpenMP workers sleep while they wait (``OMP_WAIT_POLICY=PASSIVE``) rather than spin.
"""

import glob
import os
import threading
import time

# numba's OpenMP pool reads this at its first parallel call, after every engine's code
# generator imported this module; an explicit OMP_WAIT_POLICY in the environment wins.
os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")

_LIMITER = None


def single_threaded_libraries() -> None:
    """Limit the BLAS thread pools of the loaded numpy and scipy to 1 thread (idempotent).

    scipy's linear algebra is imported first so that its BLAS, which numba's ``np.linalg``
    calls through ``scipy.linalg.cython_lapack``, is loaded and therefore limited too."""
    global _LIMITER
    if _LIMITER is not None:
        return
    import scipy.linalg  # noqa: F401  (loads scipy's BLAS so that the limit reaches it)
    from threadpoolctl import threadpool_limits

    _LIMITER = threadpool_limits(limits=1, user_api="blas")


def set_threads(n: int | None) -> int:
    """Run with ``n`` numba threads (None: numba's default) and single-threaded libraries;
    returns the number of numba threads in use."""
    import numba

    single_threaded_libraries()
    if n is not None:
        numba.set_num_threads(int(n))
    return numba.get_num_threads()


def thread_cpu() -> dict[str, int]:
    """CPU nanoseconds used so far by each thread of this process, by thread id (Linux
    schedstat, exact for waiting workers; the calling thread's own is its thread CPU clock;
    empty elsewhere). For benchmarks: per-thread CPU time does not depend on the machine's load."""
    out = {}
    for path in glob.glob(f"/proc/{os.getpid()}/task/*/schedstat"):
        try:
            with open(path) as f:
                out[path.split("/")[-2]] = int(f.read().split()[0])
        except (OSError, ValueError, IndexError):
            pass
    if out:
        out[str(threading.get_native_id())] = time.thread_time_ns()
    return out
