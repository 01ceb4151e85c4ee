"""Cost of the drying integrators at the paper's drying speed: ABM4 at dt = 0.004 against the
error-controlled Runge-Kutta-Chebyshev scheme rkc2 (issue 15, item 1).

Both schemes start from the same initial state of the paper-speed scene
(config/scenes/drying/paper_speed.yaml: Table I material, v_r = 2.2e-5, Pi = tau/t* = 0.022;
N = 400 L^2 at the paper's density) and advance in alternating chunks of simulated time in one
process, so the CPU times are measured side by side on the same (shared, noisy) machine and
their ratio is meaningful even when absolute times are not. Prints per scheme: steps, rate
evaluations (two pair passes each), spectral-radius work (viscous-only evaluations of the
power iteration), linear-solver work (none: both schemes are explicit), rejected steps,
removed particles, CPU s, and per simulated time unit; then the gain and the CPU time of a
paper run (t = 0..300) at L = 5 and L = 10, scaled linearly in N from the measured size.
ABM4's cost per time unit is fixed by its step (500 evaluations per time unit plus 4 extra
RK4 steps after each removal), so ``--abm4-t-end`` may stop it early; the table says so.

``--start-from T`` first advances rkc2 alone from t = 0 to T (its cost is printed), then both
schemes continue from that common state: a cheap side-by-side test of the cracking phase
(T = 150 at the paper's speed: first removals at t ~ 170), which also prints how far apart the
two solutions end (removed particles, first removal, mean stress).

    python benchmarks/drying_integrators.py [--box-length 2.5] [--t-end 300] [--seed 1]
        [--abm4-t-end 300] [--start-from 0] [--chunk 10] [--threads 1] [--set KEY=VALUE ...]
"""

from __future__ import annotations

import argparse
import math
import time

import numba

from craquelure.drying.api import engine_from_initial
from craquelure.drying.initial_state import build_initial_state
from craquelure.scene import load_scene, scenes_dir

PAPER_T_END = 300.0


class Tally:
    """One scheme's engine and its cost so far."""

    def __init__(self, scene, init, name: str, t_end: float) -> None:
        self.engine = engine_from_initial(scene, init)
        self.engine.control_time_step()
        self.name, self.t_end = name, t_end
        self.reset()

    def reset(self) -> None:
        eng = self.engine
        self.cpu = 0.0
        self.removal_steps = 0
        self.first_removal = math.nan
        self.t0, self.steps0, self.evals0 = eng.t, eng.step_count, eng.evaluations
        self.radius0, self.removed0 = eng.viscous_evaluations, eng.n_removed
        self.rejected0 = eng.controller.rejected if eng.controller else 0

    def take_state_of(self, other: Tally) -> None:
        """Continue from another scheme's state (same particles and initial positions)."""
        eng, src = self.engine, other.engine
        eng.state = src.state.copy()
        eng.mass, eng.alive = src.mass.copy(), src.alive.copy()
        eng.t, eng.n_removed = src.t, src.n_removed
        eng.stepper.restart()
        eng.rebuild()
        self.reset()

    def advance(self, t_stop: float) -> None:
        eng = self.engine
        t_stop = min(t_stop, self.t_end)
        start = time.process_time()
        while eng.t < t_stop - eng.time_tolerance():
            eng.stop_at = t_stop
            removed = eng.step()
            eng.check_health()
            if removed:
                self.removal_steps += 1
                if math.isnan(self.first_removal):
                    self.first_removal = eng.t
        self.cpu += time.process_time() - start

    def row(self) -> dict[str, float]:
        eng = self.engine
        span = eng.t - self.t0
        evals = eng.evaluations - self.evals0
        return {
            "scheme": self.name, "t": span, "steps": eng.step_count - self.steps0,
            "rate_evals": evals, "radius_evals": eng.viscous_evaluations - self.radius0,
            "rejected": (eng.controller.rejected if eng.controller else 0) - self.rejected0,
            "removed": eng.n_removed - self.removed0, "removal_steps": self.removal_steps,
            "first_removal": self.first_removal, "cpu": self.cpu,
            "evals_per_t": evals / span, "cpu_per_t": self.cpu / span,
        }


