"""CF-1.11 metadata for every dataset, applied in one place (:func:`craquelure.io.write_dataset`
calls :func:`apply`), so a model's writer only says what its variables are.

Global attributes: ``Conventions``, ``title``, ``source``, ``history`` (UTC time and command
line, one line per write, appended), ``references`` (the model's source papers) and, for
models in reduced units, ``reduced_unit_system`` (what the unit of each quantity is).

Variables: every variable gets ``long_name`` and ``units`` that UDUNITS parses. A model in
reduced units (drying, lattice, softdyn) writes its quantities as multiples of the model's own
scales; those get ``units = "1"`` and the scale in ``reduced_units`` (e.g. ``"eta/lambda"`` for a
drying time, ``"R/tau"`` for a Soft Dynamics velocity). Wall times (``"s"``), angles
(``"degree"``) and true ratios (``"1"``) keep their units. Impact is in SI per unit thickness
(2D): masses kg/m, energies J/m, forces N/m; a 3D impact dataset (attribute ``dim`` = 3) takes
the whole-body units instead (kg, J, N; :func:`per_body`).

A model writer's own ``long_name``/``units`` attributes win over the table below, which fills
in the variables a writer leaves bare. Strings (labels) get a long name but no units.
"""

from __future__ import annotations

import shlex
import sys
from dataclasses import dataclass, field
from datetime import UTC, datetime
from pathlib import Path

import xarray as xr

import craquelure

CONVENTIONS = "CF-1.11"
# Units kept as they are in reduced-unit models: they are physical (wall time, angles) or a
# true ratio.
PHYSICAL_UNITS = {"1", "s", "degree"}
UNIT_ALIASES = {"deg": "degree", "N/m": "N m-1"}


@dataclass(frozen=True)
class ModelMetadata:
    title: str
    references: str
    reduced_unit_system: str | None = None  # None: SI
    variables: dict[str, tuple[str, str | None]] = field(default_factory=dict)


# per unit thickness (2D) -> whole body (3D)
_BODY_UNITS = {"kg m-1": "kg", "J m-1": "J", "N m-1": "N", "kg s-1": "kg m s-1",
               "N s m-1": "N s"}


def per_body(variables: dict[str, tuple[str, str | None]]) -> dict[str, tuple[str, str | None]]:
    """A 2D per-thickness table as the 3D one: "per unit thickness" dropped from the long
    names, units multiplied by a length (kg m-1 -> kg, J m-1 -> J, N m-1 -> N, ...)."""
    return {name: (long_name.replace(" per unit thickness", ""),
                   _BODY_UNITS.get(units, units))
            for name, (long_name, units) in variables.items()}


_TIME_DRYING = "eta/lambda"
_LENGTH_DRYING = "eta/sqrt(rho0 lambda)"
_AREA_DRYING = "(eta/sqrt(rho0 lambda))^2"

