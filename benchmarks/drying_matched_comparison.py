"""Matched comparison of the drying integrators at the paper's drying speed (issue 15, item 1):
the same seeds run with ABM4 (dt = 0.004, the paper's scheme) and with the error-controlled
rkc2, then the statistics of each scheme with bootstrap intervals over seeds:

- onset, in units of t* = sigma_Y/v_r: first removal, first closed fragment (first snapshot
  with >= 2 fragments) and all samples broken (every sample >= 2 fragments), per seed and the
  bootstrap interval of their mean (all-broken: of the maximum over seeds);
- <S>_t, the pooled mean fragment area, at every snapshot;
- the fit 1/<S>_t = b (t - t0) over the snapshots at which every sample of both schemes is
  broken (least squares), b and t0/t*.

Agreement per statistic: the two 95 % bootstrap intervals overlap (printed as "agree") or not
("DIFFER"); with one seed there is no interval and no verdict. Runs are written to
``--out-dir`` and reused (an interrupted run resumes from its checkpoint), so the comparison
can be built up over several sessions; ``--analyse-only`` only
reads what exists. Scene: config/scenes/drying/paper_speed.yaml (L = 5, N = 1e4,
v_r = 2.2e-5, t = 0..300). The full comparison of the issue:

    nohup nice python benchmarks/drying_matched_comparison.py --seeds 1 2 3 4 5 6 7 8 \\
        --out-dir results/drying/matched > matched.log &

Reduced (smaller box, fewer seeds): ``--box-length 2.5 --seeds 1 2``.
"""

from __future__ import annotations

import argparse
import json
import time
import warnings
from pathlib import Path

import numpy as np
import xarray as xr

from craquelure.drying.analysis import analyse_run
from craquelure.drying.api import run
from craquelure.io import open_dataset, write_dataset
from craquelure.scene import load_scene, scenes_dir

N_BOOT = 2000
RNG_SEED = 20261201


def _run_path(out_dir: Path, integrator: str, seed: int) -> Path:
    return out_dir / f"{integrator}_seed{seed}.nc"


def simulate(scene, out_dir: Path, integrator: str, seed: int) -> float:
    """Run (or resume) one seed; returns the CPU seconds of this process's part."""
    out = _run_path(out_dir, integrator, seed)
    if out.exists():
        return 0.0
    start = time.process_time()
    run(scene.with_overrides([f"numerics.integrator={integrator}"]), out, seed=seed,
        resume=True)
    cpu = time.process_time() - start
    log = out_dir / "cpu_seconds.json"
    record = json.loads(log.read_text()) if log.exists() else {}
    record[out.name] = record.get(out.name, 0.0) + cpu
    log.write_text(json.dumps(record, indent=1))
    return cpu


def fragments(out_dir: Path, integrator: str, seed: int) -> xr.Dataset:
    path = _run_path(out_dir, integrator, seed)
    cached = path.with_name(path.stem + ".fragments.nc")
    if not cached.exists():
        write_dataset(analyse_run(open_dataset(path), progress=False), cached)
    return open_dataset(cached)


def _interval(draws: np.ndarray) -> list[float]:
    draws = draws[np.isfinite(draws)]
    if draws.size == 0:
        return [float("nan"), float("nan")]
    return [float(np.percentile(draws, 2.5)), float(np.percentile(draws, 97.5))]


def statistics(frags: list[xr.Dataset], tstar: float, fit_mask: np.ndarray) -> dict:
    """Statistics of one scheme over its seeds, with bootstrap-over-seeds intervals."""
    times = frags[0]["time"].values.astype(float)
    count = np.stack([f["n_fragments"].values for f in frags]).astype(float)
    total = np.stack([np.bincount(f["fragment_time_index"].values,
                                  weights=f["fragment_area"].values, minlength=times.size)
                      for f in frags])
    first_removal = np.array([f.attrs["first_removal_time"] for f in frags], float) / tstar
    broken = count >= 2
    first_closed = np.array([times[np.argmax(b)] if b.any() else np.nan for b in broken]) / tstar
    rng = np.random.default_rng(RNG_SEED)
    n_s = len(frags)
    draws = rng.integers(0, n_s, size=(N_BOOT, n_s))
    weights = np.zeros((N_BOOT, n_s))
    np.add.at(weights, (np.repeat(np.arange(N_BOOT), n_s), draws.ravel()), 1.0)

    def mean_stat(values: np.ndarray) -> dict:
        """Mean over the seeds that reached the event (NaN if none did)."""
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            return {"value": float(np.nanmean(values)),
                    "ci95": _interval(np.nanmean(values[draws], axis=1))}

    with np.errstate(invalid="ignore", divide="ignore"):
        mean_area = total.sum(axis=0) / count.sum(axis=0)
        boot_area = (weights @ total) / (weights @ count)
    out = {
        "seeds": n_s,
        "first_removal_over_t_star": mean_stat(first_removal),
        "first_closed_fragment_over_t_star": mean_stat(first_closed),
        "all_broken_over_t_star": {"value": float(np.max(first_closed)),
                                   "ci95": _interval(np.max(first_closed[draws], axis=1))},
        "mean_area": {"times": times.tolist(), "value": mean_area.tolist(),
                      "ci95": [_interval(boot_area[:, k]) for k in range(times.size)]},
    }
    t = times[fit_mask]
    if t.size >= 3:
        def fit(area: np.ndarray) -> tuple[float, float]:
            slope, intercept = np.polyfit(t, 1.0 / area, 1)
            return slope, -intercept / slope / tstar

        b, t0 = fit(mean_area[fit_mask])
        boot = np.array([fit(row[fit_mask]) for row in boot_area
                         if np.all(np.isfinite(row[fit_mask]) & (row[fit_mask] > 0))])
        out["fit"] = {"times": t.tolist(), "b": {"value": b, "ci95": _interval(boot[:, 0])},
                      "t0_over_t_star": {"value": t0, "ci95": _interval(boot[:, 1])}}
    return out


