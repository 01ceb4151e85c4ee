"""Do `craquelure check`'s wall-time predictions hold? Predicted against measured, every scene.

Two modes:

``--calibrate`` measures the throughput model of each engine (:mod:`craquelure.throughput`)
and writes ``src/craquelure/throughput.yaml``:

- per step and per particle-neighbour: engine steps timed in this process at two sizes (drying:
  N = 1600 and 6400 at the default density, ABM4 steps / 2 evaluations; impact: the default
  disc, 40 and 100 cells, all effects; lattice: a shear-beam block of 1600 and 6400 particles,
  10 steps per kernel call as in a run; the two sizes give the fixed and the N-proportional
  cost), and at 1 and 2 threads on the larger size (the speed-up S(2); the lattice on a block of
  17 600, where its parallel kernel runs; then each other lattice effect added to the 6400
  block alone: its extra cost per particle-step). Single-thread timings are CPU time (equal to
  the wall time on an idle machine; not inflated by waiting on a busy one), S(2) is wall time;
- softdyn: one T1 (``softdyn/t1_single_ci``) in-process, seconds per unit of its workload;
- per run: ``craquelure run`` of each model's CI scene cut to a few steps, in a subprocess
  (process start, imports, cached kernels, initial state, writing).

Without it, every built-in scene (or ``--scenes``) is run with ``craquelure run`` in a
subprocess at ``--threads`` numba threads, after an untimed warm-up (compiles the kernels), and
the measured wall time is printed beside the prediction of `craquelure check` for the scene as
run (same overrides); ``ok`` when within +-30 %. The time-stepped models (drying, impact,
lattice) run with ``outputs.t_end`` cut so that the predicted compute part (steps x per-step
cost, the term the model is about) is at most ``--compute-seconds`` (default 20 s; drying/table1
runs ~1/500 of its t_end); the "compute" column is that part's predicted share of the wall time.
Scenes whose whole run is a second of compute behind ~1.5 s of process start stay as they are,
and for every row the time loop is compared on its own as well: predicted compute part against
the loop's wall time, which the run prints ("done: ... wall time X s"; it includes loading the
cached kernels, ~0.1-0.3 s, which the model books under the fixed cost). ``--max-stretch K``
runs such scenes up to K times past their t_end to give the per-step terms more weight, at the
price of leaving the regime a scene is built for (``lattice/creep_slab`` diverges after
t = 14 600, 4.9 x its t_end). softdyn studies are not time-stepped and run as they are (all take
seconds). ``--fraction f`` instead scales every time-stepped scene's t_end by f (f = 1: the
scenes as they are). The run's CPU time and predicted / CPU are printed too: at one thread on an
idle machine they equal the wall figures; on a busy one the CPU time is the less load-sensitive
check (not load-free: at load average 20 on 2 cores a process start took ~1.5x its idle CPU
time).

    python benchmarks/predictions.py --calibrate          # ~5 min on an idle 2-core machine
    python benchmarks/predictions.py                      # every scene, ~10 min idle
    python benchmarks/predictions.py --fraction 1 --scenes lattice/glen impact/default
"""

from __future__ import annotations

import argparse
import math
import os
import re
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import yaml

from craquelure.errors import SceneError
from craquelure.models import model_api
from craquelure.scene import load_scene
from craquelure.softdyn.engine import run
from craquelure.threads import set_threads
from craquelure.throughput import ENGINES, TABLE, predicted_parts

ROOT = Path(__file__).resolve().parents[1]
TOLERANCE = 0.30
STEPPED = ("drying", "impact", "lattice")


def timed_steps(step, steps: int, repeats: int = 3, clock=time.perf_counter) -> float:
    """Median time per call after one untimed call (wall time; ``time.process_time`` for a
    single thread: on an idle machine the same, on a busy one not inflated by waiting)."""
    step()
    times = []
    for _ in range(repeats):
        t0 = clock()
        for _ in range(steps):
            step()
        times.append((clock() - t0) / steps)
    return float(np.median(times))


