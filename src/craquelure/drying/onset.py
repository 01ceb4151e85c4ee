r"""The onset in numbers (spec open doubt 7): kappa_max at a fixed drying stress against the
disorder of the initial particles.

Before any removal each particle's mean stress is :math:`\bar\sigma_I = \kappa_I F`
(:mod:`craquelure.drying.engine`), :math:`\kappa_I` coming from the SPH divergence of the
uniform drying stress on irregular particles. The study's runs (scene ``onset_fixed_f``) hold
:math:`F = \sigma_Y` with fracture off; per run (one point: a minimum gap of the random
placement in units of :math:`\Delta = L/\sqrt N`, a ratio :math:`h/\Delta`, i.e. N at fixed L
and h, and a mass solve)

- ``kappa_max``: max over live particles of :math:`\bar\sigma_I / F` at the last snapshot, with the
  initial-stress scale :math:`a\sigma_Y / F` (0.01 at F = sigma_Y) as its uncertainty;
- ``kappa_change``: its change from the previous snapshot (relaxation check: the values are
  read once the non-uniform stress has relaxed, rate :math:`(\lambda + 2\mu)/\eta`);
- ``predicted_first_removal_over_t_star`` :math:`= 1/\kappa_{max}` (source criterion).

The mass solve is what limits the disorder: below a minimum gap of 0.8 the truncated CG gives
negative masses (spec section 7) and the clamped CG is needed; a larger :math:`h/\Delta`
smooths the SPH sums and with it the stress peaks."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import xarray as xr

from craquelure.drying.analysis import run_scene


def kappa_point(run: xr.Dataset) -> dict[str, float | str]:
    """kappa_max of one fixed-F run (module docstring) and the point it stands for."""
    scene = run_scene(run)
    cap = float(scene.get("material.drying_stress_cap"))
    rate = float(scene.get("material.drying_rate"))
    times = run["time"].values.astype(float)
    force = np.minimum(rate * times, cap)
    alive = run["alive"].values.astype(bool)
    stress = np.where(alive, run["mean_stress"].values, -np.inf)
    kappa = stress.max(axis=1) / force
    length, n = float(scene.get("domain.box_length")), int(scene.get("particles.n"))
    sigma_y = float(scene.get("material.yield_stress"))
    amplitude = float(scene.get("material.initial_stress_amplitude"))
    return {
        "min_gap": float(scene.get("particles.rsa_min_separation")),
        "h_over_spacing": float(scene.get("numerics.h")) / (length / np.sqrt(n)), "n_particles": n,
        "mass_solve": str(scene.get("numerics.mass_solve")["method"]),
        "seed": int(run.attrs.get("seed", -1)), "drying_stress": float(force[-1]),
        "kappa_max": float(kappa[-1]),
        "kappa_change": float(kappa[-1] - kappa[-2]) if kappa.size > 1 else float("nan"),
        "kappa_initial_stress_bound": amplitude * sigma_y / float(force[-1]),
        "predicted_first_removal_over_t_star": float(1.0 / kappa[-1]),
    }


def kappa_study(runs: Sequence[xr.Dataset], labels: Sequence[str]) -> xr.Dataset:
    """One dataset (dim ``point``) of :func:`kappa_point` over the study's runs."""
    rows = [kappa_point(run) for run in runs]
    names = {  # long name, units
        "kappa_max": ("max_I sigma_bar_I / F at fixed F, fracture off", "1"),
        "kappa_change": ("change of kappa_max since the previous snapshot", "1"),
        "kappa_initial_stress_bound": ("largest shift of kappa by the initial stress, a "
                                       "sigma_Y/F", "1"),
        "predicted_first_removal_over_t_star": ("predicted first removal 1/kappa_max in t*", "1"),
        "min_gap": ("minimum gap of the random placement", "L/sqrt(N)"),
        "h_over_spacing": ("kernel support over the mean spacing h/Delta", "1"),
        "drying_stress": ("drying stress F held", "lambda"), "n_particles": ("particles N", "1"),
        "seed": ("seed", "1"),
    }
    data = {key: ("point", np.array([r[key] for r in rows]), {"long_name": name, "units": units})
            for key, (name, units) in names.items()}
    data["mass_solve"] = ("point", np.array([r["mass_solve"] for r in rows]),
                          {"long_name": "mass solve of the initial state"})
    ds = xr.Dataset(data, coords={"point": ("point", list(labels))})
    ds.attrs.update({"box_length": float(run_scene(runs[0]).get("domain.box_length")),
                     "scene_name": str(runs[0].attrs.get("scene_name", ""))})
    return ds
