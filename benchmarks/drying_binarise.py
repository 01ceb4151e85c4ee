"""Binarisation and labelling cost per snapshot (drying spec sections 9 and 11).

Prints, for RSA-like random particles at the paper's density (h/Delta = 4) and mesh spacing
0.01 h, the wall time of the Shepard field on the mesh (``mesh_field``, row-strip neighbour
search) and of the periodic labelling, per snapshot, and the cost per run of 22 snapshots.

    python benchmarks/drying_binarise.py [--sizes 4 10] [--threads 2] [--spacing 0.01]
"""

from __future__ import annotations

import argparse
import time

import numba
import numpy as np

from craquelure.drying.binarise import label_periodic
from craquelure.drying.field import mesh_field

H = 0.2
SNAPSHOTS_PER_RUN = 22


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=float, nargs="+", default=[4.0, 10.0],
                        help="box sides L (N = 400 L^2)")
    parser.add_argument("--threads", type=int, default=numba.config.NUMBA_NUM_THREADS)
    parser.add_argument("--spacing", type=float, default=0.01, help="mesh spacing / h")
    args = parser.parse_args(argv)
    numba.set_num_threads(args.threads)
    rng = np.random.default_rng(0)
    mesh_field(rng.uniform(0, 1, 10), rng.uniform(0, 1, 10), np.ones(10), 1.0, H, 0.1)  # JIT
    print(f"threads {args.threads}, mesh spacing {args.spacing} h")
    print(f"{'L':>5} {'N':>7} {'mesh':>11} {'field [s]':>10} {'label [s]':>10} "
          f"{'pairs/s':>9} {'per run [s]':>11}")
    for length in args.sizes:
        n = int(400 * length**2)
        x, y = rng.uniform(0, length, n), rng.uniform(0, length, n)
        volume = np.full(n, length**2 / n)
        t0 = time.perf_counter()
        phi = mesh_field(x, y, volume, length, H, args.spacing * H)
        t1 = time.perf_counter()
        _, n_frag = label_periodic(phi >= 0.8)
        t2 = time.perf_counter()
        pairs = phi.size * (n / length**2) * np.pi * H * H
        print(f"{length:5g} {n:7d} {phi.shape[0]:>5d}^2 {t1 - t0:10.2f} {t2 - t1:10.2f} "
              f"{pairs / (t1 - t0):9.2e} {SNAPSHOTS_PER_RUN * (t2 - t0):11.1f}")


if __name__ == "__main__":
    main()