DRYING = ModelMetadata(
    title="Drying paste: 2D SPH of a thin visco-elastic layer under a drying stress, cracks by "
          "particle removal",
    references="the drying-paste SPH paper, arXiv:1209.6114 (equations reconstructed in the "
               "project spec ../shared/spec/drying.md)",
    reduced_unit_system="nondimensionalised by rho0, lambda and eta (drying spec section 1): "
                        f"stress lambda, time {_TIME_DRYING}, length {_LENGTH_DRYING} "
                        "(written 'length'), velocity sqrt(lambda/rho0), density rho0",
    variables={
        # campaign / fragments / thickness / accuracy datasets
        "time": ("snapshot time", _TIME_DRYING),
        "step_time": ("time-series sample time", _TIME_DRYING),
        "mass": ("particle mass", "rho0 length^2"),
        "seed": ("random seed of the sample", "1"),
        "bin": ("histogram bin index", "1"),
        "area_lo": ("lower edge of the fragment-area bin", _AREA_DRYING),
        "area_hi": ("upper edge of the fragment-area bin", _AREA_DRYING),
        "x_lo": ("lower edge of the scaled-area bin X = S/<S>_t", "1"),
        "x_hi": ("upper edge of the scaled-area bin X = S/<S>_t", "1"),
        "n_fragments": ("number of fragments", "1"),
        "total_area": ("total fragment area of the sample", _AREA_DRYING),
        "sample_mean_area": ("mean fragment area of the sample", _AREA_DRYING),
        "paste_fraction": ("fraction of paste mesh points", "1"),
        "first_removal_time": ("time of the first particle removal", _TIME_DRYING),
        "mean_area": ("mean fragment area <S>_t", _AREA_DRYING),
        "mean_area_se": ("standard error of <S>_t over seeds", _AREA_DRYING),
        "inverse_mean_area": ("1/<S>_t", "(eta/sqrt(rho0 lambda))^-2"),
        "inverse_mean_area_se": ("standard error of 1/<S>_t", "(eta/sqrt(rho0 lambda))^-2"),
        "n_fragments_mean": ("mean number of fragments per sample", "1"),
        "n_fragments_se": ("standard error of the number of fragments", "1"),
        "unbroken_fraction": ("fraction of samples still one fragment", "1"),
        "size_density": ("P(S;t), pooled over seeds", "(eta/sqrt(rho0 lambda))^-2"),
        "size_in_range_fraction": ("fraction of fragments with S <= S_max", "1"),
        "scaled_density": ("scaled distribution <S>_t P(X <S>_t; t)", "1"),
        "fragment_area": ("fragment area S", _AREA_DRYING),
        "fragment_scaled_area": ("X = S/<S>_t", "1"),
        "fragment_time": ("snapshot time of the fragment", _TIME_DRYING),
        "fragment_time_index": ("index of the snapshot on dim time", "1"),
        "fragment_seed": ("random seed of the fragment's sample", "1"),
        "n_alive": ("particles not removed", "1"),
        "integrator": ("time integrator", None),
        "dt": ("time step", _TIME_DRYING),
        "dt_pair": ("index of the pair of consecutive time steps", "1"),
        "thickness": ("layer thickness H", _LENGTH_DRYING),
        "alive_now": ("1 if the particle is present at the checkpoint", "1"),
        "n_seeds": ("seeds per thickness", "1"),
        "all_broken": ("1 if every sample has >= 2 fragments", "1"),
        "usable": ("1 if every thickness has every sample broken", "1"),
        "exponent": ("beta_t: slope of log <S> against log H", "1"),
        "late": ("1 if usable and in the last third of the run", "1"),
        # drying-speed study (craquelure.drying.speed): times in units of t*, slopes of b*
        "speed": ("Pi = tau/t*, tau = eta/(2 mu)", "1"),
        "fixed_time": ("t/t*", "1"),
        "t_star": ("t* = sigma_Y/v_r", _TIME_DRYING),
        "drying_rate": ("drying rate v_r", "lambda^2/eta"),
        **{f"{base}{end}": (f"{base.replace('_', ' ')}, in t*", "1")
           for base in ("first_removal_earliest", "first_removal_median", "first_sample_broken",
                        "half_samples_broken", "all_samples_broken", "t0_over_t_star")
           for end in ("", "_lo", "_hi")},
        **{f"b_over_b_star{end}": ("slope b of 1/<S>_t, in b*", "1") for end in ("", "_lo", "_hi")},
    },
)

