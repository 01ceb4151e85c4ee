"""Initial disorder and the onset of cracking at the paper's drying speed (issue 15, item 3;
drying spec section 12, doubt 3): the minimum gap of the random (RSA) initial positions,
``particles.rsa_min_separation`` in units of Delta = L/sqrt(N), against

- the mass-consistency solve (``numerics.mass_solve.method: clamped_cg`` at every gap): CG
  residual, the smallest mass in units of m_bar, masses held at the floor 0.1 m_bar, the
  Shepard field's range and whether spec check 3 passes (below 0.8 Delta it does not: the
  states are used anyway and the table says so);
- the onset, in units of t* = sigma_Y/v_r: first removal, and first closed fragment (first
  snapshot with >= 2 fragments; snapshots every 10 time units = 0.044 t*), per seed, with the
  mean over seeds and its 95 % bootstrap interval over seeds.

Scene: config/scenes/drying/paper_speed.yaml (Table I material, v_r = 2.2e-5, Pi = 0.022, rkc2),
at a reduced box (default L = 2.5, N = 2500: a quarter of the paper-speed scene's area, so
onset times are those of a smaller sample, later by extreme-value statistics, and a crack
wrapping the torus may leave a sample one fragment). Runs and initial states are written to
``--out-dir`` and reused (a run resumes from its checkpoint); ``--analyse-only`` prints the table
from what exists.

    nohup nice python benchmarks/drying_initial_disorder.py --gaps 0.5 0.65 0.8 --seeds 1 2 3 \\
        --out-dir results/drying/initial_disorder > disorder.log &
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np
import xarray as xr

from craquelure.drying.analysis import analyse_run
from craquelure.drying.api import run
from craquelure.drying.initial_state import build_initial_state
from craquelure.drying.mass_consistency import MassBounds, MassSolveReport, check_mass_report
from craquelure.errors import CraquelureError
from craquelure.io import open_dataset, write_dataset
from craquelure.provenance import WallClock, provenance_attrs
from craquelure.scene import load_scene, scenes_dir

N_BOOT = 2000
RNG_SEED = 20261201


def _label(gap: float) -> str:
    return f"gap{gap:g}".replace(".", "p")


def initial_state(scene, out_dir: Path, gap: float, seed: int) -> tuple[Path, dict]:
    """Initial state at this gap (clamped CG, check 3 reported, not enforced)."""
    path = out_dir / f"{_label(gap)}_seed{seed}.init.nc"
    if not path.exists():
        clock = WallClock()
        ds = build_initial_state(scene, seed, check=False)
        ds.attrs.update(provenance_attrs(scene, seed, clock))
        write_dataset(ds, path)
    ds = open_dataset(path)
    a = ds.attrs
    m_bar = float(ds["mass"].values.mean())
    fields = MassSolveReport.__dataclass_fields__
    report = MassSolveReport(**{k: a[k] for k in fields if k in a})
    try:
        check_mass_report(report, m_bar, MassBounds())
        check3 = "pass"
    except CraquelureError as err:
        check3 = "miss: " + str(err).split(": ", 1)[1].split(". Positions")[0]
    info = {"cg_residual": float(a["cg_residual"]),
            "mass_min_over_m_bar": float(ds["mass"].values.min()) / m_bar,
            "masses_at_floor": int(a.get("masses_at_floor", 0)),
            "shepard": [float(a["shepard_min"]), float(a["shepard_max"])],
            "check3": check3}
    return path, info


def simulate(scene, init: Path, out: Path) -> float:
    """Run (or resume) one state; CPU seconds of this process's part (0 if it existed)."""
    if out.exists():
        return 0.0
    start = time.process_time()
    run(scene, out, init=init, resume=True)
    return time.process_time() - start


def onset(out: Path, tstar: float) -> dict:
    cached = out.with_name(out.stem + ".fragments.nc")
    if not cached.exists():
        write_dataset(analyse_run(open_dataset(out), progress=False), cached)
    frags: xr.Dataset = open_dataset(cached)
    times = frags["time"].values.astype(float)
    broken = frags["n_fragments"].values >= 2
    closed = float(times[np.argmax(broken)]) / tstar if broken.any() else float("nan")
    alive = frags["n_alive"].values
    return {"first_removal": float(frags.attrs["first_removal_time"]) / tstar,
            "first_closed_fragment": closed, "removed_at_end": int(alive[0] - alive[-1]
                                                                  if alive.size else 0),
            "fragments_at_end": int(frags["n_fragments"].values[-1])}