def _agree(a: list[float], b: list[float], seeds: int) -> str:
    if seeds < 2:
        return "n/a (1 seed: no interval)"
    if not all(np.isfinite(a + b)):
        return "n/a"
    return "agree" if a[0] <= b[1] and b[0] <= a[1] else "DIFFER"


def report(stats: dict[str, dict], cpu: dict[str, float]) -> None:
    names = list(stats)
    a, b = (stats[n] for n in names)
    print(f"{'statistic':<34} " + " ".join(f"{n + ' [95% CI]':>34}" for n in names) + "  overlap")
    rows = [(k, a[k], b[k]) for k in ("first_removal_over_t_star",
                                      "first_closed_fragment_over_t_star",
                                      "all_broken_over_t_star")]
    if "fit" in a and "fit" in b:
        rows += [("fit b", a["fit"]["b"], b["fit"]["b"]),
                 ("fit t0/t*", a["fit"]["t0_over_t_star"], b["fit"]["t0_over_t_star"])]
    for t, va, ca, vb, cb in zip(a["mean_area"]["times"], a["mean_area"]["value"],
                                 a["mean_area"]["ci95"], b["mean_area"]["value"],
                                 b["mean_area"]["ci95"], strict=True):
        rows.append((f"<S>_t at t = {t:g}", {"value": va, "ci95": ca},
                     {"value": vb, "ci95": cb}))
    for label, x, y in rows:
        cells = [f"{s['value']:.4g} [{s['ci95'][0]:.4g}, {s['ci95'][1]:.4g}]" for s in (x, y)]
        verdict = _agree(x["ci95"], y["ci95"], min(a["seeds"], b["seeds"]))
        print(f"{label:<34} {cells[0]:>34} {cells[1]:>34}  {verdict}")
    for n in names:
        print(f"CPU s of the runs made by this process, {n}: {cpu.get(n, 0.0):.0f}")


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, nargs="+", default=[1, 2, 3, 4, 5, 6, 7, 8])
    parser.add_argument("--box-length", type=float, default=5.0, help="L (N = 400 L^2)")
    parser.add_argument("--t-end", type=float, default=300.0)
    parser.add_argument("--integrators", nargs=2, default=["abm4", "rkc2"])
    parser.add_argument("--out-dir", type=Path, default=Path("results/drying/matched"))
    parser.add_argument("--analyse-only", action="store_true")
    args = parser.parse_args(argv)
    overrides = [f"domain.box_length={args.box_length!r}",
                 f"particles.n={int(round(400 * args.box_length**2))}",
                 f"outputs.t_end={args.t_end!r}"]
    path = scenes_dir() / "drying" / "paper_speed.yaml"
    # the snapshots up to --t-end, set together with it (a scene never holds times after t_end)
    times = [t for t in load_scene(path).get("outputs.times") if t <= args.t_end]
    scene = load_scene(path, [*overrides, f"outputs.times={times}"])
    args.out_dir.mkdir(parents=True, exist_ok=True)
    cpu = {name: 0.0 for name in args.integrators}
    if not args.analyse_only:
        for seed in args.seeds:
            for name in args.integrators:
                cpu[name] += simulate(scene, args.out_dir, name, seed)
    seeds = [s for s in args.seeds
             if all(_run_path(args.out_dir, n, s).exists() for n in args.integrators)]
    if not seeds:
        print("no seed has finished runs of both schemes yet")
        return
    tstar = float(scene.get("material.yield_stress")) / float(scene.get("material.drying_rate"))
    tau = float(scene.get("material.eta")) / (2.0 * float(scene.get("material.lame_mu")))
    frags = {n: [fragments(args.out_dir, n, s) for s in seeds] for n in args.integrators}
    counts = np.concatenate([np.stack([f["n_fragments"].values for f in frags[n]])
                             for n in args.integrators])
    fit_mask = np.all(counts >= 2, axis=0)
    stats = {n: statistics(frags[n], tstar, fit_mask) for n in args.integrators}
    print(f"# matched comparison: seeds {seeds}, L = {args.box_length:g}, "
          f"N = {int(scene.get('particles.n'))}, t = 0..{args.t_end:g}, t* = {tstar:.1f}, "
          f"Pi = tau/t* = {tau / tstar:.3f}; fit over the snapshots where every sample of "
          f"both schemes is broken: {np.asarray(times)[fit_mask].tolist()}")
    report(stats, cpu)
    log = args.out_dir / "cpu_seconds.json"
    if log.exists():  # every part of each run, over all the processes that ran it
        record = json.loads(log.read_text())
        for seed in seeds:
            parts = [record.get(_run_path(args.out_dir, n, seed).name) for n in args.integrators]
            if all(parts):
                print(f"recorded CPU s, seed {seed}: " + ", ".join(
                    f"{n} {c:.0f}" for n, c in zip(args.integrators, parts, strict=True))
                    + f"; ratio {parts[0] / parts[1]:.2f}")
    (args.out_dir / "comparison.json").write_text(json.dumps(
        {"seeds": seeds, "box_length": args.box_length, "t_end": args.t_end, "t_star": tstar,
         "statistics": stats}, indent=1))


if __name__ == "__main__":
    main()
