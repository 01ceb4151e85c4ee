"""Cost of one impact run to t_end in 2D and 3D side by side (issue 16 item 6; spec section 8):
the source's 3D disc (10 112 particles) against the 2D plane-strain slice (1264), same concrete,
same kappa, same threads, one after the other in one process so that both see the same machine.

Prints per run: steps, wall and CPU seconds (process CPU time: all threads), listed-pair visits
(the two pair loops walk the neighbour list, skin included, every step) and pair evaluations
inside the support 2 h_ij (counted on the initial lattice, times 2 loops times steps: the
spec's measure), their rates per wall and CPU second, the neighbour-list rebuilds, and the 3D/2D
ratios. The compile time is excluded (one warm-up step on a separate engine of the same effect
set first).

    .venv/bin/python benchmarks/impact_3d_cost.py [--threads 2] [--kappa 1.0] [--t-end 1e-3]
    .venv/bin/python benchmarks/impact_3d_cost.py --threads 1 --profile-steps 200
"""

import argparse
import time

import numba
import numpy as np

from craquelure.impact.api import ImpactRun
from craquelure.scene import load_scene


def in_support_pairs(eng) -> int:
    """Ordered pairs of the neighbour list with r < 2 h_ij (both rows counted)."""
    st = eng.state
    i = np.repeat(np.arange(st.x.size), np.diff(eng.offsets))
    j = eng.index
    r2 = (st.x[i] - st.x[j]) ** 2 + (st.y[i] - st.y[j]) ** 2 + (st.z[i] - st.z[j]) ** 2
    return int(np.count_nonzero(r2 < (st.h[i] + st.h[j]) ** 2))


def one_run(scene_name: str, kappa: float, t_end: float, seed: int) -> dict:
    scene = load_scene(scene_name, [f"numerics.kappa={kappa}", f"outputs.t_end={t_end!r}",
                                    "outputs.snapshot_times=[]"])
    warm = ImpactRun(scene, seed)
    warm.engine.step()  # compile (cached afterwards) outside the timing
    run = ImpactRun(scene, seed)
    eng = run.engine
    support = in_support_pairs(eng)
    listed = 0
    rebuilds = 0
    built = eng.index
    wall0, cpu0 = time.perf_counter(), time.process_time()
    run.start()
    while not run.done():
        run.advance()
        listed += eng.index.size
        if eng.index is not built:
            rebuilds += 1
            built = eng.index
        bad = run.divergence()
        if bad is not None:
            raise RuntimeError(f"{scene_name}: {bad}")
        run.sample()
    wall, cpu = time.perf_counter() - wall0, time.process_time() - cpu0
    steps = eng.step_count
    return {"scene": scene_name, "particles": eng.state.x.size, "steps": steps, "wall": wall,
            "cpu": cpu, "listed_visits": 2 * listed, "support_evals": 2 * support * steps,
            "neighbours": support / eng.state.x.size, "rebuilds": rebuilds,
            "dt": t_end / steps}


def profile(scene_name: str, kappa: float, steps: int) -> dict:
    """CPU seconds per step in each piece of a step (material pass, force pass with artificial
    stress and contact, neighbour list, the rest: kicks, drift, diagnostics), over ``steps``
    steps after the first 0.2 ms (contact and damage under way)."""
    scene = load_scene(scene_name, [f"numerics.kappa={kappa}", "outputs.snapshot_times=[]"])
    run = ImpactRun(scene, 0)
    eng = run.engine
    while eng.t < 2e-4:
        eng.step()
    spent = {"material pass": 0.0, "force pass": 0.0, "neighbour list": 0.0}

    def timed(name, fn):
        def wrapper(*args, **kwargs):
            t0 = time.process_time()
            out = fn(*args, **kwargs)
            spent[name] += time.process_time() - t0
            return out
        return wrapper

    k = eng.k
    material, force = k.material_pass, k.force_pass
    eng._neighbours = timed("neighbour list", eng._neighbours)
    t0 = time.process_time()
    try:
        k.material_pass = timed("material pass", material)
        k.force_pass = timed("force pass", force)
        for _ in range(steps):
            eng.step()
    finally:
        k.material_pass, k.force_pass = material, force
    total = time.process_time() - t0
    spent["rest"] = total - sum(spent.values())
    return {name: value / steps for name, value in spent.items()}


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--kappa", type=float, default=1.0)
    parser.add_argument("--t-end", type=float, default=1e-3)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--profile-steps", type=int, default=0,
                        help="only profile this many 3D steps (after 0.2 ms) and stop")
    args = parser.parse_args()
    numba.set_num_threads(args.threads)
    if args.profile_steps:
        spent = profile("impact/disc3d", args.kappa, args.profile_steps)
        total = sum(spent.values())
        print(f"3D disc, kappa {args.kappa}, {args.threads} threads: CPU per step "
              f"{total * 1e3:.1f} ms: " + ", ".join(
                  f"{name} {v * 1e3:.1f} ms ({v / total:.0%})" for name, v in spent.items()))
        return
    out = {}
    for dim, name in ((2, "impact/default"), (3, "impact/disc3d")):
        r = one_run(name, args.kappa, args.t_end, args.seed)
        out[dim] = r
        print(f"{dim}D {name}: {r['particles']} particles, {r['neighbours']:.1f} neighbours "
              f"in the support, {r['steps']} steps (mean dt {r['dt'] * 1e9:.0f} ns), "
              f"{r['rebuilds']} list rebuilds; wall {r['wall']:.1f} s, CPU {r['cpu']:.1f} s "
              f"({args.threads} threads); pair evaluations {r['support_evals']:.3g} "
              f"({r['support_evals'] / r['wall']:.3g}/wall s, "
              f"{r['support_evals'] / r['cpu']:.3g}/CPU s), listed-pair visits "
              f"{r['listed_visits']:.3g}", flush=True)
    a, b = out[3], out[2]
    print(f"3D / 2D: wall x{a['wall'] / b['wall']:.1f}, CPU x{a['cpu'] / b['cpu']:.1f}, pair "
          f"evaluations x{a['support_evals'] / b['support_evals']:.1f}, CPU per pair evaluation "
          f"x{(a['cpu'] / a['support_evals']) / (b['cpu'] / b['support_evals']):.2f}")


if __name__ == "__main__":
    main()