# Impact: the spec's SI units, 2D per unit out-of-plane thickness.
IMPACT = ModelMetadata(
    title="Concrete impact: 2D SPH concrete disc with random particle masses hitting a rigid "
          "base",
    references="M. Husek, F. Hokes, J. Kala, P. Kral, Inclusion of Randomness into SPH "
               "Simulations, WSEAS Transactions; J. Kala, M. Husek, Effect of the support "
               "domain size in SPH fracture simulations, Shock Vib. 2016; project spec "
               "../shared/spec/impact.md",
    variables={
        "time": ("simulated time", "s"),
        "snapshot_time": ("simulated time of the snapshot", "s"),
        "x0": ("initial position x", "m"),
        "y0": ("initial position y", "m"),
        "z0": ("initial position z along the disc axis (3D)", "m"),
        "z": ("final position z (3D)", "m"),
        "vz": ("final velocity z (3D)", "m s-1"),
        "mass": ("particle mass per unit thickness", "kg m-1"),
        "precrack": ("1 if the particle is on a pre-crack", "1"),
        "x": ("final position x", "m"),
        "y": ("final position y", "m"),
        "vx": ("final velocity x", "m s-1"),
        "vy": ("final velocity y", "m s-1"),
        "damage": ("final damage D", "1"),
        "softening": ("final softening s = (kappa - kappa0)/(kappa_f - kappa0)", "1"),
        "plastic_strain": ("final equivalent plastic strain", "1"),
        "plastic_compaction": ("final plastic volumetric compaction on the cap", "1"),
        "h": ("final smoothing length", "m"),
        "rho": ("final density", "kg m-3"),
        "series_contact_force_penalty": ("base contact force per unit thickness (penalty "
                                         "force at the sample time)", "N m-1"),
        "series_kinetic": ("kinetic energy per unit thickness", "J m-1"),
        "series_internal": ("internal energy per unit thickness", "J m-1"),
        "series_elastic": ("elastic strain energy per unit thickness", "J m-1"),
        "series_plastic": ("plastic work per unit thickness", "J m-1"),
        "series_damage": ("energy dissipated by damage per unit thickness", "J m-1"),
        "series_viscous": ("energy dissipated by artificial viscosity per unit thickness",
                           "J m-1"),
        "series_artificial_stress": ("energy of the artificial stress per unit thickness",
                                     "J m-1"),
        "series_penalty": ("energy stored in the contact penalty per unit thickness", "J m-1"),
        "series_kinematic_removed": ("energy removed by the kinematic contact constraint per "
                                     "unit thickness", "J m-1"),
        "series_balance_error": ("relative energy balance error (E(t) - E0)/E0", "1"),
        "series_momentum_y": ("total momentum y per unit thickness", "kg s-1"),
        "series_vcm_y": ("centre-of-mass velocity y", "m s-1"),
        "series_cracked_fraction": ("fraction of cracked particles", "1"),
        "series_impulse": ("impulse transmitted to the base per unit thickness", "N s m-1"),
        "snap_x": ("position x", "m"),
        "snap_y": ("position y", "m"),
        "snap_damage": ("damage D", "1"),
        "snap_softening": ("softening s = (kappa - kappa0)/(kappa_f - kappa0)", "1"),
        "snap_plastic_strain": ("equivalent plastic strain", "1"),
    },
)

_LENGTH_LATTICE = "L"
_TIME_LATTICE = "L sqrt(rho/E_b)"
_ENERGY_LATTICE = "E_b L^2"

LATTICE = ModelMetadata(
    title="Beam-lattice fracture and flow (NUMFRAC style): discs bonded by breakable beams",
    references="J. A. Astrom et al., A particle based simulation model for glacier dynamics, "
               "The Cryosphere 7, 1591-1602 (2013); NUMFRAC PRACE white paper; project spec "
               "../shared/spec/lattice.md",
    reduced_unit_system="natural units of the lattice (lattice spec section 1): length L "
                        "(lattice spacing) = 1, disc density rho = 1, beam modulus E_b (k_n) = "
                        f"1; time {_TIME_LATTICE}, energy {_ENERGY_LATTICE} per unit "
                        "thickness, force E_b L",
    variables={
        "time": ("time of the energy sample", _TIME_LATTICE),
        "frame_time": ("time of the frame", _TIME_LATTICE),
        "kinetic": ("translational kinetic energy", _ENERGY_LATTICE),
        "rotational": ("rotational kinetic energy", _ENERGY_LATTICE),
        "elastic": ("elastic energy of the intact beams", _ENERGY_LATTICE),
        "contact": ("elastic energy of the contacts", _ENERGY_LATTICE),
        "external": ("potential energy of the external fields (gravity, buoyancy, bed)",
                     _ENERGY_LATTICE),
        "work": ("work done on the lattice by supports and drives", _ENERGY_LATTICE),
        "damping": ("energy dissipated by damping and friction", _ENERGY_LATTICE),
        "fracture": ("elastic energy released by broken beams", _ENERGY_LATTICE),
        "melting": ("energy removed with melted beams", _ENERGY_LATTICE),
        "total": ("energy balance: kinetic + potential - work + losses", _ENERGY_LATTICE),
        "broken": ("beams broken so far", "1"),
        "melted": ("beams melted so far", "1"),
        "load_ux": ("mean displacement x of the loaded particles", _LENGTH_LATTICE),
        "load_uy": ("mean displacement y of the loaded particles", _LENGTH_LATTICE),
        "drive_fx": ("force x exerted by the drive", "E_b L"),
        "drive_fy": ("force y exerted by the drive", "E_b L"),
        "x": ("position x", _LENGTH_LATTICE),
        "y": ("position y", _LENGTH_LATTICE),
        "theta": ("rotation of the particle", "rad"),
        "mass": ("particle mass", "rho L^2"),
        "body": ("label of the body the particle belongs to", "1"),
        "row": ("row of the particle in the lattice", "1"),
        "col": ("column of the particle in the lattice", "1"),
        "bond_i": ("index of the first particle of the beam", "1"),
        "bond_j": ("index of the second particle of the beam", "1"),
        "bond_state": ("beam state: 1 intact, 0 broken (other values: see the engine)", "1"),
        "bond_break_time": ("time the beam broke (NaN: never)", _TIME_LATTICE),
        "bond_unbreakable": ("1 if the beam can never break", "1"),
    },
)

