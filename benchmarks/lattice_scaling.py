"""Scaling of the lattice kernel (spec section 9 / check 12): time per step per particle from
1e3 to 1e5 particles (beams only); prints a table and the spread max/min (check 12: within
30 %, i.e. max/min <= 1.3).

    .venv/bin/python benchmarks/lattice_scaling.py [--particles 1000 10000 100000]
        [--steps 100] [--threads 2]
"""

import argparse

import numba

from craquelure.lattice import bench


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--particles", type=int, nargs="+", default=[1000, 10000, 100000])
    parser.add_argument("--steps", type=int, default=100)
    parser.add_argument("--threads", type=int, default=2)
    args = parser.parse_args()
    numba.set_num_threads(args.threads)
    rows = bench.scaling(args.particles, args.steps)
    print("particles  bonds    kernel    ms/step   ns/step/particle  bond updates/s")
    for r in rows:
        print(f"{r['particles']:9d} {r['bonds']:7d}  {'parallel' if r['parallel'] else 'serial':8}"
              f"  {r['time_per_step'] * 1e3:8.3f}  {r['time_per_step_per_particle'] * 1e9:16.1f}"
              f"  {r['bond_updates_per_s']:.3g}")
    per = [r["time_per_step_per_particle"] for r in rows]
    spread = max(per) / min(per)
    print(f"spread of time/step/particle: {spread:.2f} (check 12: <= 1.3 -> "
          f"{'pass' if spread <= 1.3 else 'FAIL'})")


if __name__ == "__main__":
    main()
