"""Throughput of the drying-paste rate function and integrator step.

Prints, for N = 4e3, 4e4, 4e5 (drying density: L = sqrt(N)/20, h = 0.2, ~49 neighbours inside
h, the Verlet list holds those within 1.1 h), each effect set and 1 and 2 numba threads:
neighbour-pair visits per second (both pair passes of one rate evaluation, list pairs),
particle-steps per second and ms per ABM4 step (2 evaluations; timed after the RK4 start-up). Run:

    .venv/bin/python benchmarks/sph_engine.py [--sizes 4000 40000] [--repeats 5]
"""

from __future__ import annotations

import argparse
import time

import numba
import numpy as np
import yaml

from craquelure.drying.engine import DryingEngine
from craquelure.drying.positions import random_sequential_addition
from craquelure.scene import load_scene_text
from craquelure.sph.neighbours import Box, cell_order

EFFECT_SETS = {
    "drying (all 7)": ["elasticity", "viscosity", "drying", "substrate", "fracture", "xsph",
                       "continuity"],
    "no xsph": ["elasticity", "viscosity", "drying", "substrate", "fracture", "continuity"],
    "elastic only": ["elasticity", "continuity"],
}


def scene_for(n: int, effects: list[str]):
    length = float(np.sqrt(n) / 20.0)
    data = {
        "model": "drying", "domain": {"box_length": length},
        "particles": {"n": n},
        "material": {"rho0": 1.0, "lame_lambda": 1.0, "lame_mu": 0.1, "eta": 1.0,
                     "thickness": 0.316, "yield_stress": 5e-3, "drying_rate": 2.2e-5},
        "numerics": {"h": 0.2, "integrator": "abm4", "dt": 0.004},
        "outputs": {"t_end": 1.0}, "effects": effects,
    }
    return load_scene_text(yaml.safe_dump(data), name=f"bench{n}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[4000, 40000, 400000])
    parser.add_argument("--repeats", type=int, default=10)
    args = parser.parse_args()
    print(f"# numba {numba.__version__}, max threads {numba.config.NUMBA_NUM_THREADS}")
    print(f"{'N':>8} {'effects':<16} {'thr':>3} {'pairs/eval':>11} {'pair visits/s':>14} "
          f"{'ms/eval':>9} {'ms/step':>9} {'particle-steps/s':>17}")
    for n in args.sizes:
        length = np.sqrt(n) / 20.0
        x, y = random_sequential_addition(n, length, 0.8 * length / np.sqrt(n),
                                          np.random.default_rng(0))
        order = cell_order(x, y, 0.2, Box.square(length))  # as `craquelure init` stores them
        x, y = x[order], y[order]
        mass = np.full(n, length**2 / n)
        for label, effects in EFFECT_SETS.items():
            scene = scene_for(n, effects)
            engine = DryingEngine(scene, x, y, mass, np.ones(n), np.zeros((3, n)))
            rng = np.random.default_rng(1)
            engine.state[2:4] = rng.uniform(-1e-6, 1e-6, (2, n))
            pairs = int(engine.index.size)
            for threads in (1, 2):
                numba.set_num_threads(threads)
                engine.evaluate(engine.state, 0.0)  # warm-up (compile / load cache)
                t0 = time.perf_counter()
                for _ in range(args.repeats):
                    engine.evaluate(engine.state, 0.0)
                per_eval = (time.perf_counter() - t0) / args.repeats
                for _ in range(engine.stepper.restart_steps + 1):
                    engine.step()  # past the RK4 start-up, so steps are ABM4 (2 evaluations)
                t0 = time.perf_counter()
                for _ in range(max(2, args.repeats // 2)):
                    engine.step()
                per_step = (time.perf_counter() - t0) / max(2, args.repeats // 2)
                print(f"{n:>8} {label:<16} {threads:>3} {pairs:>11} "
                      f"{2 * pairs / per_eval:>14.3e} {1e3 * per_eval:>9.2f} "
                      f"{1e3 * per_step:>9.2f} {n / per_step:>17.3e}", flush=True)


if __name__ == "__main__":
    main()