SOFTDYN = ModelMetadata(
    title="Soft Dynamics: elastic spheres in a viscous fluid (normal approach, T1 "
          "rearrangement)",
    references="P. Rognon, C. Gay, Soft Dynamics simulation: 1. Normal approach of two "
               "deformable particles in a viscous fluid and optimal-approach strategy, Eur. "
               "Phys. J. E 27, 253 (2008), arXiv:0803.1573; 2. Elastic spheres undergoing a T1 "
               "process in a viscous fluid, arXiv:0901.0171 (2009); project spec "
               "../shared/spec/softdyn.md",
    reduced_unit_system="softdyn spec section 1: length R (sphere radius), force F_v (the "
                        "tension driving the T1), time tau = eta R^2/F_v (Stokes time); E R^2 "
                        "and eta R are the elastic and viscous scales",
    variables={
        "time": ("time", "tau"),
        "position": ("centre position", "R"),
        "velocity": ("centre velocity", "R/tau"),
        "load": ("applied force", "F_v"),
        "gap": ("surface-to-surface gap h", "R"),
        "interaction_radius": ("radius a of the interaction region", "R"),
        "force_tangential": ("tangential pair force |f_t|", "F_v"),
        "zeta_n": ("normal lubrication friction coefficient", "eta R"),
        "zeta_t": ("tangential lubrication friction coefficient", "eta R"),
        "particle": ("sphere label", None),
        "pair": ("pair label", None),
        "dim": ("Cartesian component", None),
        "point": ("grid point of the sweep", "1"),
        "h0": ("initial gap h0", "R"),
        "force": ("reduced force F~", "1"),
        "h_star": ("Hertz gap h* = R (F~/k_n)^(2/3)", "R"),
        "duration": ("T1 duration (CD force reaches phi F_v)", "tau"),
        "finished": ("1 if the T1 ended before outputs.t_end", "1"),
        "computed": ("1 if the point is inside study.window and was run", "1"),
        "theta_end": ("angle AC-AB at the end", "degree"),
        "T_P": ("Poiseuille prediction c_n ln(R/h0) (Eq. 33)", "tau"),
        "T_H": ("Hertz prediction (c_n/2)(h*/h0)^2 (Eq. 34)", "tau"),
        "T_sep": ("quadrature of the AB opening time (section 7)", "tau"),
        "h0_over_h_star": ("h0/h*, h* = R (F~/k_n)^(2/3)", "1"),
        "regime": ("hertz (h0/h* <= 1/3), poiseuille (>= 3) or crossover", None),
        "n_rhs": ("right-hand-side evaluations", "1"),
        "n_steps": ("time steps", "1"),
        "run_wall_time_s": ("wall time of the run", "s"),
        "integrator": ("time integrator", None),
        "rtol": ("relative tolerance of the adaptive integrator", "1"),
        "dt": ("fixed time step", "tau"),
        "theta": ("angle between AC and AB", "degree"),
        # accuracy study: adaptive integrators (integrator, rtol) and fixed-step Heun (dt)
        "adaptive_duration": ("T1 duration, adaptive integrator", "tau"),
        "adaptive_n_rhs": ("right-hand-side evaluations, adaptive integrator", "1"),
        "adaptive_wall_time_s": ("wall time, adaptive integrator", "s"),
        "heun_duration": ("T1 duration, fixed-step Heun", "tau"),
        "heun_n_rhs": ("right-hand-side evaluations, fixed-step Heun", "1"),
        "heun_wall_time_s": ("wall time, fixed-step Heun", "s"),
        "heun_stable": ("1 if the fixed-step Heun run stayed stable", "1"),
        # T1 occurrence scan (fh_over_fv, force)
        "fh_over_fv": ("load ratio F_h/F_v", "1"),
        "occurred": ("1 if theta reached theta_end before t_end", "1"),
        "predicted": ("1 if F_h < F_v/sqrt3 (AB in tension, Eq. 27)", "1"),
        "f_ab_end": ("normal force of pair AB at the end", "F_v"),
        "f_v": ("vertical load F_v", "E R^2"),
        "f_h": ("horizontal load F_h", "E R^2"),
        "tau": ("Stokes time tau = eta R^2/F_v", "eta/E"),
    },
)

