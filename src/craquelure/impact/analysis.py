"""Campaign analysis of the impact model (spec sections 6-7, check 12): run datasets to
``results/impact/summary.json``.

:func:`summarise` reads the run datasets' ``metric_*`` attributes, groups them by case
(masses, pre-crack, κ), gives per-seed values, medians and spread (min, max, interquartile
range), and evaluates each of the source's qualitative findings as a criterion with the
measured numbers, ``reproduced`` true or false. The figures are :mod:`.figures`.
"""

from __future__ import annotations

import json
import math
from collections import defaultdict
from pathlib import Path

import numpy as np

from craquelure.io import open_dataset

PER_RUN = ("n_main_cracks", "main_crack_angle_deg", "cracked_fraction",
           "cracked_fraction_damage", "crushed_area", "crushed_height", "contact_force_peak",
           "contact_impulse", "contact_duration", "rebound_velocity",
           "energy_balance_error_max", "min_y_final", "precrack_cracked_fraction",
           "precrack_angle_deg", "wall_time_s", "steps", "centre_crossings")


def _num(v):
    if isinstance(v, np.generic):
        v = v.item()
    if isinstance(v, float) and not math.isfinite(v):
        return None
    return v


def read_metrics(path: Path) -> dict:
    ds = open_dataset(path)
    out = {k[len("metric_"):]: _num(v) for k, v in ds.attrs.items() if k.startswith("metric_")}
    out["wall_time_s"] = _num(ds.attrs.get("wall_time_s"))
    out["seed"] = int(ds.attrs.get("seed", 0))
    out["path"] = str(path)
    return out


def case_key(m: dict) -> str:
    return f"{m['distribution']}/{m['precrack_layout']}/kappa{float(m['kappa']):g}"


def _stats(values):
    vals = np.array([v for v in values if v is not None], float)
    if vals.size == 0:
        return None
    q1, med, q3 = np.percentile(vals, [25, 50, 75])
    return {"median": float(med), "min": float(vals.min()), "max": float(vals.max()),
            "iqr": float(q3 - q1), "n": int(vals.size)}


def _angle_diff(a, b):
    d = abs((a - b + 90.0) % 180.0 - 90.0)
    return d


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
    findings = evaluate_findings(out_cases, distribution)
    total_wall = sum(m["wall_time_s"] or 0 for m in runs)
    return {
        "profile": profile, "scene": scene, "n_runs": len(runs),
        "n_seeds_heterogeneous": max((len(c["seeds"]) for k, c in out_cases.items()
                                      if not k.startswith("homogeneous/")), default=0),
        "all_runs_finished": True,
        "max_energy_balance_error": max(abs(m["energy_balance_error_max"]) for m in runs),
        "total_run_wall_time_s": total_wall,
        "cases": out_cases, "findings": findings,
        "notes": ("cracked = softening s >= 0.9 (residual tensile strength <= 0.1 f_t); "
                  "D_t >= 0.9 is reported as cracked_fraction_damage. Main cracks: clusters of "
                  "cracked, not crushed particles (reference distance <= 1.5 Delta) with extent "
                  ">= R; parallel crack bands closer than 1.5 Delta merge into one cluster, "
                  "and cracks joined by a branch or a transverse crack count once: "
                  "centre_crossings (cracked runs along the row at the disc centre height) "
                  "counts them separately and is given with each finding."),
    }


def _med(cases, key, q):
    c = cases.get(key)
    if c is None or c["stats"].get(q) is None:
        return None
    return c["stats"][q]["median"]


