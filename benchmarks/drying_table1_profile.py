"""Cost and profile of one Table I drying run (issue 28, item 1): config/scenes/drying/table1.yaml
(L = 10, N = 4e4, v_r = 2.2e-5, Pi = 0.022, t = 0..300) with rkc2, one seed, through the
ordinary run path (``craquelure.drying.api.run``: checkpoints, resume, the run dataset).

Where the CPU time goes is measured by wrapping, in this process only, the engine's entry
points with ``time.process_time`` counters (they do not change any result): the full rate
evaluations (both pair passes and the per-particle updates), the viscous-only rate calls of the
power iteration, neighbour-list builds, particle removals (with their rebuild and restart
evaluation) and the whole step; "Python per step" is the step's time outside those calls (the
RKC stage combinations, the error norm, the removal-event limit). The split of one rate
evaluation into its pair passes is measured separately by benchmarks/drying_roofline.py.

Run with one numba thread (CPU time is then the work, whatever the load):

    NUMBA_NUM_THREADS=1 nohup nice -n 5 python benchmarks/drying_table1_profile.py \\
        --out results/drying/table1/rkc2_seed1.nc > table1.log 2>&1 &

It resumes from the run's checkpoint when restarted; the profile of each process part is
appended to ``<out>.profile.json`` and the report sums the parts.
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

from craquelure.drying import api
from craquelure.drying import engine as engine_module
from craquelure.scene import load_scene, scenes_dir

COUNTERS = ("rate", "rate_in_step", "power_iteration_rate", "power_iteration",
            "neighbour_list", "removal", "step", "run")


class Profile:
    def __init__(self) -> None:
        self.cpu = dict.fromkeys(COUNTERS, 0.0)
        self.calls = dict.fromkeys(COUNTERS, 0)

        self.in_step = False
        self.listed_pairs = 0

    def timed(self, key: str, fn):
        def wrapper(*args, **kwargs):
            outer = key == "step"
            if outer:
                self.in_step = True
            start = time.process_time()
            try:
                return fn(*args, **kwargs)
            finally:
                spent = time.process_time() - start
                self.cpu[key] += spent
                self.calls[key] += 1
                if key == "rate" and self.in_step:
                    self.cpu["rate_in_step"] += spent
                    self.calls["rate_in_step"] += 1
                if outer:
                    self.in_step = False
        self.listed_pairs = 0
        return wrapper


class _TimedModule:
    """A rate module whose ``rate`` is timed under ``key``."""

    def __init__(self, module, profile: Profile, key: str) -> None:
        self._module = module
        self.rate = profile.timed(key, module.rate)

    def __getattr__(self, name):
        return getattr(self._module, name)


def instrument(profile: Profile) -> None:
    """Wrap the engine's entry points (this process only)."""
    compile_rate = engine_module.compile_rate

    def timed_compile(effects, kernel):
        key = "power_iteration_rate" if tuple(effects) == ("viscosity",) else "rate"
        return _TimedModule(compile_rate(effects, kernel), profile, key)

    engine_module.compile_rate = timed_compile
    build = profile.timed("neighbour_list", engine_module.neighbour_list)

    def counted_build(*args, **kwargs):
        offsets, index = build(*args, **kwargs)
        profile.listed_pairs += index.size  # pairs of every build, for the mean
        return offsets, index

    engine_module.neighbour_list = counted_build
    cls = engine_module.DryingEngine
    cls.viscous_spectral_radius = profile.timed("power_iteration", cls.viscous_spectral_radius)
    cls.remove_overstressed = profile.timed("removal", cls.remove_overstressed)
    cls.step = profile.timed("step", cls.step)


