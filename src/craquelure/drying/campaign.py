r"""The campaign aggregate of per-seed fragment datasets over seeds (stage 2 of
:mod:`craquelure.drying.analysis`; drying spec section 10).

**Campaign.** Dims: ``seed`` (independent samples), ``time`` (snapshot times, the same in every
sample), ``bin`` (histogram bins), and ``fragment`` (all fragments of all samples and times, with
``fragment_seed`` / ``fragment_time``: ragged data stored flat).

- Pooled mean [D, spec]: :math:`\langle S\rangle_t = \sum_s A_{s,t} / \sum_s n_{s,t}`, with
  :math:`A_{s,t}` the total fragment area and :math:`n_{s,t}` the number of fragments of sample s
  at time t.
- Its standard error over seeds is the ratio-estimator (delta-method) one,
  :math:`\mathrm{SE}^2 = \sum_s (A_{s,t} - \langle S\rangle_t n_{s,t})^2 /
  (N_s (N_s - 1)\, \bar n_t^2)` [D]; :math:`\mathrm{SE}(1/\langle S\rangle) =
  \mathrm{SE}/\langle S\rangle^2`.
- :math:`P(S;t)`: density of the pooled sizes at time t on common linear bins
  :math:`[0, S_{max}]`, normalised by the number of all fragments at t (so it integrates to
  the fraction inside the bins). :math:`S_{max}` is the largest fragment in the statistics
  window (:func:`campaign_window`) [D: the early one-fragment samples, S = L^2, would
  otherwise squeeze every later histogram into the first bin].
- Scaled distribution (30, 31): :math:`X = S/\langle S\rangle_t`,
  :math:`\tilde P(X) = \langle S\rangle_t P(X \langle S\rangle_t; t)`, i.e. the density of X,
  on common bins :math:`[0, X_{max}]` (largest X in the window)."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np
import xarray as xr

from craquelure.drying.analysis import run_scene
from craquelure.drying.time_scales import campaign_window, t_star
from craquelure.errors import CraquelureError
from craquelure.io import read_dataset, write_dataset
from craquelure.provenance import WallClock, provenance_attrs

DEFAULT_BINS = 30
# Fragment labellings of the per-seed datasets: fragment areas, their snapshot index and the
# count per snapshot. "periodic": the torus (the spec's); "open": the image as a plain
# rectangle, whose edges cut fragments (what clustering a snapshot without wrap-around gives).
LABELLINGS = {
    "periodic": ("fragment_area", "fragment_time_index", "n_fragments"),
    "open": ("fragment_area_open", "fragment_time_index_open", "n_fragments_open"),
}
SCENE_NUMBERS = {  # campaign attribute -> scene path
    **{key: f"material.{key}" for key in ("yield_stress", "drying_rate", "thickness",
                                          "lame_lambda", "lame_mu")},
    "viscosity": "material.eta", "rho0": "material.rho0", "n_particles": "particles.n",
}


def pooled_mean(total_area: np.ndarray, count: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Pooled mean area over the seed axis (axis 0) and its ratio-estimator standard error."""
    total_area = np.asarray(total_area, float)
    count = np.asarray(count, float)
    n_s = total_area.shape[0]
    with np.errstate(invalid="ignore", divide="ignore"):
        mean = total_area.sum(axis=0) / count.sum(axis=0)
        resid = total_area - mean * count
        nbar = count.mean(axis=0)
        se = (np.sqrt((resid**2).sum(axis=0) / (n_s * (n_s - 1))) / nbar if n_s > 1
              else np.full_like(mean, np.nan))
    return mean, se


def _density(values: np.ndarray, edges: np.ndarray) -> np.ndarray:
    if values.size == 0:
        return np.full(edges.size - 1, np.nan)
    counts, _ = np.histogram(values, bins=edges)
    return counts / (values.size * np.diff(edges))


