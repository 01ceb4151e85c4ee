"""Do two threads help? 1- and 2-thread throughput of every engine with default settings.

For each engine, at N >= 1.7e4 particles (softdyn: its largest built-in scene), the engine a user
gets (default settings; the library thread pools held to one thread by
:func:`craquelure.threads.single_threaded_libraries`, as in every run) is timed over
``--steps`` steps at 1 and at 2 numba threads, alternately, ``--rounds`` times; the median of
each is printed (particle-steps/s, the ratio 2T/1T and its range over the rounds, min 1T / max
2T to max 1T / min 2T) with the process CPU time per step, which is the load-independent figure
on a shared machine; CPU / wall time on 2 threads says how many cores the process really had (a
verdict below the target with fewer than 1.6 says so). "CPU bound" is the 1-thread CPU time per
step over the busiest thread's CPU time per step at 2 threads (Linux per-thread accounting): the
2T/1T the work allows if the two threads always had a core (it counts serial code, imbalance and
the threads' overhead, not waiting for a core or for a sleeping thread to wake), so it does not
depend on the machine's load.

- drying SPH: the default scene (all 7 effects, ABM4) at N = 17 600, L = sqrt(N)/20 (the default
  density, ~49 neighbours within h);
- impact SPH: the ``impact/rings`` scene (17 592 particles, h = 1.5 Delta);
- lattice: a free triangular block of 17 600 particles, shear beams (engine default: the
  parallel kernel from 20 000 bonds on when more than one thread is set), advanced as a run
  advances it: ``--steps`` steps in one kernel call (a run calls the kernel once per frame
  interval; one Python call per step would add ~0.1 ms of serial Python work to a 1.6 ms step);
- softdyn: the T1 of ``softdyn/t1_single`` (4 spheres, 5 pairs): right-hand sides per second.
  The model is serial by design (a handful of spheres; scipy's adaptive integrators call the
  right-hand side one at a time), so 2 threads cannot help; the row shows they do not hurt.

    python benchmarks/threads.py [--n 17600] [--steps 40] [--rounds 5] [--engines drying ...]

On an idle 2-core machine the full run takes about 3 min; ``--n 4000 --steps 10 --rounds 2``
is a smoke test (about 40 s after compilation).
"""

from __future__ import annotations

import argparse
import math
import os
import statistics
import time

import numba
import numpy as np

from craquelure.scene import load_scene
from craquelure.threads import set_threads, single_threaded_libraries, thread_cpu

TARGET = 1.8


def drying(n: int):
    from craquelure.drying.api import engine_from_initial
    from craquelure.drying.initial_state import build_initial_state

    scene = load_scene("drying/default", [f"particles.n={n}",
                                          f"domain.box_length={math.sqrt(n) / 20.0}"])
    engine = engine_from_initial(scene, build_initial_state(scene, 0))
    for _ in range(engine.stepper.restart_steps + 1):
        engine.step()  # past the RK4 start-up: the steps timed are ABM4's
    pairs = engine.index.size / n
    return {"engine": engine, "n": n, "neighbours": pairs, "advance": repeat(engine.step),
            "unit": "particle-steps/s"}


def impact(n: int):
    from craquelure.impact.api import initial_state, settings
    from craquelure.impact.engine import Engine
    from craquelure.impact.initial_state import build_specimen

    # the rings at the spacing that gives about n particles (17 592 at 5e-4 m)
    spacing = 5e-4 if abs(n - 17592) <= 100 else 5e-4 * math.sqrt(17592 / n)
    scene = load_scene("impact/rings", [f"particles.spacing={spacing}"])
    sp = build_specimen(scene, 0)
    engine = Engine(settings(scene), initial_state(scene, sp))
    return {"engine": engine, "n": sp.n, "neighbours": np.diff(engine.offsets).mean(),
            "advance": repeat(engine.step), "unit": "particle-steps/s"}


def lattice(n: int, parallel: bool | None = None):
    from craquelure.lattice.bench import block_engine

    # parallel=True: the parallel kernel at 2 threads whatever the bond count (to measure
    # where the engine's threshold PARALLEL_MIN_BONDS should sit); at 1 thread always serial
    engine = block_engine(n, parallel=parallel if numba.get_num_threads() > 1 else None)
    engine.run(2)
    return {"engine": engine, "n": engine.system.n,
            "neighbours": 2 * engine.system.bi.size / engine.system.n,
            "advance": engine.run, "unit": "particle-steps/s"}


def softdyn(_n: int):
    from craquelure.softdyn.initial_state import build

    setup = build(load_scene("softdyn/t1_single"))
    sysm = setup.system
    y = sysm.initial_state()
    return {"engine": sysm, "n": sysm.n, "neighbours": 2 * sysm.n_pairs / sysm.n,
            "advance": repeat(lambda: sysm.rhs(0.0, y)), "unit": "particle-RHS/s"}


ENGINES = {"drying": drying, "impact": impact, "lattice": lattice, "softdyn": softdyn}
LABEL = {"drying": "drying SPH", "impact": "impact SPH", "lattice": "lattice",
         "softdyn": "softdyn"}
CANNOT = {"softdyn": "serial model: 4 spheres, scipy's integrators call one RHS at a time"}


