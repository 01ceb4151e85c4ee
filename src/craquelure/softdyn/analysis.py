"""Analysis of Soft Dynamics runs: from the workflow's datasets (sweep, phase scan, accuracy
study, T1 or sphere-pair run, told apart by their content: :func:`numbers`) to ``summary.json``,
the numbers the claims judge (the same quantities as the spec checks in ``tests/softdyn``).
"""

import json
import math
from pathlib import Path

import numpy as np
import xarray as xr

from craquelure.io import open_dataset, write_text_atomic
from craquelure.scene import stored_scene
from craquelure.softdyn import theory


def _material(ds: xr.Dataset) -> tuple[float, float]:
    scene = stored_scene(ds.attrs["scene"])
    return float(scene.get("material.c_n")), float(scene.get("material.k_n"))


def sweep_numbers(ds: xr.Dataset) -> dict:
    """Fig. 5: per force, is T decreasing in h0, and the local slope d ln T / d ln h0 between
    the two grid points nearest below h0/h* = 0.1; the span of T in decades."""
    done = (ds.computed == 1) & (ds.finished == 1)
    duration = ds.duration.where(done)
    monotone, slopes = [], []
    for force in ds.force.values:
        col = duration.sel(force=force)
        ratio = ds.h0_over_h_star.sel(force=force).values
        ok = np.isfinite(col.values)
        t, r = col.values[ok], ratio[ok]
        if t.size >= 2:
            monotone.append(bool(np.all(np.diff(t) < 0)))
        hertz = np.nonzero(r <= 0.1 + 1e-9)[0]
        if hertz.size >= 2:
            i, j = hertz[-1], hertz[-2]
            slopes.append([float(force), math.log(t[j] / t[i]) / math.log(r[j] / r[i]),
                           float(r[j]), float(r[i])])
    finite = duration.values[np.isfinite(duration.values)]
    return {"kind": "sweep", "finished": int(done.sum()), "forces": int(ds.force.size),
            "monotone": monotone, "slopes": slopes,
            "span_decades": math.log10(finite.max() / finite.min()) if finite.size else 0.0}


def phase_numbers(ds: xr.Dataset) -> dict:
    """Fig. 3: the occurrence of the T1 and its prediction on the (F_h/F_v, F~) grid."""
    return {"kind": "phase", "fh_over_fv": ds.fh_over_fv.values.tolist(),
            "force": ds.force.values.tolist(), "occurred": ds.occurred.values.tolist(),
            "predicted": ds.predicted.values.tolist()}


def t1_numbers(ds: xr.Dataset) -> dict:
    theta = ds.theta.values
    return {"kind": "t1", "theta_start": float(theta[0]), "theta_final": float(theta[-1]),
            "largest_rise": float(np.max(np.diff(theta), initial=0.0)),
            "duration": float(ds.attrs["duration"])}


def approach_numbers(ds: xr.Dataset) -> dict:
    """Check 4: the rate of ln h while h >= 100 h* (times c_n tau) and d(h^-2)/dt while
    h <= h*/100 over its prediction 2/(c_n tau h*^2) (``None`` without 3 samples)."""
    c_n, k_n = _material(ds)
    hs = theory.h_star(float(ds.attrs["reduced_force"]), k_n)
    t, h = ds.time.values, ds.gap.values[:, 0]
    out = {"kind": "approach", "rate": None, "rate_samples": 0, "hertz_ratio": None}
    window = (h >= 100 * hs) & (t > 100 * float(stored_scene(ds.attrs["scene"]).get(
        "loads.ramp_time")))
    if window.sum() >= 3:
        out["rate"] = float(-np.polyfit(t[window], np.log(h[window]), 1)[0] * c_n)
        out["rate_samples"] = int(window.sum())
    window = h <= hs / 100
    if window.sum() >= 3:
        t_w, h_w = t[window], h[window]
        measured = (h_w[-1] ** -2 - h_w[0] ** -2) / (t_w[-1] - t_w[0])
        out["hertz_ratio"] = float(measured / (2.0 / (c_n * hs**2)))
    return out


def separation_numbers(ds: xr.Dataset) -> dict:
    c_n, k_n = _material(ds)
    h0, force = float(ds.attrs["h0"]), float(ds.attrs["reduced_force"])
    return {"kind": "separation", "h0": h0, "reduced_force": force,
            "duration": float(ds.attrs["duration"]),
            "predicted": float(theory.t_separation(h0, force, k_n, c_n))}


def accuracy_numbers(ds: xr.Dataset) -> dict:
    return {"kind": "accuracy", "duration_order": float(ds.attrs["heun_duration_order"]),
            "state_order": float(ds.attrs["heun_state_order"])}


def numbers(path: Path) -> dict:
    """The numbers of one source dataset, by what it contains."""
    ds = open_dataset(path)
    if "duration" in ds.data_vars and "h0" in ds.dims:
        out = sweep_numbers(ds)
    elif "occurred" in ds.data_vars:
        out = phase_numbers(ds)
    elif "heun_duration_order" in ds.attrs:
        out = accuracy_numbers(ds)
    elif "theta" in ds.data_vars:
        out = t1_numbers(ds)
    elif "gap" in ds.data_vars:
        direction = stored_scene(ds.attrs["scene"]).get("loads.direction")
        out = approach_numbers(ds) if direction == "compression" else separation_numbers(ds)
    else:
        raise ValueError(f"softdyn analysis: {path} is none of sweep, phase scan, accuracy "
                         f"study, T1 run or sphere-pair run")
    return {"source": str(path), **out}


def summarise(sources: list[Path], out: Path) -> dict:
    """``summary.json``: the numbers of every source, in order."""
    summary = {"sources": [numbers(Path(p)) for p in sources]}
    write_text_atomic(out, json.dumps(summary, indent=2) + "\n")
    return summary
