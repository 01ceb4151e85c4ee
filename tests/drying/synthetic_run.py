"""Synthetic datasets in the drying engine's formats, for the analysis tests.

``lattice_run``: a run dataset (dims ``time``, ``particle``, ``step_time``; variables ``x``,
``y``, ``vx``, ``vy``, ``alive``, ``mass``, ``rho``, ``mean_stress``; time series; attrs ``h``,
``box_length``, ``effects``, ``scene``, ``seed``) of particles on a square lattice with
particle-free bands removed. ``fragment_dataset``: a per-seed fragment dataset as written by
``craquelure fragments``, with fragment areas drawn from a prescribed law; ``campaign_of``: a
campaign of such datasets whose mean area follows a known law.
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from craquelure.drying.campaign import build_campaign
from craquelure.scene import load_scene

T_STAR = 5e-3 / 2.2e-4  # default scene: 22.7
TIMES = np.arange(9.0, 31.0)  # default profile snapshots; t* = 22.7, window [18, 30]


def lattice_scene(n_side: int, box_length: float, scene: str = "drying/ci",
                  extra: tuple[str, ...] = ()):
    return load_scene(scene, [f"domain.box_length={box_length}", f"particles.n={n_side**2}",
                              "particles.placement=square_lattice", *extra])


def band_mask(x: np.ndarray, y: np.ndarray, bands) -> np.ndarray:
    """True for particles inside any band (axis, lo, hi)."""
    out = np.zeros(x.size, bool)
    for axis, lo, hi in bands:
        c = x if axis == "x" else y
        out |= (c >= lo) & (c < hi)
    return out


def lattice_run(n_side: int = 40, box_length: float = 2.0, bands_per_time=((),),
                times=None, seed: int = 1, scene: str = "drying/ci") -> xr.Dataset:
    """Run dataset: lattice spacing L/n, V = spacing^2, bands_per_time[k] removed at time k."""
    sc = lattice_scene(n_side, box_length, scene)
    delta = box_length / n_side
    g = (np.arange(n_side) + 0.5) * delta
    gx, gy = np.meshgrid(g, g)
    x, y = gx.ravel(), gy.ravel()
    n = x.size
    n_t = len(bands_per_time)
    times = np.arange(1.0, n_t + 1) if times is None else np.asarray(times, float)
    alive = np.ones((n_t, n), np.int8)
    removed = np.zeros(n, bool)
    for k, bands in enumerate(bands_per_time):
        removed |= band_mask(x, y, bands)
        alive[k] = ~removed
    rng = np.random.default_rng(seed)
    stress = rng.uniform(0.0, 1.0, (n_t, n)) * sc.get("material.yield_stress")
    step_time = np.linspace(0.0, times[-1], 4 * n_t + 1)
    n_removed = np.interp(step_time, times, (alive == 0).sum(axis=1))
    zeros = np.zeros((n_t, n))
    return xr.Dataset(
        {
            "x": (("time", "particle"), np.tile(x, (n_t, 1))),
            "y": (("time", "particle"), np.tile(y, (n_t, 1))),
            "vx": (("time", "particle"), zeros),
            "vy": (("time", "particle"), zeros),
            "alive": (("time", "particle"), alive),
            "mass": (("time", "particle"), np.full((n_t, n), delta * delta)),
            "rho": (("time", "particle"), np.ones((n_t, n))),
            "mean_stress": (("time", "particle"), stress),
            "n_removed": ("step_time", np.floor(n_removed)),
            "kinetic_energy": ("step_time", np.zeros(step_time.size)),
            "elastic_energy": ("step_time", np.zeros(step_time.size)),
            "momentum_x": ("step_time", np.zeros(step_time.size)),
            "momentum_y": ("step_time", np.zeros(step_time.size)),
        },
        coords={"time": ("time", times), "step_time": ("step_time", step_time)},
        attrs={"h": sc.get("numerics.h"), "box_length": box_length, "n_particles": n,
               "effects": ",".join(sc.effects), "scene": sc.text, "scene_name": sc.name,
               "seed": seed, "finished": 1},
    )


def fragment_dataset(seed: int, times, mean_area, n_per_time, shape=2.0,
                     scene: str = "drying/default", first_removal: float = np.nan,
                     drying_rate: float = 2.2e-4) -> xr.Dataset:
    """Fragment dataset with gamma-distributed areas: at times[k], n_per_time[k] fragments of
    mean mean_area[k] and gamma shape ``shape`` (a number or one per time). The scene's drying
    rate is pinned (t* = 22.7 by default) so the synthetic laws do not follow profile edits."""
    sc = load_scene(scene, [f"material.drying_rate={drying_rate!r}"])
    rng = np.random.default_rng(seed)
    times = np.asarray(times, float)
    shapes = np.broadcast_to(np.asarray(shape, float), times.shape)
    areas, index = [], []
    for k in range(times.size):
        a = rng.gamma(shapes[k], mean_area[k] / shapes[k], int(n_per_time[k]))
        areas.append(a)
        index.append(np.full(a.size, k))
    area = np.concatenate(areas)
    index = np.concatenate(index).astype(np.int64)
    n = np.bincount(index, minlength=times.size)
    mean = np.array([a.mean() if a.size else np.nan for a in areas])
    return xr.Dataset(
        {
            "fragment_area": ("fragment", area),
            "fragment_time": ("fragment", times[index]),
            "fragment_time_index": ("fragment", index),
            "n_fragments": ("time", n),
            "mean_area": ("time", mean),
            "paste_fraction": ("time", np.full(times.size, 0.9)),
            "n_alive": ("time", np.full(times.size, sc.get("particles.n"))),
        },
        coords={"time": ("time", times)},
        attrs={"h": sc.get("numerics.h"), "box_length": sc.get("domain.box_length"),
               "n_particles": sc.get("particles.n"), "phi0": 0.8, "mesh_spacing": 0.002,
               "mesh_spacing_h": 0.01, "edge_depth": 0.0398, "first_removal_time": first_removal,
               "scene": sc.text, "scene_name": sc.name, "seed": seed,
               "effects": ",".join(sc.effects)},
    )


def campaign_of(b, t0, shape=2.0, n_seeds=30, window_mode="paper"):
    """A campaign whose 1/<S>_t = b (t - t0) and half of whose samples stay whole until t0 + 1."""
    mean = 1.0 / (b * np.maximum(TIMES - t0, 0.5))
    frags = []
    for s in range(n_seeds):
        n = np.maximum(1, np.round(16.0 / mean)).astype(int)  # box area 16 (L = 4)
        n[TIMES < t0 + 1] = 1 + (s % 2) * (n[TIMES < t0 + 1] - 1)  # half still unbroken
        frags.append(fragment_dataset(s + 1, TIMES, mean, n, shape=shape,
                                      first_removal=t0 - 1.0 + 0.1 * s))
    return build_campaign(frags, n_bins=20, window_mode=window_mode)
