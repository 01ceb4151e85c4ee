"""Analysis of the impact model (spec sections 6-7, check 12): run datasets to per-run metrics
to ``results/impact/summary.json``.

Every measurement is made here (:func:`run_metrics`), from a run dataset's final fields and
series (:mod:`.api` writes no analysis) with the thresholds of the scene stored in it; an older
dataset's ``metric_*`` attributes are recomputed, not read (:func:`run_fact` aside).
:func:`summarise` groups the runs by dimension and case, with per-seed values, medians and
spread, and judges check 12's findings (:mod:`.check12`).
"""

from __future__ import annotations

import json
import math
from collections import defaultdict
from pathlib import Path

import numpy as np

from craquelure.impact import check12, measure
from craquelure.impact.workflow import case_key
from craquelure.io import open_dataset
from craquelure.scene import stored_scene

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
           # cracks by opening (craquelure.impact.measure.opening_cracks)
           "opening_w_c", "n_main_cracks_opening", "n_cracks_opening",
           "n_secondary_cracks_opening", "row_runs_x_mm", "row_runs_opening_mm",
           "row_runs_cracks", "row_largest_run_share", "main_run_x_mid", "main_run_opening",
           "main_run_share", "main_crack_theta_opening_deg", "main_crack_length_opening",
           "main_crack_max_opening", "second_crack_length_opening", "max_opening",
           "main_run_opening_half", "main_run_opening_growth", "precrack_coverage_opening",
           "precrack_largest_opening_on_line", "precrack_line_max_opening",
           "main_cracks_elsewhere_opening",
           # what the comparisons hold fixed, per run
           "spacing", "as_epsilon", "crack_band_width", "contact_a", "material_model")

# Resolved numbers a run used and what only the running engine saw: attributes of the run
# dataset (names of today's runs; older runs wrote them as metric_<legacy name>).
RUN_FACTS = {**{name: name for name in ("spacing", "radius", "n_particles", "as_epsilon",
                                         "crack_band_width", "contact_a", "material_model")},
             **{name: f"run_{name}" for name in ("dt_min", "energy_initial", "max_penetration",
                                                 "kinematic_impulse", "contact_force_peak_step",
                                                 "steps")}}


# "does not open further": the main crack's opening at the end against this earlier snapshot
OPENING_EARLIER_TIME = 5.0e-4  # s (the spec's 0.5 ms map)


def _num(v):
    if isinstance(v, np.generic):
        v = v.item()
    if isinstance(v, float) and not math.isfinite(v):
        return None
    return v


def run_fact(ds, name: str, default=None):
    """A resolved number or engine fact of a run (:data:`RUN_FACTS`), from today's attribute
    or an older run's ``metric_<name>``."""
    key = RUN_FACTS.get(name, name)
    return ds.attrs[key] if key in ds.attrs else ds.attrs.get(f"metric_{name}", default)


def run_scene(ds):
    """The scene a run dataset stores, read back as it was written (no re-validation)."""
    return stored_scene(str(ds.attrs["scene"]), name=str(ds.attrs.get("scene_name", "scene")))


def run_dim(ds, scene=None) -> int:
    """2 or 3: the run's ``dim`` attribute, else its scene's ``domain.dim``."""
    if "dim" in ds.attrs:
        return int(ds.attrs["dim"])
    scene = scene if scene is not None else run_scene(ds)
    return int(scene.get("domain.dim"))


def run_metrics(ds) -> dict:
    """Every per-run measurement (spec section 6, check 12) of a run dataset, from its final fields,
    series and stored scene; 3D on its mid-thickness layer (:func:`.measure.run_metrics`)."""
    scene = run_scene(ds)
    g = scene.get
    cracked = g("material.cracked_threshold")
    crushed = g("material.crushed_strain")
    measure_name = g("material.cracked_measure")
    x0, y0 = ds["x0"].values, ds["y0"].values
    crack = ds["damage" if measure_name == "damage" else "softening"].values
    plastic = ds["plastic_strain"].values
    precrack = ds["precrack"].values.astype(bool)
    spacing = float(run_fact(ds, "spacing"))
    centre_y = float(ds.attrs.get("centre_y", 0.5 * (y0.min() + y0.max())))
    z0 = ds["z0"].values if "z0" in ds else None
    out = measure.run_metrics(x0, y0, crack, plastic, precrack, spacing,
                              float(run_fact(ds, "radius")), cracked, crushed, centre_y, z0=z0)
    G_F, f_t = scene.optional("material.G_F"), scene.optional("material.f_t")
    # no fracture energy or tensile strength in the scene: nothing can open to a crack
    w_c = measure.full_softening_opening(G_F, f_t) if G_F and f_t else float("inf")
    half = None
    if "snap_x" in ds and ds.sizes.get("snapshot_time", 0):
        times = ds["snapshot_time"].values
        k = int(np.argmin(np.abs(times - OPENING_EARLIER_TIME)))
        if abs(times[k] - OPENING_EARLIER_TIME) <= 0.05 * OPENING_EARLIER_TIME:
            half = (ds["snap_x"].values[k], ds["snap_y"].values[k])
    out.update(measure.opening_metrics(
        x0, y0, ds["x"].values, ds["y"].values, ds["mass"].values, plastic, precrack, spacing,
        w_c, centre_y, z0=z0, half=half))
    out["cracked_fraction_damage"] = float(np.mean(ds["damage"].values >= cracked))
    out["cracked_measure"] = measure_name
    out.update(measure.contact_metrics(ds["time"].values, ds["series_contact_force"].values,
                                       ds["series_vcm_y"].values))
    out.update({
        "energy_balance_error_max": float(np.abs(ds["series_balance_error"].values).max()),
        "min_y_final": float(ds["y"].values.min()),
        "n_zero_mass": int(np.sum(ds["mass"].values == 0)),
        "kappa": g("numerics.kappa"), "effects": ",".join(scene.effects),
        "f_t": f_t, "impact_velocity": g("particles.impact_velocity"),
        "plane": g("domain.plane"), "distribution": g("particles.masses.distribution"),
        "precrack_layout": g("particles.precrack"), "dim": run_dim(ds, scene),
    })
    out.update({name: _num(run_fact(ds, name)) for name in RUN_FACTS})
    return {k: _num(v) for k, v in out.items()}