def drying_probe(n: int):
    from craquelure.drying.api import engine_from_initial
    from craquelure.drying.initial_state import build_initial_state

    scene = load_scene("drying/default", [f"particles.n={n}",
                                          f"domain.box_length={math.sqrt(n) / 20.0}"])
    eng = engine_from_initial(scene, build_initial_state(scene, 0))
    for _ in range(eng.stepper.restart_steps + 1):
        eng.step()
    # per rate evaluation: an ABM4 step makes 2
    return n, eng.index.size / n, lambda: eng.step(), 2.0


def impact_probe(cells: int):
    from craquelure.impact.api import initial_state, settings, workload
    from craquelure.impact.engine import Engine
    from craquelure.impact.initial_state import build_specimen

    scene = load_scene("impact/default", [f"particles.diameter_cells={cells}"])
    sp = build_specimen(scene, 0)
    eng = Engine(settings(scene), initial_state(scene, sp))
    # neighbours as the prediction counts them (the workload's grid estimate, 20.9; the list
    # of the 40-cell disc holds 18.9 per particle, its rim has fewer): the fitted cost per
    # pair then carries the same convention as the scenes it predicts
    return sp.n, float(workload(scene)["neighbours"]), lambda: eng.step(), 1.0


def lattice_probe(n: int, effects=("beams",)):
    from craquelure.lattice.bench import block_engine

    eng = block_engine(n, effects)
    # a run advances the kernel a frame interval per call: 10 steps per call here, not 1 (one
    # Python call per step costs ~0.07 ms, as much as 800 particles' step)
    return (eng.system.n, 2 * eng.system.bi.size / eng.system.n, lambda: eng.run(10), 10.0)


# probe and its two sizes (serial kernels), and the size the speed-up S(2) is measured at (the
# lattice's parallel kernel starts at 20 000 bonds: its S(2) is that of a larger block)
PROBES = {"drying": (drying_probe, (1600, 6400), 6400), "impact": (impact_probe, (40, 100), 100),
          "lattice": (lattice_probe, (1600, 6400), 17600)}
# N-proportional cost charged per neighbour (SPH pair loops) or per particle (lattice)
PER_PAIR = {"drying": True, "impact": True, "lattice": False}


def fit_engine(name: str, steps: int) -> dict:
    probe, sizes, size_s = PROBES[name]
    points = []
    for size in sizes:
        set_threads(1)
        n, k, step, per = probe(size)
        points.append((n, k, timed_steps(step, steps, clock=time.process_time) / per))
    t1 = points[-1][2]
    if size_s != sizes[-1]:
        _, _, step1, per1 = probe(size_s)
        t1 = timed_steps(step1, steps, clock=time.process_time) / per1
    set_threads(2)
    _, _, step2, per2 = probe(size_s)
    t2 = timed_steps(step2, steps) / per2
    set_threads(1)
    (n_a, k_a, t_a), (n_b, k_b, t_b) = points
    x_a, x_b = (n_a * k_a, n_b * k_b) if PER_PAIR[name] else (n_a, n_b)
    slope = (t_b - t_a) / (x_b - x_a)
    fixed = max(0.0, t_a - slope * x_a)
    unit = "rate evaluations" if name == "drying" else "steps"
    out = {"unit": unit, "per_unit_s": float(fixed),
           "per_particle_s": 0.0 if PER_PAIR[name] else float(slope),
           "per_pair_s": float(slope) if PER_PAIR[name] else 0.0,
           "speedup_2": float(max(1.0, t1 / t2))}
    if name == "lattice":
        out["per_particle_effect_s"] = lattice_effect_costs(sizes[-1], t_b, steps)
    return out


def lattice_effect_costs(size: int, t_beams: float, steps: int) -> dict[str, float]:
    """Extra seconds per particle-step of each lattice effect on the beams-only block (the
    drying and impact probes run their default scenes' full effect sets instead). A block at
    rest breaks, melts and touches little: the cost measured is the effect's per-particle
    work, not the contact rebuilds that breaking triggers."""
    from craquelure.registry import known_effects

    set_threads(1)
    extra = {}
    for name in sorted(known_effects("lattice")):
        if name == "beams":
            continue
        n, _, step, per = lattice_probe(size, ("beams", name))
        t = timed_steps(step, steps, clock=time.process_time) / per
        extra[name] = round(max(0.0, (t - t_beams) / n), 14)
    return extra