def evaluate_findings(cases: dict, dist: str) -> list[dict]:
    f = []

    def add(name, criterion, values, ok):
        f.append({"finding": name, "criterion": criterion, "values": values,
                  "reproduced": bool(ok) if ok is not None else None,
                  "status": "not run" if ok is None else ("reproduced" if ok else
                                                          "NOT reproduced")})

    homo = cases.get("homogeneous/none/kappa1")
    if homo:
        n, ang, area = (homo["per_seed"]["n_main_cracks"][0],
                        homo["per_seed"]["main_crack_angle_deg"][0],
                        homo["per_seed"]["crushed_area"][0])
        add("homogeneous: one symmetric vertical main crack, crushed contact zone",
            "N_mc = 1, |theta| <= 10 deg, A_cr > 0",
            {"N_mc": n, "theta_deg": ang, "A_cr_m2": area,
             "centre_crossings": homo["per_seed"]["centre_crossings"][0]},
            n == 1 and ang is not None and abs(ang) <= 10 and area > 0)
    else:
        add("homogeneous: one main crack", "N_mc = 1", {}, None)
    het = {k: cases.get(f"{dist}/none/kappa{k:g}") for k in (0.7, 1.0, 1.5)}
    phi_h = _med(cases, "homogeneous/none/kappa1", "cracked_fraction")
    if het[1.0]:
        n1 = _med(cases, f"{dist}/none/kappa1", "n_main_cracks")
        p1 = _med(cases, f"{dist}/none/kappa1", "cracked_fraction")
        add("heterogeneous kappa = 1: several main cracks, more damage",
            "median N_mc >= 2 and median phi_c above the homogeneous disc",
            {"median_N_mc": n1, "median_phi_c": p1, "phi_c_homogeneous": phi_h,
             "median_centre_crossings": _med(cases, f"{dist}/none/kappa1", "centre_crossings"),
             "centre_crossings_homogeneous": _med(cases, "homogeneous/none/kappa1",
                                                  "centre_crossings")},
            n1 >= 2 and phi_h is not None and p1 > phi_h)
    if het[1.5] and het[1.0]:
        frac = het[1.5]["fraction_one_main_crack"]
        p15 = _med(cases, f"{dist}/none/kappa1.5", "cracked_fraction")
        p1 = _med(cases, f"{dist}/none/kappa1", "cracked_fraction")
        add("kappa = 1.5: heterogeneity smoothed, one main crack",
            "N_mc = 1 in >= 60 % of seeds and median phi_c(1.5) < phi_c(1.0)",
            {"fraction_N_mc_1": frac, "median_phi_c_1.5": p15, "median_phi_c_1.0": p1},
            frac >= 0.6 and p15 < p1)
    if het[0.7] and het[1.0]:
        frac = het[0.7]["fraction_one_main_crack"]
        vals = {q: (_med(cases, f"{dist}/none/kappa0.7", q), _med(cases, f"{dist}/none/kappa1", q))
                for q in ("cracked_fraction", "crushed_area")}
        add("kappa = 0.7: one main crack, more failure along it and at the contact",
            "N_mc = 1 in >= 50 % of seeds; median phi_c and A_cr above kappa = 1.0",
            {"fraction_N_mc_1": frac, "phi_c_0.7_vs_1.0": vals["cracked_fraction"],
             "A_cr_0.7_vs_1.0": vals["crushed_area"]},
            frac >= 0.5 and vals["cracked_fraction"][0] > vals["cracked_fraction"][1]
            and vals["crushed_area"][0] > vals["crushed_area"][1])
    _crossing_findings(cases, dist, add)
    forces = {k: _med(cases, f"homogeneous/none/kappa{k:g}", "contact_force_peak")
              for k in (0.7, 1.0, 1.5)}
    if all(v is not None for v in forces.values()):
        spread = (max(forces.values()) - min(forces.values())) / max(forces.values())
        add("contact forces differ between kappa values (homogeneous disc)",
            "peak force spread over kappa > 5 %", {"peak_force_N_per_m": forces,
                                                   "relative_spread": spread}, spread > 0.05)
    for pf in ("pf1", "pf2", "pf3"):
        c = cases.get(f"homogeneous/{pf}/kappa1")
        if not c:
            continue
        frac = c["per_seed"]["precrack_cracked_fraction"][0]
        ang = c["per_seed"]["main_crack_angle_deg"][0]
        pang = c["per_seed"]["precrack_angle_deg"][0]
        diff = _angle_diff(ang, pang) if ang is not None and pang is not None else None
        add(f"{pf}: failure follows the zero-mass line",
            ">= 80 % of particles within 1.5 Delta of the pre-crack cracked and the main crack "
            "within 15 deg of it",
            {"fraction_cracked_near_precrack": frac, "main_crack_angle_deg": ang,
             "precrack_angle_deg": pang, "angle_difference_deg": diff},
            frac is not None and frac >= 0.8 and diff is not None and diff <= 15)
    return f


def _crossing_findings(cases: dict, dist: str, add) -> None:
    """The main-crack findings again with the centre-line crossings as the crack counter
    (see :mod:`craquelure.impact.measure`): the cluster rule merges joined radial cracks."""
    def med(key):
        return _med(cases, key, "centre_crossings")

    def frac_one(key):
        c = cases.get(key)
        vals = [v for v in c["per_seed"]["centre_crossings"] if v is not None] if c else []
        return float(np.mean([v == 1 for v in vals])) if vals else None

    homo, het1 = med("homogeneous/none/kappa1"), med(f"{dist}/none/kappa1")
    if homo is not None:
        add("homogeneous, by centre crossings: one central main crack",
            "exactly 1 cracked run along the centre row", {"centre_crossings": homo},
            homo == 1)
    if homo is not None and het1 is not None:
        add("heterogeneous kappa = 1, by centre crossings: several main cracks",
            "median crossings >= 2 and above the homogeneous disc",
            {"median_crossings": het1, "homogeneous": homo}, het1 >= 2 and het1 > homo)
    f15, f07 = frac_one(f"{dist}/none/kappa1.5"), frac_one(f"{dist}/none/kappa0.7")
    if f15 is not None and het1 is not None:
        add("kappa = 1.5, by centre crossings: one main crack",
            "1 crossing in >= 60 % of seeds", {"fraction_1_crossing": f15,
                                                "median_crossings": med(f"{dist}/none/kappa1.5")},
            f15 >= 0.6)
    if f07 is not None and het1 is not None:
        add("kappa = 0.7, by centre crossings: one main crack",
            "1 crossing in >= 50 % of seeds", {"fraction_1_crossing": f07,
                                                "median_crossings": med(f"{dist}/none/kappa0.7")},
            f07 >= 0.5)


def write_summary(summary: dict, path: Path) -> None:
    from craquelure.io import write_text_atomic

    write_text_atomic(path, json.dumps(summary, indent=2, default=_num) + "\n")
