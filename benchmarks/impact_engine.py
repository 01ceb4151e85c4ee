"""Speed of the impact engine: steps per second and pair visits per second for the spec's
1264-particle disc (default scene) at each kappa, one numba thread.

    .venv/bin/python benchmarks/impact_engine.py [--steps 400]
"""

import argparse
import time

import numba
import numpy as np

from craquelure.impact.api import initial_state, settings
from craquelure.impact.engine import Engine
from craquelure.impact.initial_state import build_specimen
from craquelure.scene import load_scene


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--steps", type=int, default=400)
    parser.add_argument("--threads", type=int, default=1)
    args = parser.parse_args()
    numba.set_num_threads(args.threads)
    for kappa in (0.7, 1.0, 1.5):
        scene = load_scene("impact/default", [f"numerics.kappa={kappa}"])
        sp = build_specimen(scene, 0)
        eng = Engine(settings(scene), initial_state(scene, sp))
        for _ in range(5):  # compile / warm up
            eng.step()
        t0 = time.perf_counter()
        for _ in range(args.steps):
            eng.step()
        wall = time.perf_counter() - t0
        pairs = int(np.diff(eng.offsets).sum())
        print(f"kappa {kappa}: {args.steps / wall:7.1f} steps/s, dt {eng.dt * 1e9:.0f} ns, "
              f"{pairs / sp.n:.1f} listed neighbours, "
              f"{2 * pairs * args.steps / wall:.3g} pair visits/s, "
              f"1 ms of impact ~ {1e-3 / eng.dt / (args.steps / wall):.0f} s")


if __name__ == "__main__":
    main()