def fit_softdyn() -> dict:
    from craquelure.softdyn.api import workload
    from craquelure.softdyn.initial_state import build

    scene = load_scene("softdyn/t1_single_ci")
    set_threads(1)
    run(build(scene), desc="warm-up")
    t0 = time.perf_counter()
    run(build(scene), desc="calibration")
    seconds = time.perf_counter() - t0
    return {"unit": "T1 integrations x log(1 + T) (1 + log10(1/F~))",
            "per_unit_s": seconds / workload(scene)["units"], "per_particle_s": 0.0,
            "per_pair_s": 0.0, "speedup_2": 1.0}


CI_SCENES = {"drying": ("drying/ci", ["outputs.t_end=0.02", "outputs.times=[0.02]"]),
             "impact": ("impact/ci", ["outputs.t_end=2.0e-6", "outputs.snapshot_times=[]"]),
             "lattice": ("lattice/gravity_block", ["outputs.t_end=0.5"]),
             "softdyn": ("softdyn/t1_single_ci", ["outputs.t_end=0.01"])}


def run_once(scene: str, overrides: list[str], threads: int, cpu: bool = False):
    """Wall time of ``craquelure run`` in a subprocess; with ``cpu=True`` a dict of it
    (``wall``), the process's CPU time (``cpu``) and the wall time of its time loop (``loop``,
    from the run's "done: ... wall time X s" line: the part the per-step model predicts,
    without process start, imports, initial state and writing)."""
    env = {**os.environ, "NUMBA_NUM_THREADS": str(threads)}
    with tempfile.TemporaryDirectory() as tmp:
        cmd = [sys.executable, "-m", "craquelure", "run", scene, "--out", f"{tmp}/run.nc"]
        for item in overrides:
            cmd += ["--set", item]
        r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
        t0 = time.perf_counter()
        proc = subprocess.run(cmd, env=env, capture_output=True, text=True)
        wall = time.perf_counter() - t0
        r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    if proc.returncode != 0:
        raise RuntimeError(f"{scene} {overrides}: {proc.stderr.strip().splitlines()[-1:]}")
    used = (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)
    if not cpu:
        return wall
    loops = LOOP_LINE.findall(proc.stderr + proc.stdout)
    return {"wall": wall, "cpu": used, "loop": float(loops[-1]) if loops else math.nan}


# time loops predicted shorter than this are dominated by loading the cached kernels (0.1-0.5 s
# idle, seconds on a busy machine), not by per-step work
LONG_LOOP_S = 2.0
LOOP_LINE = re.compile(r"\bdone: .*?wall time ([0-9.]+) s")


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
    """Overrides that run ``ref`` to ``fraction`` x its t_end (none for softdyn or f = 1)."""
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


def predicted(ref: str, overrides: list[str], threads: int) -> tuple[float, float]:
    """(fixed cost, compute part) predicted for ``ref`` with ``overrides``, as `craquelure
    check` predicts it."""
    scene = load_scene(ref, overrides)
    return predicted_parts(scene.model, model_api(scene.model).workload(scene), threads)


def run_factor(ref: str, threads: int, compute_seconds: float, max_stretch: float) -> float:
    """t_end factor that makes the predicted compute part ``compute_seconds`` (at most
    ``max_stretch``, by default 1: never past the scene's t_end; 1 for softdyn)."""
    if load_scene(ref).model not in STEPPED:
        return 1.0
    _, compute = predicted(ref, [], threads)
    return min(max_stretch, compute_seconds / compute) if compute > 0 else max_stretch


def warm_up(ref: str, threads: int) -> None:
    """An untimed short run that compiles the scene's kernels: t_end x 1e-3 (a scene may refuse
    a run shorter than its step: then x 1e-2, x 1e-1); softdyn: t_end = 0.01."""
    if load_scene(ref).model not in STEPPED:
        cuts = [["outputs.t_end=0.01"]]
    else:
        cuts = [scaled_overrides(ref, f) for f in (1e-3, 1e-2, 1e-1)]
    for overrides in cuts:
        try:
            load_scene(ref, overrides)
            run_once(ref, overrides, threads)
            return
        except (SceneError, RuntimeError):
            continue  # a warm-up only compiles; some studies refuse a cut run


