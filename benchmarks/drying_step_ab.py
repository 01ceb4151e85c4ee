"""One Table I ABM4 step (config/scenes/drying/table1.yaml: L = 10, N = 4e4) of this checkout
against another checkout of the project, side by side: one worker process per checkout (each
with its own ``src`` first on the path and its own numba cache), both alive for the whole
run, timed alternately A, B, A, B, ... so that both see the same machine load.

Each worker builds seed 1's initial state, steps past the RK4 start-up (the steps timed are
ABM4: two rate evaluations each, neighbour rebuilds when due) and then, per request, times
``--steps`` steps in CPU time (one numba thread unless ``--threads``). The report gives each
round's ms per step and the ratio B/A per round and over all rounds (median). The steps timed
are the run's first (no removal yet): the regime of most of a Table I run's steps.

    python benchmarks/drying_step_ab.py --against /path/to/other/checkout [--rounds 5]
        [--steps 20] [--threads 1] [--write benchmarks/tables/drying_step.md]
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parents[1]


def worker(threads: int) -> None:
    """Serve ``steps K`` requests on stdin with one JSON line each: CPU s per step."""
    import numba

    from craquelure.drying.api import engine_from_initial
    from craquelure.drying.initial_state import build_initial_state
    from craquelure.scene import load_scene

    numba.set_num_threads(threads)
    scene = load_scene("drying/table1")
    engine = engine_from_initial(scene, build_initial_state(scene, seed=1))
    for _ in range(engine.stepper.restart_steps + 2):
        engine.step()
    print(json.dumps({"ready": True, "n": engine.n}), flush=True)
    for line in sys.stdin:
        steps = int(line.split()[1])
        start = time.process_time()
        for _ in range(steps):
            engine.step()
        cpu = (time.process_time() - start) / steps
        print(json.dumps({"cpu_per_step": cpu, "t": engine.t, "evaluations": engine.evaluations,
                          "neighbour_builds": engine.neighbour_builds}), flush=True)


def start_worker(tree: Path, threads: int) -> subprocess.Popen:
    env = dict(os.environ, PYTHONPATH=str(tree / "src"),
               CRAQUELURE_CACHE=str(tree / ".numba-cache"), NUMBA_NUM_THREADS=str(threads))
    proc = subprocess.Popen([sys.executable, __file__, "--worker", "--threads", str(threads)],
                            cwd=tree, env=env, stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                            text=True)
    ready = json.loads(proc.stdout.readline())
    if not ready.get("ready"):
        raise RuntimeError(f"worker in {tree} did not start")
    return proc


def ask(proc: subprocess.Popen, steps: int) -> dict:
    proc.stdin.write(f"steps {steps}\n")
    proc.stdin.flush()
    return json.loads(proc.stdout.readline())


def git_commit(tree: Path) -> str:
    return subprocess.run(["git", "-C", str(tree), "rev-parse", "--short", "HEAD"],
                          capture_output=True, text=True).stdout.strip()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--against", type=Path, help="the other checkout (B)")
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--steps", type=int, default=20)
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument("--write", type=Path, help="write the summary table (Markdown)")
    parser.add_argument("--worker", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.worker:
        worker(args.threads)
        return
    if args.against is None:
        parser.error("--against is required")
    trees = {"A": HERE, "B": args.against.resolve()}
    names = {k: f"{git_commit(t)} ({t})" for k, t in trees.items()}
    procs = {k: start_worker(t, args.threads) for k, t in trees.items()}
    per_step = {"A": [], "B": []}
    print(f"# Table I ABM4 step, {args.threads} thread(s), {args.steps} steps per timing, CPU "
          f"time; A = {names['A']}, B = {names['B']}; a shared machine: ratios compare")
    for r in range(args.rounds):
        for k in ("A", "B"):
            per_step[k].append(ask(procs[k], args.steps)["cpu_per_step"])
        a, b = per_step["A"][-1], per_step["B"][-1]
        print(f"round {r + 1}: A {1e3 * a:.1f} ms/step, B {1e3 * b:.1f} ms/step, B/A {b / a:.2f}")
    for proc in procs.values():
        proc.stdin.close()
        proc.wait()
    ratios = [b / a for a, b in zip(per_step["A"], per_step["B"], strict=True)]
    med = {k: statistics.median(v) for k, v in per_step.items()}
    print(f"median: A {1e3 * med['A']:.1f} ms/step, B {1e3 * med['B']:.1f} ms/step; B/A per "
          f"round {min(ratios):.2f}-{max(ratios):.2f}, median {statistics.median(ratios):.2f}")
    if args.write:
        lines = ["| checkout | ms per ABM4 step (CPU, median) | per round |", "|---|---|---|"]
        for k in ("A", "B"):
            rounds = ", ".join(f"{1e3 * v:.1f}" for v in per_step[k])
            lines.append(f"| {k}: `{git_commit(trees[k])}` | {1e3 * med[k]:.1f} | {rounds} |")
        lines.append("")
        lines.append(f"Table I scene (L = 10, N = 4e4), seed 1, {args.threads} numba thread(s), "
                     f"{args.rounds} alternating rounds of {args.steps} steps; B/A per round "
                     f"{min(ratios):.2f}-{max(ratios):.2f}, median "
                     f"**{statistics.median(ratios):.2f}x**. Written by "
                     f"`benchmarks/drying_step_ab.py`.")
        args.write.parent.mkdir(parents=True, exist_ok=True)
        args.write.write_text("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
