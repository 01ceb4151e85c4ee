"""Weak-scaling figure of the lattice kernel: time per step per particle versus N (wall and CPU
time per thread). A measurement without a verdict: spec check 12 is judged by
benchmarks/lattice_scaling.py (craquelure.lattice.claims.BENCHMARKED)."""

import sys

import numba

from craquelure.io import write_text_atomic
from craquelure.lattice import bench, figures

if "snakemake" in globals():
    smk = snakemake  # noqa: F821
    sys.stderr = sys.stdout = open(smk.log[0], "w")  # noqa: SIM115
    numba.set_num_threads(smk.threads)
    rows = bench.scaling(smk.params.particles, smk.params.steps)
    lines = ["particles\tbonds\ttime_per_step_s\ttime_per_step_per_particle_s\t"
             "cpu_time_per_thread_per_step_per_particle_s\tbond_updates_per_s\t"
             "bond_updates_per_cpu_s\tthreads\tparallel"]
    lines += [f"{r['particles']}\t{r['bonds']}\t{r['time_per_step']:.6g}\t"
              f"{r['time_per_step_per_particle']:.6g}\t"
              f"{r['cpu_per_thread_per_step_per_particle']:.6g}\t"
              f"{r['bond_updates_per_s']:.6g}\t{r['bond_updates_per_cpu_s']:.6g}\t"
              f"{r['threads']}\t{int(r['parallel'])}" for r in rows]
    write_text_atomic(smk.output.table, "\n".join(lines) + "\n")
    figures.scaling(rows, smk.output.figure,
                    f"{smk.params.title}, {smk.threads} thread(s), {smk.params.steps} steps")
    print("\n".join(lines))