def print_table(rows: list[dict[str, float]]) -> None:
    print(f"{'scheme':<14} {'span':>6} {'steps':>7} {'rate ev':>8} {'radius ev':>9} "
          f"{'lin.solves':>10} {'rejected':>8} {'removed':>7} {'rem.steps':>9} "
          f"{'1st rem':>7} {'CPU s':>8} {'ev/t':>7} {'CPU s/t':>8}")
    for r in rows:
        print(f"{r['scheme']:<14} {r['t']:>6.1f} {r['steps']:>7d} {r['rate_evals']:>8d} "
              f"{r['radius_evals']:>9d} {0:>10d} {r['rejected']:>8d} {r['removed']:>7d} "
              f"{r['removal_steps']:>9d} {r['first_removal']:>7.1f} {r['cpu']:>8.1f} "
              f"{r['evals_per_t']:>7.1f} {r['cpu_per_t']:>8.3f}")


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--box-length", type=float, default=2.5, help="L (N = 400 L^2)")
    parser.add_argument("--t-end", type=float, default=PAPER_T_END)
    parser.add_argument("--abm4-t-end", type=float, default=None,
                        help="stop ABM4 here (its cost per time unit is set by its step)")
    parser.add_argument("--chunk", type=float, default=10.0, help="alternation chunk (time)")
    parser.add_argument("--start-from", type=float, default=0.0,
                        help="rkc2 alone up to here, then both from its state")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                        help="extra scene override for rkc2 (e.g. step_control values)")
    args = parser.parse_args(argv)
    numba.set_num_threads(args.threads)
    n = int(round(400 * args.box_length**2))
    base = [f"domain.box_length={args.box_length!r}", f"particles.n={n}",
            f"outputs.t_end={args.t_end!r}", f"outputs.times=[{args.t_end!r}]"]
    path = scenes_dir() / "drying" / "paper_speed.yaml"
    abm4_scene = load_scene(path, base + ["numerics.integrator=abm4", "numerics.dt=0.004"])
    rkc_scene = load_scene(path, base + ["numerics.integrator=rkc2", *args.set])
    init = build_initial_state(abm4_scene, args.seed)
    abm4_end = args.t_end if args.abm4_t_end is None else min(args.abm4_t_end, args.t_end)
    schemes = [Tally(abm4_scene, init, "abm4 dt=0.004", abm4_end),
               Tally(rkc_scene, init, "rkc2 adaptive", args.t_end)]
    t = 0.0
    control = rkc_scene.get("numerics.step_control")
    print(f"# paper drying speed v_r = {rkc_scene.get('material.drying_rate'):g} "
          f"(Pi = tau/t* = 0.022), L = {args.box_length:g}, N = {n}, seed {args.seed}, "
          f"{args.threads} numba thread(s); rkc2 tolerance {control['tolerance']:g}, "
          f"removal tolerance {control['removal_tolerance']:g}, dt_max {control['dt_max']:g}")
    if args.start_from > 0:
        t = args.start_from
        schemes[1].advance(t)
        print(f"# rkc2 alone over t = 0..{t:g}:")
        print_table([schemes[1].row()])
        schemes[0].take_state_of(schemes[1])
        schemes[1].reset()
    while t < args.t_end - 1e-9:
        t = min(t + args.chunk, args.t_end)
        for scheme in schemes:
            scheme.advance(t)
        print(f"# t = {t:g}: " + ", ".join(
            f"{s.name} {s.cpu:.1f} CPU s, removed {s.engine.n_removed}" for s in schemes),
            flush=True)
    rows = [s.row() for s in schemes]
    print(f"# both schemes over t = {args.start_from:g}..{args.t_end:g}:")
    print_table(rows)
    a_eng, r_eng = schemes[0].engine, schemes[1].engine
    if abs(a_eng.t - r_eng.t) < 1e-6:
        both = a_eng.alive & r_eng.alive
        gap = abs(a_eng.mean_stress[both] - r_eng.mean_stress[both]).max(initial=0.0)
        ys = rkc_scene.get("material.yield_stress")
        print(f"agreement at t = {a_eng.t:g}: removed {a_eng.n_removed} (abm4) vs "
              f"{r_eng.n_removed} (rkc2), {int((a_eng.alive != r_eng.alive).sum())} particles "
              f"removed by one scheme only; max |mean stress difference| on common particles "
              f"{gap / ys:.3g} sigma_Y")
    abm4, rkc = rows
    if abm4["t"] < rkc["t"] - 1e-6:
        # ABM4 after a removal: 4 RK4 steps (4 evaluations instead of 2) restart it.
        extra = 4 * 2 * rkc["removal_steps"] / rkc["t"]
        print(f"# ABM4 ran to t = {abm4['t']:g} only; over the whole run it needs "
              f"{abm4['evals_per_t']:.0f} + {extra:.1f} evaluations per time unit (RK4 "
              f"restarts after the {rkc['removal_steps']} removal steps rkc2 saw)")
        abm4_cpu_t = abm4["cpu_per_t"] * (1 + extra / abm4["evals_per_t"])
    else:
        abm4_cpu_t = abm4["cpu_per_t"]
    print(f"gain, CPU s per simulated time unit: {abm4_cpu_t / rkc['cpu_per_t']:.1f}x "
          f"(rate evaluations {abm4['evals_per_t'] / rkc['evals_per_t']:.1f}x; "
          f"CPU per evaluation abm4 {abm4['cpu'] / abm4['rate_evals'] * 1e3:.2f} ms, rkc2 "
          f"{rkc['cpu'] / (rkc['rate_evals'] + 0.5 * rkc['radius_evals']) * 1e3:.2f} ms "
          f"counting a radius evaluation as half)")
    if args.start_from > 0 or args.t_end < PAPER_T_END:
        print(f"# per-run figures below extrapolate the span t = {args.start_from:g}.."
              f"{args.t_end:g} only")
    for length in (5.0, 10.0):
        scale = 400 * length**2 / n * PAPER_T_END
        print(f"CPU s per paper run (t = 0..300) at L = {length:g} (N = {400 * length**2:.0f}), "
              f"linear in N: abm4 {abm4_cpu_t * scale:.0f}, rkc2 {rkc['cpu_per_t'] * scale:.0f}")


if __name__ == "__main__":
    main()
