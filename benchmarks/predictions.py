"""Do `craquelure check`'s wall-time predictions hold? Predicted against measured, every scene.

Two modes:

``--calibrate`` measures the throughput model of each engine (:mod:`craquelure.throughput`)
and writes ``src/craquelure/throughput.yaml``:

- per step and per particle-neighbour: engine steps timed in this process at two sizes (drying:
  N = 1600 and 6400 at the default density, ABM4 steps / 2 evaluations; impact: the default
  disc, 40 and 100 cells, all effects; lattice: a shear-beam block of 1600 and 6400 particles;
  the two sizes give the fixed and the N-proportional cost), and again at 2 threads on the
  larger size (the speed-up S(2));
- softdyn: one T1 (``softdyn/t1_single_ci``) in-process, seconds per unit of its workload;
- per run: ``craquelure run`` of each model's CI scene cut to a few steps, in a subprocess
  (process start, imports, cached kernels, initial state, writing).

Without it, every built-in scene (or ``--scenes``) is run with ``craquelure run`` in a
subprocess at ``--threads`` numba threads, after an untimed warm-up (compiles the kernels), with
``outputs.t_end`` scaled by ``--fraction`` for the time-stepped models (the prediction is made
for the scene as run, with the same override), and the measured wall time is printed beside the
prediction of `craquelure check`; ``ok`` when within +-30 %.

    python benchmarks/predictions.py --calibrate          # ~3 min on an idle 2-core machine
    python benchmarks/predictions.py --fraction 0.1       # every scene at 1/10 of t_end
    python benchmarks/predictions.py --scenes impact/default drying/ci
"""

from __future__ import annotations

import argparse
import math
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import yaml

from craquelure.models import model_api
from craquelure.scene import load_scene
from craquelure.threads import set_threads
from craquelure.throughput import ENGINES, TABLE, predicted_wall_time

ROOT = Path(__file__).resolve().parents[1]
TOLERANCE = 0.30
STEPPED = ("drying", "impact", "lattice")


def timed_steps(step, steps: int, repeats: int = 3) -> float:
    """Median wall time per call after one untimed call."""
    step()
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        for _ in range(steps):
            step()
        times.append((time.perf_counter() - t0) / steps)
    return float(np.median(times))


def drying_probe(n: int):
    from craquelure.drying.initial_state import build_initial_state
    from craquelure.drying.run import engine_from_initial

    scene = load_scene("drying/default", [f"particles.n={n}",
                                          f"domain.box_length={math.sqrt(n) / 20.0}"])
    eng = engine_from_initial(scene, build_initial_state(scene, 0))
    for _ in range(eng.stepper.restart_steps + 1):
        eng.step()
    # per rate evaluation: an ABM4 step makes 2
    return n, eng.index.size / n, lambda: eng.step(), 2.0


def impact_probe(cells: int):
    from craquelure.impact.api import initial_state, settings
    from craquelure.impact.engine import Engine
    from craquelure.impact.specimen import build_specimen

    scene = load_scene("impact/default", [f"particles.diameter_cells={cells}"])
    sp = build_specimen(scene, 0)
    eng = Engine(settings(scene), initial_state(scene, sp))
    return sp.n, float(np.diff(eng.offsets).mean()), lambda: eng.step(), 1.0


def lattice_probe(n: int):
    from craquelure.lattice.bench import block_engine

    eng = block_engine(n)
    return eng.system.n, 2 * eng.system.bi.size / eng.system.n, lambda: eng.run(1), 1.0


PROBES = {"drying": (drying_probe, (1600, 6400)), "impact": (impact_probe, (40, 100)),
          "lattice": (lattice_probe, (1600, 6400))}
# N-proportional cost charged per neighbour (SPH pair loops) or per particle (lattice)
PER_PAIR = {"drying": True, "impact": True, "lattice": False}


def fit_engine(name: str, steps: int) -> dict:
    probe, sizes = PROBES[name]
    points = []
    for size in sizes:
        set_threads(1)
        n, k, step, per = probe(size)
        points.append((n, k, timed_steps(step, steps) / per))
    set_threads(2)
    n2, _, step2, per2 = probe(sizes[-1])
    t2 = timed_steps(step2, steps) / per2
    set_threads(1)
    (n_a, k_a, t_a), (n_b, k_b, t_b) = points
    x_a, x_b = (n_a * k_a, n_b * k_b) if PER_PAIR[name] else (n_a, n_b)
    slope = (t_b - t_a) / (x_b - x_a)
    fixed = max(0.0, t_a - slope * x_a)
    unit = "rate evaluations" if name == "drying" else "steps"
    return {"unit": unit, "per_unit_s": float(fixed),
            "per_particle_s": 0.0 if PER_PAIR[name] else float(slope),
            "per_pair_s": float(slope) if PER_PAIR[name] else 0.0,
            "speedup_2": float(max(1.0, t_b / t2))}