def measure(scenes: list[str], threads: int, fraction: float | None = None,
            compute_seconds: float = 20.0, max_stretch: float = 1.0) -> None:
    rule = (f"t_end x {fraction:g} (time-stepped models)" if fraction is not None else
            f"t_end scaled to at most {compute_seconds:g} s of predicted compute and at most "
            f"x {max_stretch:g}")
    print(f"# {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}; {threads} thread(s); "
          f"{rule}; load average {os.getloadavg()[0]:.1f}; model {TABLE.name}")
    print(f"{'':<30} {'':>8} {'':>7} {'whole run, wall [s]':^27}  {'time loop [s]':^21}  "
          f"{'CPU [s]':^14}")
    print(f"{'scene':<30} {'t_end x':>8} {'compute':>7} {'predicted':>9} {'measured':>9} "
          f"{'ratio':>6}  {'predicted':>9} {'run':>6} {'ratio':>4}  {'run':>6} {'ratio':>6}  "
          f"verdict")
    hits = dominated = dominated_hits = loops = loop_hits = 0
    for ref in scenes:
        factor = (fraction if fraction is not None else
                  run_factor(ref, threads, compute_seconds, max_stretch))
        overrides = scaled_overrides(ref, factor)
        fixed, compute = predicted(ref, overrides, threads)
        total = fixed + compute
        warm_up(ref, threads)
        try:
            got = run_once(ref, overrides, threads, cpu=True)
        except RuntimeError as exc:
            print(f"{ref:<30} {factor:>8.3g} {compute / total:>7.0%} {total:>9.1f} "
                  f"{'-':>9}  MISS: the run failed: {exc}", flush=True)
            continue
        measured = got["wall"]
        ratio = total / measured
        ok = abs(ratio - 1.0) <= TOLERANCE
        hits += ok
        if compute >= fixed:
            dominated += 1
            dominated_hits += ok
        if compute >= LONG_LOOP_S:
            loops += 1
            loop_hits += abs(compute / got["loop"] - 1.0) <= TOLERANCE
        print(f"{ref:<30} {factor:>8.3g} {compute / total:>7.0%} {total:>9.1f} "
              f"{measured:>9.1f} {ratio:>6.2f}  {compute:>9.2f} {got['loop']:>6.1f} "
              f"{compute / got['loop']:>5.2f}  {got['cpu']:>6.1f} {total / got['cpu']:>6.2f}  "
              f"{'ok' if ok else 'MISS'}", flush=True)
    print(f"# whole run: {hits} of {len(scenes)} within +-{TOLERANCE:.0%}; {dominated_hits} of "
          f"the {dominated} rows whose predicted compute part is at least half of the wall time")
    print(f"# time loop alone: {loop_hits} of the {loops} rows predicting at least "
          f"{LONG_LOOP_S:g} s of compute within +-{TOLERANCE:.0%} (in shorter loops loading the "
          f"cached kernels weighs)")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--calibrate", action="store_true")
    parser.add_argument("--steps", type=int, default=20, help="steps per calibration timing")
    parser.add_argument("--scenes", nargs="+", default=None)
    parser.add_argument("--fraction", type=float, default=None,
                        help="scale every time-stepped scene's t_end by this (1: as they are)")
    parser.add_argument("--compute-seconds", type=float, default=20.0,
                        help="without --fraction: predicted compute part of each stepped run")
    parser.add_argument("--max-stretch", type=float, default=1.0,
                        help="without --fraction: longest run, in units of the scene's t_end")
    parser.add_argument("--threads", type=int, default=1)
    args = parser.parse_args()
    if args.calibrate:
        calibrate(args.steps)
    else:
        measure(args.scenes or built_in_scenes(), args.threads, args.fraction,
                args.compute_seconds, args.max_stretch)


if __name__ == "__main__":
    main()