def repeat(step):
    """``advance(k)``: k calls of ``step`` (engines stepped from Python, as their runs do)."""
    def advance(k: int) -> None:
        for _ in range(k):
            step()
    return advance


def timed(advance, steps: int) -> tuple[float, float, float]:
    """Wall, process CPU and busiest thread's CPU time per step. The busiest thread's CPU
    time is what the wall time would be if the threads never waited for a core: cpu(1T) over
    it is the speed-up the work itself allows (serial parts, imbalance and the threads' own
    overhead included), whatever else runs on the machine."""
    s0 = thread_cpu()
    t0, c0 = time.perf_counter(), time.process_time()
    advance(steps)
    wall, cpu = (time.perf_counter() - t0) / steps, (time.process_time() - c0) / steps
    s1 = thread_cpu()
    busiest = max((s1[k] - s0.get(k, 0) for k in s1), default=math.nan) * 1e-9 / steps
    return wall, cpu, busiest


def measure(name: str, n: int, steps: int, rounds: int, **options) -> dict:
    """Median wall and CPU time per step at 1 and 2 threads, alternated round by round. Each
    thread count gets its own engine built with that count set (an engine may choose its
    kernels by the thread count, as the lattice does)."""
    built = {}
    for threads in (1, 2):
        set_threads(threads)
        built[threads] = ENGINES[name](n, **options)
        timed(built[threads]["advance"], 2)  # compile / load cached kernels, first-touch
    wall = {1: [], 2: []}
    cpu = {1: [], 2: []}
    busiest = []
    for _ in range(rounds):
        for threads in (1, 2):
            set_threads(threads)
            w, c, b = timed(built[threads]["advance"], steps)
            wall[threads].append(w)
            cpu[threads].append(c)
            if threads == 2:
                busiest.append(b)
    b = built[1]
    out = {"name": name, "n": b["n"], "neighbours": b["neighbours"], "unit": b["unit"]}
    for threads in (1, 2):
        w = statistics.median(wall[threads])
        out[f"rate{threads}"] = b["n"] / w
        out[f"cpu{threads}"] = statistics.median(cpu[threads])
        out[f"wall{threads}"] = w
    out["ratio"] = out["rate2"] / out["rate1"]
    out["spread"] = (min(wall[1]) / max(wall[2]), max(wall[1]) / min(wall[2]))
    # speed-up the work allows: 1-thread CPU per step over the busiest thread's at 2 threads
    out["cpu_bound"] = out["cpu1"] / statistics.median(busiest)
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=17600, help="particles (>= 1.7e4 for the table)")
    parser.add_argument("--steps", type=int, default=40, help="steps per timing")
    parser.add_argument("--rounds", type=int, default=5, help="alternated 1T/2T rounds")
    parser.add_argument("--engines", nargs="+", default=list(ENGINES), choices=list(ENGINES))
    parser.add_argument("--lattice-parallel", action="store_true",
                        help="lattice: the parallel kernel at 2 threads below the engine's "
                             "threshold too (e.g. --n 3600, the gravity_block scene's size)")
    args = parser.parse_args()
    single_threaded_libraries()
    from threadpoolctl import threadpool_info

    pools = ", ".join(f"{p['internal_api']} {p['num_threads']}" for p in threadpool_info()
                      if p["user_api"] == "blas")
    print(f"# {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}; numba "
          f"{numba.__version__} ({numba.config.THREADING_LAYER} layer), "
          f"{numba.config.NUMBA_NUM_THREADS} cores; BLAS pools held to: {pools}")
    print(f"# {args.rounds} rounds x {args.steps} steps per thread count, alternated; medians")
    print(f"{'engine':<11} {'N':>6} {'neigh':>6} {'1 thread':>10} {'2 threads':>10} "
          f"{'2T/1T':>6} {'range':>11} {'CPU bound':>9} {'CPU ms/step 1T':>15} {'2T':>7}  "
          f"{'unit / verdict'}")
    for name in args.engines:
        options = ({"parallel": True} if name == "lattice" and args.lattice_parallel
                   else {})
        r = measure(name, args.n, args.steps, args.rounds, **options)
        cores = r["cpu2"] / r["wall2"]  # CPU seconds per wall second on 2 threads
        if name in CANNOT:
            verdict = f"cannot scale: {CANNOT[name]}"
        elif r["ratio"] >= TARGET:
            verdict = "target met"
        elif cores < 1.6:
            verdict = (f"below the {TARGET}x target: the process got {cores:.2f} cores on 2 "
                       f"threads (load average {os.getloadavg()[0]:.1f}), rerun on an idle "
                       f"machine")
        else:
            verdict = f"below the {TARGET}x target with {cores:.2f} cores busy"
        print(f"{LABEL[name]:<11} {r['n']:>6} {r['neighbours']:>6.1f} {r['rate1']:>10.3g} "
              f"{r['rate2']:>10.3g} {r['ratio']:>6.2f} "
              f"{r['spread'][0]:>5.2f}-{r['spread'][1]:<5.2f} "
              f"{'-' if name in CANNOT else format(r['cpu_bound'], '.2f'):>9} "
              f"{r['cpu1'] * 1e3:>15.2f} "
              f"{r['cpu2'] * 1e3:>7.2f}  {r['unit']}; {verdict}", flush=True)


if __name__ == "__main__":
    main()
