r"""Analysis of drying runs (drying spec sections 9, 10 and 13, checks 14-16): run datasets to
the analysis datasets and ``results/drying/summary.json``, in three stages, each a dataset or
file of its own (the claims read only the summary):

1. :func:`fragments_from_run_file` (this module): the fragments of every snapshot of one run
   (the image and its labelling are :mod:`craquelure.drying.binarise`).
2. :func:`~craquelure.drying.campaign.campaign_from_files`: the campaign aggregate of the
   per-seed fragment datasets.
3. :func:`~craquelure.drying.summary.write_summary`: the statistics that test the paper's
   claims, checks 14-16 (:mod:`craquelure.drying.ensemble`).

Times are in units of :math:`t^* = \sigma_Y/v_r`, with the paper's windows rescaled
(:mod:`craquelure.drying.time_scales`)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import xarray as xr

from craquelure.drying import crack_measures
from craquelure.drying.binarise import edge_depth, fragment_areas, snapshot_image
from craquelure.drying.field import mesh_spacing
from craquelure.drying.time_scales import t_star
from craquelure.errors import CraquelureError, SceneError
from craquelure.io import DatasetError, open_dataset, read_dataset, write_dataset
from craquelure.progress import Progress
from craquelure.provenance import WallClock, provenance_attrs
from craquelure.scene import Scene, stored_scene

RUN_VARIABLES = ("x", "y", "alive", "mass", "rho")


def run_scene(run: xr.Dataset) -> Scene:
    """The resolved scene stored in a run dataset's ``scene`` attribute."""
    if "scene" not in run.attrs:
        raise CraquelureError("run dataset has no `scene` attribute (not a craquelure run?)")
    return stored_scene(str(run.attrs["scene"]), name=str(run.attrs.get("scene_name", "scene")))


def grouped_study(groups: dict, build) -> xr.Dataset:
    """A study over groups of fragment datasets (``{key: [path, ...]}``, one key per thickness,
    speed or box size): ``build({key: [dataset, ...]})`` with the provenance of the first run
    and the ``sources`` it read."""
    clock = WallClock()
    fragments = {key: [open_dataset(p) for p in paths] for key, paths in groups.items()}
    study = build(fragments)
    first = next(iter(fragments.values()))[0]
    study.attrs.update(provenance_attrs(run_scene(first), None, clock,
                                        effects=str(first.attrs.get("effects", "")).split(",")))
    study.attrs["sources"] = ",".join(p for paths in groups.values() for p in paths)
    return study


def first_removal_time(run: xr.Dataset) -> float:
    """Earliest time-series sample with ``n_removed > 0`` (NaN if nothing was removed)."""
    if "n_removed" not in run or "step_time" not in run["n_removed"].dims:
        return float("nan")
    removed = np.asarray(run["n_removed"].values) > 0
    if not removed.any():
        return float("nan")
    return float(run["step_time"].values[np.argmax(removed)])