def read_metrics(path: Path) -> dict:
    ds = open_dataset(path)
    out = run_metrics(ds)
    out["wall_time_s"] = _num(ds.attrs.get("wall_time_s"))
    out["seed"] = int(ds.attrs.get("seed", 0))
    out["path"] = str(path)
    return out


def run_case_key(m: dict) -> str:
    return case_key(m["distribution"], m["precrack_layout"], m["kappa"])


def _stats(values):
    vals = np.array([v for v in values if v is not None and not isinstance(v, str)], float)
    if vals.size == 0:
        return None
    q1, med, q3 = np.percentile(vals, [25, 50, 75])
    return {"median": float(med), "min": float(vals.min()), "max": float(vals.max()),
            "iqr": float(q3 - q1), "n": int(vals.size)}


def _cases(runs: list[dict]) -> dict:
    cases: dict[str, list] = defaultdict(list)
    for m in runs:
        cases[run_case_key(m)].append(m)
    out = {}
    for key, ms in sorted(cases.items()):
        ms = sorted(ms, key=lambda m: m["seed"])
        out[key] = {
            "seeds": [m["seed"] for m in ms],
            "as_epsilon": ms[0].get("as_epsilon"),
            "contact_a": ms[0].get("contact_a"),
            "per_seed": {q: [m.get(q) for m in ms] for q in PER_RUN},
            "stats": {q: _stats([m.get(q) for m in ms]) for q in PER_RUN
                      if q not in ("precrack_angle_deg",)},
            "fraction_one_main_crack": float(np.mean([m["n_main_cracks"] == 1 for m in ms])),
        }
    return out


def summarise(paths, profile: str, scene: str, distribution: str,
              fixed_across_kappa: dict | None = None) -> dict:
    """summary.json of a campaign: cases (3D keys prefixed ``3D/``) and check-12 findings per
    dimension; ``fixed_across_kappa``: the config's ε_AS and ℓ_c held fixed across κ."""
    runs = [read_metrics(Path(p)) for p in paths]
    by_dim: dict[str, list] = defaultdict(list)
    for m in runs:
        by_dim[f"{int(m.get('dim') or 2)}D"].append(m)  # "2D" or "3D"
    dims = [d for d in ("3D", "2D") if d in by_dim]
    out_cases, findings, reported, seeds_by_dim = {}, [], {}, {}
    for dim in dims:
        cases = _cases(by_dim[dim])
        found, reported[dim] = check12.evaluate(cases, distribution, dim, fixed_across_kappa)
        findings += found
        seeds_by_dim[dim] = max((len(c["seeds"]) for k, c in cases.items()
                                 if not k.startswith("homogeneous/")), default=0)
        out_cases.update({("" if dim == "2D" else f"{dim}/") + k: {**c, "dim": dim}
                          for k, c in cases.items()})
    total_wall = sum(m["wall_time_s"] or 0 for m in runs)
    return {
        "profile": profile, "scene": scene, "n_runs": len(runs),
        "n_seeds_heterogeneous": max(seeds_by_dim.values(), default=0),
        "n_seeds_heterogeneous_by_dim": seeds_by_dim,
        "all_runs_finished": True,
        "max_energy_balance_error": max(abs(m["energy_balance_error_max"]) for m in runs),
        "total_run_wall_time_s": total_wall,
        "run_wall_time_s_by_dim": {d: sum(m["wall_time_s"] or 0 for m in by_dim[d])
                                   for d in dims},
        "material_model": sorted({str(m.get("material_model")) for m in runs}),
        "material_model_by_dim": {d: sorted({str(m.get("material_model")) for m in by_dim[d]})
                                  for d in dims},
        "fixed_across_kappa": dict(fixed_across_kappa or {}),
        "cases": out_cases, "findings": findings,
        # findings carry their dimension ("dim"): the 3D campaign's beside the 2D one's
        "dimensions": dims, "reported_without_verdict": reported,
        "notes": ("Cracks are counted by opening (measure.opening_cracks, 2026-12-02): the "
                  "growth of neighbour-pair separations in the plane (2D) or the mid-thickness "
                  "layer (3D), opened above w_c = 2 G_F/f_t (the crack band's full-softening "
                  "opening); N_main = main-crack crossings of the centre row (runs of opened "
                  "gaps, ceil(k/2) cracks per run of k), each finding judged by its defining "
                  "condition (check12.verdict). Softening-based numbers stay as secondary: "
                  "cracked = softening s >= 0.9 (cracked_fraction), D_t >= 0.9 "
                  "(cracked_fraction_damage), clusters (n_main_cracks_revised)."),
    }


def write_summary(summary: dict, path: Path) -> None:
    from craquelure.io import write_text_atomic

    write_text_atomic(path, json.dumps(summary, indent=2, default=_num) + "\n")