def report(parts: list[dict], dataset_attrs: dict | None, pairs_per_pass: float | None) -> None:
    cpu = {k: sum(p["cpu"][k] for p in parts) for k in COUNTERS}
    calls = {k: sum(p["calls"][k] for p in parts) for k in COUNTERS}
    total = cpu["run"]
    print(f"# {len(parts)} process part(s); CPU s of the run: {total:.1f}")
    # neighbour builds happen inside steps (moved particles, removals) and at checkpoints
    in_step_other = (cpu["step"] - cpu["rate_in_step"] - cpu["power_iteration"]
                     - cpu["neighbour_list"])
    rows = [
        ("rate evaluations (2 pair passes each)", cpu["rate"], calls["rate"]),
        ("power iteration (viscous-only rates)", cpu["power_iteration_rate"],
         calls["power_iteration_rate"]),
        ("power iteration, Python part", cpu["power_iteration"] - cpu["power_iteration_rate"],
         calls["power_iteration"]),
        ("neighbour-list builds", cpu["neighbour_list"], calls["neighbour_list"]),
        ("Python per step (RKC combinations, error norm, removal test)", in_step_other,
         calls["step"]),
        ("outside steps (initial state, compilation, snapshots, checkpoints)",
         total - cpu["step"], 0),
    ]
    print(f"{'part':<64} {'CPU s':>9} {'share':>7} {'calls':>8} {'ms/call':>9}")
    for label, c, n in rows:
        print(f"{label:<64} {c:>9.1f} {100 * c / total:>6.1f}% {n:>8d} "
              f"{1e3 * c / n if n else float('nan'):>9.2f}")
    print(f"{'  of which removals (rebuild + restart evaluation, in the rows above)':<64} "
          f"{cpu['removal']:>9.1f} {100 * cpu['removal'] / total:>6.1f}% "
          f"{calls['removal']:>8d}")
    if dataset_attrs:
        a = dataset_attrs
        t_end = a["t_end"]
        print(f"steps {a['steps']}, rejected {a['rejected_steps']}, rate evaluations "
              f"{a['rate_evaluations']}, power-iteration evaluations "
              f"{a['spectral_radius_evaluations']}, neighbour builds {a['neighbour_builds']}; "
              f"evaluations per time unit {a['rate_evaluations'] / t_end:.1f}")
    if pairs_per_pass:
        per_eval = cpu["rate"] / max(calls["rate"], 1)
        print(f"listed pairs per pass {pairs_per_pass:.3e}: {2 * pairs_per_pass / per_eval:.3e} "
              f"pair visits/s over whole evaluations")
    print(f"100-seed campaign from this run: {100 * total / 3600:.1f} core-hours")


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scene", type=Path, default=scenes_dir() / "drying" / "table1.yaml")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--out", type=Path, default=Path("results/drying/table1/rkc2_seed1.nc"))
    parser.add_argument("--checkpoint-every", type=int, default=None,
                        help="steps between checkpoints (default: the scene's; wall-time "
                        "checkpoints as for craquelure run)")
    parser.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    parser.add_argument("--report-only", action="store_true")
    args = parser.parse_args(argv)
    log = args.out.with_name(args.out.name + ".profile.json")
    parts = json.loads(log.read_text()) if log.exists() else []
    if not args.report_only and not (args.out.exists() and parts):
        scene = load_scene(args.scene, ["numerics.integrator=rkc2", *args.set])
        profile = Profile()
        instrument(profile)
        args.out.parent.mkdir(parents=True, exist_ok=True)
        start, wall = time.process_time(), time.perf_counter()
        part: dict = {}
        parts.append(part)

        def save() -> None:
            """This part's profile so far (also every 50 steps: a run stopped by the clock
            still leaves its profile)."""
            profile.cpu["run"] = time.process_time() - start
            part.update({"cpu": dict(profile.cpu), "calls": dict(profile.calls),
                         "listed_pairs": profile.listed_pairs,
                         "wall": time.perf_counter() - wall, "finished": args.out.exists(),
                         "overrides": args.set, "steps_in_part": profile.calls["step"],
                         "date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())})
            tmp = log.with_name(log.name + ".tmp")
            tmp.write_text(json.dumps(parts, indent=1))
            tmp.replace(log)

        step = engine_module.DryingEngine.step

        def step_and_save(self):
            removed = step(self)
            ctrl = self.controller
            part["engine"] = {"t": self.t, "steps": self.step_count,
                              "rate_evaluations": self.evaluations,
                              "power_iteration_evaluations": self.viscous_evaluations,
                              "rejected": ctrl.rejected if ctrl else 0,
                              "removed": self.n_removed,
                              "neighbour_builds": self.neighbour_builds}
            if profile.calls["step"] % 50 == 0:
                save()
            return removed

        engine_module.DryingEngine.step = step_and_save
        try:
            api.run(scene, args.out, seed=args.seed, resume=True,
                    checkpoint_every=args.checkpoint_every)
        finally:
            save()
    builds = sum(p["calls"]["neighbour_list"] for p in parts)
    attrs, pairs = None, sum(p["listed_pairs"] for p in parts) / max(builds, 1)
    if args.out.exists():
        import xarray as xr

        with xr.open_dataset(args.out) as ds:
            attrs = dict(ds.attrs, t_end=float(ds["time"].max()))
    report(parts, attrs, pairs)


if __name__ == "__main__":
    main()