def analyse_run(run: xr.Dataset, phi0: float | None = None, spacing_h: float | None = None,
                progress: bool = True) -> xr.Dataset:
    """Fragments of every snapshot of a drying run dataset: ragged on dim ``fragment`` (all
    snapshots, in time order, periodic labelling) and ``fragment_open`` (the open image, whose
    edges cut fragments), counts and crack measures on dim ``time``. ``phi0`` and ``spacing_h``
    (mesh spacing in units of h) default to the scene's ``outputs.binarisation_threshold`` and
    ``outputs.binarisation_spacing``."""
    missing = [name for name in RUN_VARIABLES if name not in run]
    if missing or "time" not in run.dims or "particle" not in run.dims:
        raise CraquelureError(f"not a drying run dataset: missing {', '.join(missing) or 'dims'}"
                              " (expected dims time, particle and variables "
                              f"{', '.join(RUN_VARIABLES)})")
    if int(run.attrs.get("finished", 1)) == 0:
        raise CraquelureError("run dataset is not finished (a checkpoint?): analyse finished "
                              "runs only")
    for key in ("h", "box_length"):
        if key not in run.attrs:
            raise CraquelureError(f"run dataset has no `{key}` attribute")
    scene = run_scene(run)
    phi0 = float(scene.get("outputs.binarisation_threshold") if phi0 is None else phi0)
    spacing_h = float(scene.get("outputs.binarisation_spacing") if spacing_h is None
                      else spacing_h)
    if not 0.0 < phi0 < 1.0:
        raise CraquelureError(f"phi0 = {phi0} is not allowed; must lie in (0, 1)")
    if spacing_h <= 0:
        raise CraquelureError(f"mesh spacing = {spacing_h} h is not allowed; must be > 0")
    kernel = str(scene.get("numerics.kernel"))
    h, length = float(run.attrs["h"]), float(run.attrs["box_length"])
    times = run["time"].values
    bar = Progress(len(times), "fragments", unit="snapshot") if progress else None
    spacing = mesh_spacing(length, spacing_h * h)
    alive = run["alive"].values.astype(bool)
    areas, areas_open, measures = [], [], []
    for k in range(len(times)):
        image, spacing = snapshot_image(run, k, spacing_h, phi0, kernel)
        a = fragment_areas(image, spacing)
        areas.append(a)
        areas_open.append(fragment_areas(image, spacing, periodic=False))
        measures.append((image.mean(), crack_measures.crack_length_per_area(image, spacing),
                         crack_measures.largest_fraction(a, length),
                         crack_measures.damage(alive[k])))
        if bar is not None:
            bar.update_to(k + 1, f"t={times[k]:g}: {a.size} fragments")
    if bar is not None:
        bar.close()
    paste, crack_length, largest, damage = np.array(measures, float).reshape(-1, 4).T
    n_frag, n_open = (np.array([a.size for a in x], np.int64) for x in (areas, areas_open))
    mean_area = np.array([a.mean() if a.size else np.nan for a in areas], float)
    index, index_open = (np.repeat(np.arange(len(times), dtype=np.int64), n)
                         for n in (n_frag, n_open))
    area, area_open = (np.concatenate([np.zeros(0), *a]) for a in (areas, areas_open))
    # bare variables get their long names and units from craquelure.cf's table on writing
    ds = xr.Dataset(
        {
            "fragment_area": ("fragment", area, {"long_name": "fragment area S",
                                                 "units": "length^2"}),
            "fragment_time": ("fragment", times[index], {"long_name": "snapshot time"}),
            "fragment_time_index": ("fragment", index),
            "n_fragments": ("time", n_frag),
            "mean_area": ("time", mean_area, {"long_name": "mean fragment area of this run",
                                              "units": "length^2"}),
            "paste_fraction": ("time", paste,
                               {"long_name": "fraction of mesh points with phi >= phi0"}),
            "n_alive": ("time", alive.sum(axis=1).astype(np.int64)),
            "damage": ("time", damage, {"long_name": "removed-area fraction d = removed "
                                        "particles / N", "units": "1"}),
            "crack_length_per_area": ("time", crack_length, {
                "long_name": "crack length per area (half the paste/crack interface, "
                             "Cauchy-Crofton)", "units": "1/length"}),
            "largest_fragment_fraction": ("time", largest),
            "n_fragments_open": ("time", n_open, {
                "long_name": "fragments without periodic wrap-around (image as a plain "
                             "rectangle)", "units": "1"}),
            "fragment_area_open": ("fragment_open", area_open, {
                "long_name": "fragment area S, open-image labelling (no wrap-around)",
                "units": "length^2"}),
            "fragment_time_index_open": ("fragment_open", index_open),
        },
        coords={"time": ("time", times, dict(run["time"].attrs))},
    )
    ds.attrs.update({
        "h": h, "box_length": length, "n_particles": int(run.sizes["particle"]),
        "phi0": phi0, "mesh_spacing_h": spacing_h, "mesh_spacing": spacing,
        "mesh_points_per_side": int(round(length / spacing)),
        "edge_depth": edge_depth(phi0, kernel, h), "first_removal_time": first_removal_time(run),
        "connectivity": 4,
        "fracture_stress_measure": str(scene.get("material.fracture_stress_measure")),
        **onset_prediction(run, onset_time_scale(scene)),
    })
    return ds


def onset_time_scale(scene) -> float:
    """t* = sigma_Y/v_r of the run, NaN without a yield stress (optional without fracture) or
    without a drying stress that grows (the drying effect off, or v_r = 0)."""
    growing = (scene.optional("material.yield_stress") and scene.has("drying")
               and scene.get("material.drying_rate"))
    return t_star(scene) if growing else math.nan


def onset_prediction(run: xr.Dataset, tstar: float) -> dict[str, float]:
    """kappa before the first removal and the first removal it predicts (spec open doubt 7):
    ``kappa_max`` and ``kappa_criterion``, the medians of the run's records of them
    (:mod:`craquelure.drying.engine`), and ``predicted_first_removal_time`` =
    t*/kappa_criterion (NaN without records)."""
    out = {"kappa_max": math.nan, "kappa_criterion": math.nan, "kappa_records": 0,
           "predicted_first_removal_time": math.nan}
    if "kappa_max" not in run:
        return out
    kappa = np.asarray(run["kappa_max"].values, float)
    crit = np.asarray(run["kappa_criterion_max"].values, float)
    ok = np.isfinite(kappa) & np.isfinite(crit)
    if not ok.any():
        return out
    out.update(kappa_max=float(np.median(kappa[ok])), kappa_criterion=float(np.median(crit[ok])),
               kappa_records=int(ok.sum()))
    if math.isfinite(tstar):
        out["predicted_first_removal_time"] = tstar / out["kappa_criterion"]
    return out


def fragments_from_run_file(run_path: str | Path, out: str | Path, phi0: float | None = None,
                            spacing_h: float | None = None, progress: bool = True) -> Path:
    """Analyse a run file and write the fragment dataset with provenance: the run's own
    provenance is kept under ``run_*`` names, the analysis adds its own."""
    clock = WallClock()
    run = read_dataset(run_path, "drying run dataset", model="drying",
                       variables=(*RUN_VARIABLES, "time"))
    try:
        ds = analyse_run(run, phi0, spacing_h, progress)
        scene = run_scene(run)
    except SceneError as exc:
        raise DatasetError(f"{run_path}: its stored scene is not valid: {exc}") from exc
    except CraquelureError as exc:
        raise DatasetError(f"{run_path}: {exc}") from exc
    seed = run.attrs.get("seed")
    ds.attrs.update({f"run_{key}": run.attrs[key] for key in (
        "git_commit", "start_time", "wall_time_s", "host", "scene_overrides",
        "version_craquelure") if key in run.attrs})
    ds.attrs["source_run"] = str(run_path)
    ds.attrs.update(provenance_attrs(scene, None if seed is None else int(seed), clock,
                                     effects=str(run.attrs.get("effects", "")).split(",")))
    ds.attrs["wall_time_s"] = float(clock.elapsed)
    return write_dataset(ds, out)

