"""Throughput measurements of the lattice kernel (benchmarks and the scaling figure): a free
block of about N particles, the best wall and CPU times of ``steps`` steps after a warm-up. The
spec's scaling figure (section 9) is a weak-scaling plot of an MPI code; this shared-memory port
reports its serial form: time per step per particle versus N (constant = ideal) and bond
updates per second.
"""

import math
import time

import numba
import numpy as np

from craquelure.lattice import beam
from craquelure.lattice.engine import Engine, lattice_system, stable_step_estimate
from craquelure.lattice.geometry import triangular_block
from craquelure.lattice.initial_state import probe_engine


def block_engine(n_particles: int, effects=("beams",), seed: int = 0,
                 parallel: bool | None = None) -> Engine:
    """The block with the engine's kernel choice (``parallel=None``: parallel from
    ``PARALLEL_MIN_BONDS`` bonds on when more than one thread is set) or a forced one."""
    nx = max(2, int(round(math.sqrt(n_particles * 2 / math.sqrt(3)))))
    ny = max(2, int(round(n_particles / nx)))
    x, y, _ = triangular_block(nx, ny)
    c = beam.shear_beam(1.0, 0.2)
    s = lattice_system(x, y, kn=c.kn, ka=c.a, kb=c.b)
    params = dict(dt=0.2 * stable_step_estimate(s), area=c.area, inertia=c.inertia,
                  width=c.width, sigma0=1.0, tau0=1.0, contact_stiffness=1.0)
    eng = probe_engine(s, tuple(effects), params, series_every=100, seed=seed, parallel=parallel)
    rng = np.random.default_rng(seed)
    eng.set_velocity(*(1e-4 * rng.normal(size=(3, s.n))))
    return eng


def timings(engine: Engine, steps: int, repeats: int = 3) -> tuple[float, float]:
    """(best wall time, best process CPU time) per step. On a machine shared with other jobs
    the CPU time (summed over this process's threads) is the load-independent figure."""
    engine.run(2)  # compile / load the cached kernel
    best, best_cpu = math.inf, math.inf
    for _ in range(repeats):
        t0, c0 = time.perf_counter(), time.process_time()
        engine.run(steps)
        best = min(best, time.perf_counter() - t0)
        best_cpu = min(best_cpu, time.process_time() - c0)
    return best / steps, best_cpu / steps


def scaling(particles, steps: int, effects=("beams",)) -> list[dict]:
    """One row per size: wall and CPU time per step, per particle, and the CPU time per thread
    per step per particle (process CPU time / threads the kernel ran on: numba's thread count
    for the parallel kernel, 1 for the serial one), the figure that does not count the time
    spent waiting for a core on a loaded machine."""
    rows = []
    for n in particles:
        eng = block_engine(int(n), effects)
        t, cpu = timings(eng, steps)
        nb = int(eng.system.bi.size)
        parallel = bool(eng.flags["PARALLEL"])
        threads = numba.get_num_threads() if parallel else 1
        rows.append({"particles": eng.system.n, "bonds": nb, "time_per_step": t,
                     "time_per_step_per_particle": t / eng.system.n,
                     "bond_updates_per_s": nb / t, "cpu_per_step": cpu,
                     "cpu_per_thread_per_step_per_particle": cpu / threads / eng.system.n,
                     "bond_updates_per_cpu_s": nb / cpu, "threads": threads, "parallel": parallel})
    return rows