def build_campaign(fragments: Sequence[xr.Dataset], n_bins: int = DEFAULT_BINS,
                   window_mode: str = "paper", labelling: str = "periodic") -> xr.Dataset:
    """Aggregate per-seed fragment datasets (same scene and snapshot times) over seeds;
    ``window_mode`` (:data:`~craquelure.drying.time_scales.WINDOW_MODES`) fixes the statistics
    window, ``labelling`` (:data:`LABELLINGS`) which fragments are counted; both are recorded
    in the attributes."""
    if not fragments:
        raise CraquelureError("campaign: no fragment datasets given")
    if labelling not in LABELLINGS:
        raise CraquelureError(f"campaign: labelling {labelling!r} is not allowed; one of "
                              f"{', '.join(LABELLINGS)}")
    area_key, index_key, count_key = LABELLINGS[labelling]
    first = fragments[0]
    times = first["time"].values
    seeds = []
    for ds in fragments:
        if "seed" not in ds.attrs:
            raise CraquelureError("campaign: a fragment dataset has no `seed` attribute")
        seeds.append(int(ds.attrs["seed"]))
        if ds["time"].size != times.size or not np.allclose(ds["time"].values, times):
            raise CraquelureError(f"campaign: seed {seeds[-1]} has other snapshot times than "
                                  f"seed {seeds[0]}")
        for key in ("scene", "phi0", "mesh_spacing"):
            if ds.attrs.get(key) != first.attrs.get(key):
                raise CraquelureError(f"campaign: seed {seeds[-1]} differs from seed "
                                      f"{seeds[0]} in `{key}`; aggregate one scene at a time")
    if len(set(seeds)) != len(seeds):
        raise CraquelureError(f"campaign: repeated seeds {sorted(seeds)}")
    fragments, seeds = sorted(fragments, key=lambda ds: int(ds.attrs["seed"])), sorted(seeds)
    n_s, n_t = len(seeds), times.size

    count = np.stack([ds[count_key].values for ds in fragments]).astype(np.int64)
    area = np.concatenate([ds[area_key].values for ds in fragments])
    f_time_index = np.concatenate([ds[index_key].values.astype(np.int64) for ds in fragments])
    f_seed = np.repeat(np.asarray(seeds, np.int64), [ds[area_key].size for ds in fragments])
    total, _ = _totals(area, np.searchsorted(seeds, f_seed), f_time_index, n_s, n_t)
    mean, se = pooled_mean(total, count)
    with np.errstate(invalid="ignore", divide="ignore"):
        sample_mean = np.where(count > 0, total / np.maximum(count, 1), np.nan)
        x_all = area / mean[f_time_index]

    scene = run_scene(first)
    tstar = t_star(scene)
    win = campaign_window(times, count, tstar, window_mode)
    ref = win["mask"][f_time_index]
    if not ref.any():
        ref = np.ones(area.size, bool)
    s_max = float(area[ref].max()) if area.size else 1.0
    x_max = float(np.nanmax(x_all[ref])) if area.size else 1.0
    s_edges, x_edges = (np.linspace(0.0, top, n_bins + 1) for top in (s_max, x_max))
    at_time = [f_time_index == k for k in range(n_t)]
    size_density = np.reshape([_density(area[sel], s_edges) for sel in at_time], (n_t, n_bins))
    scaled_density = np.reshape([_density(x_all[sel], x_edges) for sel in at_time], (n_t, n_bins))
    in_range = np.array([np.mean(area[sel] <= s_max) if sel.any() else np.nan for sel in at_time])
    # bare variables get their long names and units from craquelure.cf's table on writing
    ds = xr.Dataset(
        {
            "n_fragments": (("seed", "time"), count, {"long_name": "fragments per sample"}),
            "total_area": (("seed", "time"), total),
            "sample_mean_area": (("seed", "time"), sample_mean),
            "paste_fraction": (("seed", "time"),
                               np.stack([d["paste_fraction"].values for d in fragments])),
            **{key: ("seed", np.array([float(d.attrs.get(key, np.nan)) for d in fragments]))
               for key in ("first_removal_time", "kappa_max", "kappa_criterion",
                           "predicted_first_removal_time")},
            # fragment datasets older than the measures: NaN
            **{key: (("seed", "time"), np.stack([d[key].values.astype(float) if key in d
                                                 else np.full(n_t, np.nan) for d in fragments]))
               for key in ("damage", "crack_length_per_area", "largest_fragment_fraction",
                           "n_fragments_open")},
            "mean_area": ("time", mean, {"long_name": "pooled mean fragment area <S>_t"}),
            "mean_area_se": ("time", se),
            "inverse_mean_area": ("time", 1.0 / mean),
            "inverse_mean_area_se": ("time", se / mean**2),
            "n_fragments_mean": ("time", count.mean(axis=0)),
            "n_fragments_se": ("time", count.std(axis=0, ddof=1) / np.sqrt(n_s)
                               if n_s > 1 else np.full(n_t, np.nan)),
            "unbroken_fraction": ("time", (count <= 1).mean(axis=0)),
            "size_density": (("time", "bin"), size_density),
            "size_in_range_fraction": ("time", in_range),
            "scaled_density": (("time", "bin"), scaled_density),
            "fragment_area": ("fragment", area),
            "fragment_scaled_area": ("fragment", x_all),
            "fragment_time": ("fragment", times[f_time_index]),
            "fragment_time_index": ("fragment", f_time_index),
            "fragment_seed": ("fragment", f_seed),
        },
        coords={
            "seed": ("seed", np.asarray(seeds, np.int64)),
            "time": ("time", times),
            "bin": ("bin", np.arange(n_bins)),
            "area_lo": ("bin", s_edges[:-1]),
            "area_hi": ("bin", s_edges[1:]),
            "x_lo": ("bin", x_edges[:-1]),
            "x_hi": ("bin", x_edges[1:]),
        },
    )
    ds.attrs.update({key: first.attrs[key] for key in
                     ("h", "box_length", "phi0", "mesh_spacing", "mesh_spacing_h", "edge_depth")
                     if key in first.attrs})
    for key, path in SCENE_NUMBERS.items():
        value = scene.optional(path)
        if value is not None:  # recorded when the scene sets it
            ds.attrs[key] = value
    ds.attrs["fracture_stress_measure"] = str(scene.get("material.fracture_stress_measure"))
    ds.attrs.update({"scene_name": str(first.attrs.get("scene_name", scene.name)),
                     "n_seeds": n_s, "seeds": ",".join(map(str, seeds)), "t_star": tstar,
                     "labelling": labelling, "window_mode": window_mode,
                     "window_start": win["start"], "window_end": win["end"]})
    return ds