def fit_softdyn() -> dict:
    from craquelure.softdyn.api import workload
    from craquelure.softdyn.scenarios import build

    scene = load_scene("softdyn/t1_single_ci")
    set_threads(1)
    build(scene).run(desc="warm-up")
    t0 = time.perf_counter()
    build(scene).run(desc="calibration")
    seconds = time.perf_counter() - t0
    return {"unit": "T1 integrations x log(1 + T) (1 + log10(1/F~))",
            "per_unit_s": seconds / workload(scene)["units"], "per_particle_s": 0.0,
            "per_pair_s": 0.0, "speedup_2": 1.0}


CI_SCENES = {"drying": ("drying/ci", ["outputs.t_end=0.02", "outputs.times=[0.02]"]),
             "impact": ("impact/ci", ["outputs.t_end=2.0e-6", "outputs.snapshot_times=[]"]),
             "lattice": ("lattice/gravity_block", ["outputs.t_end=0.5"]),
             "softdyn": ("softdyn/t1_single_ci", ["outputs.t_end=0.01"])}


def run_once(scene: str, overrides: list[str], threads: int) -> float:
    env = {**os.environ, "NUMBA_NUM_THREADS": str(threads)}
    with tempfile.TemporaryDirectory() as tmp:
        cmd = [sys.executable, "-m", "craquelure", "run", scene, "--out", f"{tmp}/run.nc"]
        for item in overrides:
            cmd += ["--set", item]
        t0 = time.perf_counter()
        proc = subprocess.run(cmd, env=env, capture_output=True, text=True)
        wall = time.perf_counter() - t0
    if proc.returncode != 0:
        raise RuntimeError(f"{scene} {overrides}: {proc.stderr.strip().splitlines()[-1:]}")
    return wall


def calibrate(steps: int) -> None:
    engines = {name: fit_engine(name, steps) for name in PROBES}
    engines["softdyn"] = fit_softdyn()
    for name in ENGINES:
        scene, overrides = CI_SCENES[name]
        run_once(scene, overrides, 1)  # compile
        engines[name]["overhead_s"] = float(min(run_once(scene, overrides, 1) for _ in range(2)))
    load = os.getloadavg()[0]
    data = {"measured": time.strftime("%Y-%m-%d", time.gmtime()),
            "machine": f"{os.cpu_count()} cores, load average {load:.1f} at calibration",
            "engines": {k: {kk: (round(vv, 12) if isinstance(vv, float) else vv)
                            for kk, vv in v.items()} for k, v in engines.items()}}
    text = ("# Throughput model of each engine (craquelure.throughput), written by\n"
            "# `python benchmarks/predictions.py --calibrate`. Seconds; see throughput.py.\n"
            + yaml.safe_dump(data, sort_keys=False, width=100))
    tmp = TABLE.with_suffix(".tmp")
    tmp.write_text(text)
    tmp.replace(TABLE)
    print(text)


def built_in_scenes() -> list[str]:
    base = ROOT / "config" / "scenes"
    return sorted(f"{p.parent.name}/{p.stem}" for p in base.glob("*/*.yaml"))


def scaled_overrides(ref: str, fraction: float) -> list[str]:
    scene = load_scene(ref)
    if scene.model not in STEPPED or fraction == 1.0:
        return []
    t_end = scene.get("outputs.t_end") * fraction
    out = [f"outputs.t_end={t_end!r}"]
    if scene.model == "drying":
        out.append(f"outputs.times=[{t_end!r}]")
    if scene.model == "impact":
        out.append("outputs.snapshot_times=[]")
    return out


def measure(scenes: list[str], fraction: float, threads: int) -> None:
    print(f"# {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}; {threads} thread(s); "
          f"t_end x {fraction:g} (time-stepped models); load average "
          f"{os.getloadavg()[0]:.1f}; model {TABLE.name}")
    print(f"{'scene':<30} {'predicted [s]':>13} {'measured [s]':>12} {'ratio':>6}  verdict")
    hits = 0
    for ref in scenes:
        overrides = scaled_overrides(ref, fraction)
        scene = load_scene(ref, overrides)
        predicted = predicted_wall_time(scene.model, model_api(scene.model).workload(scene),
                                        threads)
        warm = scaled_overrides(ref, 1e-3) if scene.model in STEPPED else ["outputs.t_end=0.01"]
        try:
            run_once(ref, warm, threads)
        except RuntimeError:
            pass  # a warm-up only compiles; some studies refuse a cut run
        measured = run_once(ref, overrides, threads)
        ratio = predicted / measured
        ok = abs(ratio - 1.0) <= TOLERANCE
        hits += ok
        print(f"{ref:<30} {predicted:>13.1f} {measured:>12.1f} {ratio:>6.2f}  "
              f"{'ok' if ok else 'MISS'}", flush=True)
    print(f"# {hits} of {len(scenes)} within +-{TOLERANCE:.0%}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--calibrate", action="store_true")
    parser.add_argument("--steps", type=int, default=20, help="steps per calibration timing")
    parser.add_argument("--scenes", nargs="+", default=None)
    parser.add_argument("--fraction", type=float, default=1.0)
    parser.add_argument("--threads", type=int, default=1)
    args = parser.parse_args()
    if args.calibrate:
        calibrate(args.steps)
    else:
        measure(args.scenes or built_in_scenes(), args.fraction, args.threads)


if __name__ == "__main__":
    main()
