"""Bond updates per second of the lattice kernel for several effect sets (spec issue target:
2e7 bond updates/s on this 2-core machine). Compilation is excluded (warm-up call). Wall
and process-CPU rates are printed: on a shared machine the CPU rate is the load-independent
one (the wall rate of an idle machine is the CPU rate times the threads' efficiency).

    .venv/bin/python benchmarks/lattice_engine.py [--particles 20000] [--steps 200]
        [--threads 2]
"""

import argparse

import numba

from craquelure.lattice import bench

EFFECT_SETS = (("beams",), ("beams", "fracture"), ("beams", "fracture", "contact"))


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--particles", type=int, default=20000)
    parser.add_argument("--steps", type=int, default=200)
    parser.add_argument("--threads", type=int, default=2)
    args = parser.parse_args()
    numba.set_num_threads(args.threads)
    for effects in EFFECT_SETS:
        eng = bench.block_engine(args.particles, effects)
        t, cpu = bench.timings(eng, args.steps)
        nb = eng.system.bi.size
        print(f"{'+'.join(effects):<24} N = {eng.system.n}, {nb} bonds, "
              f"{'parallel' if eng.flags['PARALLEL'] else 'serial'} kernel, "
              f"{args.threads} thread(s): {t * 1e3:.3f} ms/step, "
              f"{nb / t:.3g} bond updates/s (wall), {nb / cpu:.3g} per CPU-second, "
              f"{t / eng.system.n * 1e9:.1f} ns/step/particle")


if __name__ == "__main__":
    main()