MODELS = {"drying": DRYING, "impact": IMPACT, "lattice": LATTICE, "softdyn": SOFTDYN}


def command_line(argv: list[str] | None = None) -> str:
    """The command that is writing, as a user would type it (``python -m craquelure ...``
    shows as ``craquelure ...``)."""
    argv = list(sys.argv if argv is None else argv)
    if not argv:
        return "python"
    first = Path(argv[0])
    if first.name == "__main__.py" and first.parent.name == "craquelure":
        argv[0] = "craquelure"
    return shlex.join(argv)


def history_line(argv: list[str] | None = None) -> str:
    stamp = datetime.now(UTC).isoformat(timespec="seconds").replace("+00:00", "Z")
    return f"{stamp} {command_line(argv)}"


def _units(model: ModelMetadata, units: str) -> tuple[str, str | None]:
    """(UDUNITS units, reduced scale or None) for a unit string as the model writes it."""
    units = UNIT_ALIASES.get(units, units)
    if model.reduced_unit_system is None or units in PHYSICAL_UNITS or units == "rad":
        return units, None
    return "1", units


def apply(ds: xr.Dataset, argv: list[str] | None = None) -> xr.Dataset:
    """Add the CF attributes to ``ds`` in place (see the module docstring) and return it.
    Datasets without a known ``model`` attribute get the global attributes only."""
    meta = MODELS.get(str(ds.attrs.get("model", "")))
    attrs = ds.attrs
    attrs["Conventions"] = CONVENTIONS
    line = history_line(argv)
    attrs["history"] = f"{attrs['history']}\n{line}" if attrs.get("history") else line
    parts = [f"craquelure {craquelure.__version__}"]
    if meta is not None:
        parts.append(f"{ds.attrs['model']} model")
    if ds.attrs.get("scene_name"):
        parts.append(f"scene {ds.attrs['scene_name']}")
    attrs["source"] = ", ".join(parts)
    if meta is None:
        attrs.setdefault("title", "craquelure dataset")
        return ds
    if not attrs.get("title"):
        what = f", scene {attrs['scene_name']}" if attrs.get("scene_name") else ""
        seed = f", seed {attrs['seed']}" if "seed" in attrs else ""
        attrs["title"] = f"{meta.title}{what}{seed}"
    attrs["references"] = meta.references
    if meta.reduced_unit_system:
        attrs["reduced_unit_system"] = meta.reduced_unit_system
    # 3D datasets of a per-thickness model: per_body names and units
    table = per_body(meta.variables) if attrs.get("dim") == 3 else meta.variables
    for name, var in ds.variables.items():
        long_name, units = table.get(str(name), (None, None))
        if long_name and not var.attrs.get("long_name"):
            var.attrs["long_name"] = long_name
        if var.dtype.kind not in "fiub":
            continue  # labels: no units
        units = var.attrs.get("units", units)
        if units is None:
            continue
        udunits, reduced = _units(meta, str(units))
        var.attrs["units"] = udunits
        if reduced is not None:
            var.attrs["reduced_units"] = reduced
    return ds
