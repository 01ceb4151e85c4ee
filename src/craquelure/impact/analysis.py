"""Campaign analysis of the impact model (spec sections 6-7, check 12): run datasets to
``results/impact/summary.json``.

:func:`summarise` reads the run datasets' ``metric_*`` attributes, groups them by case
(masses, pre-crack, κ), gives per-seed values, medians and spread (min, max, interquartile
range), and evaluates each of the source's qualitative findings as a criterion with the
measured numbers and a verdict, per seed (:mod:`.check12`, check 12 as revised). The figures
are :mod:`.figures`.
"""

from __future__ import annotations

import json
import math
from collections import defaultdict
from pathlib import Path

import numpy as np

from craquelure.impact import check12
from craquelure.io import open_dataset

PER_RUN = ("n_main_cracks", "main_crack_angle_deg", "cracked_fraction",
           "cracked_fraction_damage", "crushed_area", "crushed_height", "contact_force_peak",
           "contact_impulse", "contact_duration", "rebound_velocity",
           "energy_balance_error_max", "min_y_final", "precrack_cracked_fraction",
           "precrack_angle_deg", "wall_time_s", "steps", "centre_crossings",
           "centre_crossings_x_mm",
           # revised check 12 (craquelure.impact.check12)
           "n_main_cracks_revised", "main_crossings_x_mm", "main_crack_length_revised",
           "main_crack_theta_deg", "main_crack_x_mid", "second_crack_length",
           "n_secondary_cracks", "cracked_fraction_near_main", "precrack_coverage",
           "precrack_tip_extension_low", "precrack_tip_extension_high",
           "main_cracks_elsewhere",
           # what the comparisons hold fixed, per run
           "spacing", "as_epsilon", "crack_band_width", "contact_a", "material_model")


def _num(v):
    if isinstance(v, np.generic):
        v = v.item()
    if isinstance(v, float) and not math.isfinite(v):
        return None
    return v


def crack_metrics(ds) -> dict:
    """The revised check-12 measurements recomputed from a run dataset's final fields (the
    run's own ``metric_*`` were computed with the measurement code of its day), with the
    thresholds of the run's resolved scene."""
    import yaml

    from craquelure.impact.measure import precrack_following, revised_cracks

    material = yaml.safe_load(ds.attrs["scene"]).get("material", {})
    cracked = material.get("cracked_threshold", 0.9)
    crushed = material.get("crushed_strain", 0.0035)
    field = "damage" if material.get("cracked_measure") == "damage" else "softening"
    x0, y0 = ds["x0"].values, ds["y0"].values
    crack, plastic = ds[field].values, ds["plastic_strain"].values
    precrack = ds["precrack"].values.astype(bool)
    spacing = float(ds.attrs["metric_spacing"])
    centre_y = 0.5 * (y0.min() + y0.max())
    out = revised_cracks(x0, y0, crack, plastic, spacing, centre_y, cracked, crushed)
    if precrack.any():
        out.update(precrack_following(x0, y0, crack, plastic, precrack, spacing, centre_y,
                                      cracked, crushed))
    return out


def read_metrics(path: Path) -> dict:
    ds = open_dataset(path)
    out = {k[len("metric_"):]: _num(v) for k, v in ds.attrs.items() if k.startswith("metric_")}
    out.update({k: _num(v) for k, v in crack_metrics(ds).items()})
    out["wall_time_s"] = _num(ds.attrs.get("wall_time_s"))
    out["seed"] = int(ds.attrs.get("seed", 0))
    out["path"] = str(path)
    return out


def case_key(m: dict) -> str:
    return f"{m['distribution']}/{m['precrack_layout']}/kappa{float(m['kappa']):g}"


def _stats(values):
    vals = np.array([v for v in values if v is not None and not isinstance(v, str)], float)
    if vals.size == 0:
        return None
    q1, med, q3 = np.percentile(vals, [25, 50, 75])
    return {"median": float(med), "min": float(vals.min()), "max": float(vals.max()),
            "iqr": float(q3 - q1), "n": int(vals.size)}


def summarise(paths, profile: str, scene: str, distribution: str) -> dict:
    runs = [read_metrics(Path(p)) for p in paths]
    cases: dict[str, list] = defaultdict(list)
    for m in runs:
        cases[case_key(m)].append(m)
    out_cases = {}
    for key, ms in sorted(cases.items()):
        ms = sorted(ms, key=lambda m: m["seed"])
        out_cases[key] = {
            "seeds": [m["seed"] for m in ms],
            "as_epsilon": ms[0].get("as_epsilon"),
            "contact_a": ms[0].get("contact_a"),
            "per_seed": {q: [m.get(q) for m in ms] for q in PER_RUN},
            "stats": {q: _stats([m.get(q) for m in ms]) for q in PER_RUN
                      if q not in ("precrack_angle_deg",)},
            "fraction_one_main_crack": float(np.mean([m["n_main_cracks"] == 1 for m in ms])),
        }
    findings, reported = check12.evaluate(out_cases, distribution, "2D")
    total_wall = sum(m["wall_time_s"] or 0 for m in runs)
    return {
        "profile": profile, "scene": scene, "n_runs": len(runs),
        "n_seeds_heterogeneous": max((len(c["seeds"]) for k, c in out_cases.items()
                                      if not k.startswith("homogeneous/")), default=0),
        "all_runs_finished": True,
        "max_energy_balance_error": max(abs(m["energy_balance_error_max"]) for m in runs),
        "total_run_wall_time_s": total_wall,
        "material_model": sorted({str(m.get("material_model")) for m in runs}),
        "cases": out_cases, "findings": findings,
        # findings carry their dimension ("dim"); a 3D campaign's sit beside the 2D ones
        "dimensions": ["2D"], "reported_without_verdict": {"2D": reported},
        "notes": ("cracked = softening s >= 0.9 (residual tensile strength <= 0.1 f_t); "
                  "D_t >= 0.9 is reported as cracked_fraction_damage. Main cracks: clusters of "
                  "cracked, not crushed particles (reference distance <= 1.5 Delta) with extent "
                  ">= R; parallel crack bands closer than 1.5 Delta merge into one cluster, "
                  "and cracks joined by a branch or a transverse crack count once: "
                  "centre_crossings (cracked runs along the row at the disc centre height) "
                  "counts them separately and is given with each finding."),
    }


def write_summary(summary: dict, path: Path) -> None:
    from craquelure.io import write_text_atomic

    write_text_atomic(path, json.dumps(summary, indent=2, default=_num) + "\n")