def mean_interval(values: np.ndarray) -> tuple[float, float, float, int]:
    """Mean over the seeds that reached the event, its 95 % bootstrap interval, how many."""
    values = values[np.isfinite(values)]
    if values.size == 0:
        return float("nan"), float("nan"), float("nan"), 0
    rng = np.random.default_rng(RNG_SEED)
    boot = values[rng.integers(0, values.size, (N_BOOT, values.size))].mean(axis=1)
    lo, hi = np.percentile(boot, [2.5, 97.5])
    return float(values.mean()), float(lo), float(hi), int(values.size)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--gaps", type=float, nargs="+", default=[0.5, 0.65, 0.8],
                        help="particles.rsa_min_separation values (units of L/sqrt(N))")
    parser.add_argument("--seeds", type=int, nargs="+", default=[1, 2, 3])
    parser.add_argument("--box-length", type=float, default=2.5, help="L (N = 400 L^2)")
    parser.add_argument("--t-end", type=float, default=300.0)
    parser.add_argument("--out-dir", type=Path, default=Path("results/drying/initial_disorder"))
    parser.add_argument("--analyse-only", action="store_true")
    args = parser.parse_args(argv)
    n = int(round(400 * args.box_length**2))
    path = scenes_dir() / "drying" / "paper_speed.yaml"
    times = [t for t in load_scene(path).get("outputs.times") if t <= args.t_end] or [args.t_end]
    base = load_scene(path, [f"domain.box_length={args.box_length!r}", f"particles.n={n}",
                             f"outputs.t_end={args.t_end!r}", f"outputs.times={times}",
                             "numerics.mass_solve.method=clamped_cg"])
    tstar = float(base.get("material.yield_stress")) / float(base.get("material.drying_rate"))
    tau = float(base.get("material.eta")) / (2.0 * float(base.get("material.lame_mu")))
    args.out_dir.mkdir(parents=True, exist_ok=True)
    cpu_log = args.out_dir / "cpu_seconds.json"
    cpu = json.loads(cpu_log.read_text()) if cpu_log.exists() else {}
    rows = []
    for seed in args.seeds:  # every gap of a seed first: a stopped study stays balanced
        for gap in args.gaps:
            scene = base.with_overrides([f"particles.rsa_min_separation={gap!r}"])
            out = args.out_dir / f"{_label(gap)}_seed{seed}.nc"
            if args.analyse_only and not out.exists():
                continue
            init, info = initial_state(scene, args.out_dir, gap, seed)
            if not args.analyse_only:
                spent = simulate(scene, init, out)
                if spent:
                    cpu[out.name] = cpu.get(out.name, 0.0) + spent
                    cpu_log.write_text(json.dumps(cpu, indent=1))
            if out.exists():
                rows.append({"gap": gap, "seed": seed, **info, **onset(out, tstar),
                             "cpu_s": cpu.get(out.name, float("nan"))})
                print(json.dumps(rows[-1]), flush=True)
    if not rows:
        print("no finished run yet")
        return
    print(f"\n# initial disorder: L = {args.box_length:g}, N = {n}, t = 0..{args.t_end:g}, "
          f"t* = {tstar:.1f}, Pi = {tau / tstar:.3f}, rkc2, clamped_cg masses; "
          f"onset in units of t* (mean over seeds [95 % bootstrap interval], seeds reaching it)")
    print(f"{'gap':>5} {'seeds':>5} {'min m/m_bar':>11} {'at floor':>8} {'Shepard':>13} "
          f"{'check 3':>7} {'first removal':>26} {'first closed fragment':>26} "
          f"{'removed':>8} {'CPU-s/run':>9}")
    for gap in args.gaps:
        mine = [r for r in rows if r["gap"] == gap]
        if not mine:
            continue
        cells = []
        for key in ("first_removal", "first_closed_fragment"):
            m, lo, hi, k = mean_interval(np.array([r[key] for r in mine], float))
            cells.append(f"{m:.3f} [{lo:.3f}, {hi:.3f}] {k}/{len(mine)}")
        shep = (min(r["shepard"][0] for r in mine), max(r["shepard"][1] for r in mine))
        passes = sum(r["check3"] == "pass" for r in mine)
        print(f"{gap:>5g} {len(mine):>5} {min(r['mass_min_over_m_bar'] for r in mine):>11.3f} "
              f"{int(np.mean([r['masses_at_floor'] for r in mine])):>8} "
              f"{shep[0]:>6.3f}-{shep[1]:<6.3f} {passes:>3}/{len(mine):<3} {cells[0]:>26} "
              f"{cells[1]:>26} {np.mean([r['removed_at_end'] for r in mine]):>8.0f} "
              f"{np.nanmean([r['cpu_s'] for r in mine]):>9.0f}")
    (args.out_dir / "disorder.json").write_text(json.dumps(
        {"box_length": args.box_length, "n": n, "t_end": args.t_end, "t_star": tstar,
         "rows": rows}, indent=1))


if __name__ == "__main__":
    main()
