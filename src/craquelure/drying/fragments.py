r"""Fragments of a binarised drying-paste image on the torus (drying spec section 9).

A fragment is a 4-connected component of paste pixels (value 1) of the periodic image:
scikit-image labels the components of the image as a plain rectangle
(``skimage.measure.label``, ``connectivity=1``), then the labels of facing edge pixels
(column 0 with column n-1, row 0 with row n-1) are joined with a union-find, so a fragment
cut by one edge, or by both (a blob around a corner), counts once. Pixels touching only
diagonally are separate fragments (4-connectivity), across the edges as well.

The area of a fragment is its pixel count times :math:`\Delta x^2` (physical units).
No minimum size is applied [D, spec section 9]; the statistics report the sensitivity to
:math:`S_{min} = \pi h^2` separately.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr
from skimage.measure import label as sk_label

from craquelure.drying.binarise import (
    DEFAULT_PHI0,
    DEFAULT_SPACING_H,
    edge_depth,
    snapshot_image,
)
from craquelure.errors import CraquelureError, SceneError
from craquelure.io import DatasetError, read_dataset, write_dataset
from craquelure.progress import Progress
from craquelure.provenance import WallClock, provenance_attrs
from craquelure.scene import Scene, stored_scene
from craquelure.sph.field import mesh_spacing


def _find(parent: np.ndarray, a: int) -> int:
    root = a
    while parent[root] != root:
        root = parent[root]
    while parent[a] != root:  # path compression
        parent[a], a = root, parent[a]
    return root


def _union_edge_labels(labels: np.ndarray, n: int) -> np.ndarray:
    """Union-find over labels that face each other across the periodic edges; returns the
    map old label -> root label (0 stays 0)."""
    parent = np.arange(n + 1)
    pairs = np.concatenate([
        np.stack([labels[:, 0], labels[:, -1]], axis=1),
        np.stack([labels[0, :], labels[-1, :]], axis=1),
    ])
    pairs = pairs[(pairs[:, 0] > 0) & (pairs[:, 1] > 0) & (pairs[:, 0] != pairs[:, 1])]
    for a, b in np.unique(pairs, axis=0):
        ra, rb = _find(parent, int(a)), _find(parent, int(b))
        if ra != rb:
            parent[max(ra, rb)] = min(ra, rb)
    return np.array([_find(parent, i) for i in range(n + 1)])


def label_periodic(image: np.ndarray) -> tuple[np.ndarray, int]:
    """4-connected labels of the 1-pixels of a periodic 2D image.

    Returns ``(labels, n)``: ``labels`` is 0 on background and 1..n on fragments, numbered in
    raster order of their first pixel.
    """
    image = np.asarray(image, dtype=bool)
    if image.ndim != 2:
        raise ValueError(f"expected a 2D image, got shape {image.shape}")
    labels, n = sk_label(image, connectivity=1, background=0, return_num=True)
    if n == 0:
        return labels, 0
    root = _union_edge_labels(labels, n)
    # scikit-image numbers components in raster order of their first pixel, and each root is
    # the smallest label of its group, so numbering the roots in increasing order keeps the
    # raster order of first appearance (no pass over the pixels needed).
    ordered = np.unique(root[1:])
    number = np.zeros(n + 1, dtype=labels.dtype)
    number[ordered] = np.arange(1, ordered.size + 1)
    relabel = number[root]
    return relabel[labels], int(ordered.size)


def fragment_areas(image: np.ndarray, spacing: float) -> np.ndarray:
    """Areas of the fragments of a periodic paste image (pixel count x spacing^2), in the
    numbering of :func:`label_periodic`."""
    labels, n = label_periodic(image)
    counts = np.bincount(labels.ravel(), minlength=n + 1)[1:]
    return counts * float(spacing) ** 2


# --- per-run fragment dataset -------------------------------------------------------------

RUN_VARIABLES = ("x", "y", "alive", "mass", "rho")


def run_scene(run: xr.Dataset) -> Scene:
    """The resolved scene stored in a run dataset's ``scene`` attribute."""
    if "scene" not in run.attrs:
        raise CraquelureError("run dataset has no `scene` attribute (not a craquelure run?)")
    return stored_scene(str(run.attrs["scene"]), name=str(run.attrs.get("scene_name", "scene")))


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
    """Fragments of every snapshot of a drying run dataset.

    ``phi0`` and ``spacing_h`` (mesh spacing in units of h) default to the scene's
    ``outputs.binarisation_threshold`` and ``outputs.binarisation_spacing``.
    Returns a dataset with ``fragment_area``, ``fragment_time``, ``fragment_time_index``
    (dim ``fragment``: ragged fragments of all snapshots, in time order) and
    ``n_fragments``, ``mean_area``, ``paste_fraction``, ``n_alive`` (dim ``time``).
    """
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
    phi0 = float(scene.get("outputs.binarisation_threshold", DEFAULT_PHI0)
                 if phi0 is None else phi0)
    spacing_h = float(scene.get("outputs.binarisation_spacing", DEFAULT_SPACING_H)
                      if spacing_h is None else spacing_h)
    if not 0.0 < phi0 < 1.0:
        raise CraquelureError(f"phi0 = {phi0} is not allowed; must lie in (0, 1)")
    if spacing_h <= 0:
        raise CraquelureError(f"mesh spacing = {spacing_h} h is not allowed; must be > 0")
    kernel = str(scene.get("numerics.kernel", "quintic"))
    h, length = float(run.attrs["h"]), float(run.attrs["box_length"])
    times = run["time"].values
    bar = Progress(len(times), "fragments", unit="snapshot") if progress else None
    areas, frag_time_index = [], []
    n_frag = np.zeros(len(times), np.int64)
    mean_area = np.full(len(times), np.nan)
    paste = np.zeros(len(times))
    spacing = mesh_spacing(length, spacing_h * h)
    for k in range(len(times)):
        image, spacing = snapshot_image(run, k, spacing_h, phi0, kernel)
        a = fragment_areas(image, spacing)
        areas.append(a)
        frag_time_index.append(np.full(a.size, k, np.int64))
        n_frag[k] = a.size
        if a.size:
            mean_area[k] = a.mean()
        paste[k] = image.mean()
        if bar is not None:
            bar.update_to(k + 1, f"t={times[k]:g}: {a.size} fragments")
    if bar is not None:
        bar.close()
    area = np.concatenate(areas) if areas else np.zeros(0)
    index = np.concatenate(frag_time_index) if frag_time_index else np.zeros(0, np.int64)
    alive = run["alive"].values.astype(bool)
    ds = xr.Dataset(
        {
            "fragment_area": ("fragment", area, {"long_name": "fragment area S",
                                                 "units": "length^2"}),
            "fragment_time": ("fragment", times[index], {"long_name": "snapshot time"}),
            "fragment_time_index": ("fragment", index,
                                    {"long_name": "index of the snapshot on dim time"}),
            "n_fragments": ("time", n_frag, {"long_name": "number of fragments"}),
            "mean_area": ("time", mean_area, {"long_name": "mean fragment area of this run",
                                              "units": "length^2"}),
            "paste_fraction": ("time", paste,
                               {"long_name": "fraction of mesh points with phi >= phi0"}),
            "n_alive": ("time", alive.sum(axis=1).astype(np.int64),
                        {"long_name": "particles not removed"}),
        },
        coords={"time": ("time", times, dict(run["time"].attrs))},
    )
    ds.attrs.update({
        "h": h,
        "box_length": length,
        "n_particles": int(run.sizes["particle"]),
        "phi0": phi0,
        "mesh_spacing_h": spacing_h,
        "mesh_spacing": spacing,
        "mesh_points_per_side": int(round(length / spacing)),
        "edge_depth": edge_depth(phi0, kernel, h),
        "first_removal_time": first_removal_time(run),
        "connectivity": 4,
    })
    return ds


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
    for key in ("git_commit", "start_time", "wall_time_s", "host", "scene_overrides",
                "version_craquelure"):
        if key in run.attrs:
            ds.attrs[f"run_{key}"] = run.attrs[key]
    ds.attrs["source_run"] = str(run_path)
    ds.attrs.update(provenance_attrs(scene, None if seed is None else int(seed), clock,
                                     effects=str(run.attrs.get("effects", "")).split(",")))
    ds.attrs["wall_time_s"] = float(clock.elapsed)
    return write_dataset(ds, out)