def campaign_from_files(paths: Sequence[str | Path], out: str | Path, n_bins: int = DEFAULT_BINS,
                        window_mode: str = "paper", labelling: str = "periodic") -> Path:
    clock = WallClock()
    variables = (*LABELLINGS.get(labelling, LABELLINGS["periodic"]), "time")
    fragments = [read_dataset(p, "fragment dataset", model="drying", variables=variables)
                 for p in paths]
    ds = build_campaign(fragments, n_bins, window_mode, labelling)
    ds.attrs.update(provenance_attrs(run_scene(fragments[0]), None, clock,
                                     effects=str(fragments[0].attrs.get("effects", ""))
                                     .split(",")))
    ds.attrs["sources"] = ",".join(str(p) for p in paths)
    return write_dataset(ds, out)


def _totals(area: np.ndarray, seed_index: np.ndarray, time_index: np.ndarray, n_s: int,
            n_t: int) -> tuple[np.ndarray, np.ndarray]:
    """Total area and fragment count per (seed, time) of fragments given by their indices."""
    flat = seed_index * n_t + time_index
    total = np.bincount(flat, weights=area, minlength=n_s * n_t)
    count = np.bincount(flat, minlength=n_s * n_t)
    return total.reshape(n_s, n_t), count.reshape(n_s, n_t).astype(float)


def per_sample_totals(campaign: xr.Dataset, s_min: float = 0.0
                       ) -> tuple[np.ndarray, np.ndarray]:
    """Total area and fragment count per (seed, time), fragments with S >= s_min only."""
    seeds = campaign["seed"].values
    area = campaign["fragment_area"].values
    keep = area >= s_min
    return _totals(area[keep], np.searchsorted(seeds, campaign["fragment_seed"].values[keep]),
                   campaign["fragment_time_index"].values[keep], seeds.size,
                   campaign.sizes["time"])
