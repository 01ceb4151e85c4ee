"""Model API of the concrete impact for the CLI: initial state, derived numbers, run.

``run`` writes one dataset per run: particle fields, field snapshots, time series, the resolved
numbers the run used and what only the running engine saw (attributes); no analysis
(:mod:`craquelure.impact.analysis`). The loop, checkpoints and ``--resume`` are the runner's
(:class:`ImpactRun`); ``init`` is not used: a run starts from the scene and seed.
"""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np
import xarray as xr

from craquelure import runner
from craquelure.errors import SceneError
from craquelure.impact.effects.artificial_stress import as_epsilon
from craquelure.impact.effects.contact_bulk import bulk_stiffness, half_cell_scale
from craquelure.impact.effects.contact_mass import DEFAULT_SCALE
from craquelure.impact.effects.damage import crack_band_width
from craquelure.impact.engine import Engine, Settings, State
from craquelure.impact.initial_state import Specimen, build_specimen, initial_smoothing_length
from craquelure.impact.material import MATERIAL_CONSTANTS, Concrete
from craquelure.provenance import WallClock, provenance_attrs
from craquelure.registry import scene_values
from craquelure.scene import Scene, load_scene_text
from craquelure.throughput import prediction_lines


def concrete(scene: Scene) -> Concrete:
    """The concrete of a scene: each constant from the scene when an effect that declares it is
    on, else its neutral value (the effect is compiled out; :mod:`craquelure.impact.effects`)."""
    values = scene_values("impact", scene, MATERIAL_CONSTANTS)
    band = scene.get("material.crack_band_width")
    if band is None:  # null: the spec's max(2 Delta, 5 h(0)/3)
        band = crack_band_width(scene.get("particles.spacing"), initial_smoothing_length(scene))
    mat = Concrete(**values, f_bc_ratio=scene.get("material.f_bc_ratio"), band=band,
                   gfc_ratio=scene.get("material.G_fc_ratio"))
    if scene.has("damage"):
        mat.validate()
    for name in ("compressive_damage", "rate_effects"):
        if scene.has(name) and not scene.has("cap_plasticity"):
            raise SceneError(f"effects: {name} acts on the cap model's surface and needs "
                             f"cap_plasticity in effects (it has: {', '.join(scene.effects)})")
    return mat


def material_model(scene: Scene) -> str:
    """The concrete model a run uses, for its dataset: 'cap' (CSCM-like), 'drucker_prager' or
    'elastic', with '+compressive_damage' / '+rate_effects' when those are on."""
    base = ("cap" if scene.has("cap_plasticity") else
            "drucker_prager" if scene.has("plasticity") else "elastic")
    extra = [e for e in ("compressive_damage", "rate_effects") if scene.has(e)]
    return "+".join([base, *extra])


def contact_scale(scene: Scene) -> float:
    """Penalty scale factor a of the run: the scene's number, or for ``auto`` the spec's 0.1
    with the mass-based formula and the half-cell stiffness with the bulk one
    (:func:`~craquelure.impact.effects.contact_bulk.half_cell_scale`); 0.1 without contact."""
    if not (scene.has("contact_bulk") or scene.has("contact_mass")):
        return DEFAULT_SCALE
    a = scene.get("numerics.contact_a")  # both contact effects require it
    if a != "auto":
        return float(a)
    if scene.has("contact_bulk"):
        return half_cell_scale(scene.get("material.bulk_modulus"),
                               scene.get("material.shear_modulus"),
                               scene.get("domain.plane") == "stress")
    return DEFAULT_SCALE


def settings(scene: Scene) -> Settings:
    g = scene.get
    return Settings(
        material=concrete(scene), rho0=g("material.rho0"), spacing=g("particles.spacing"),
        effects=scene.effects, base_y=g("domain.base_y"), contact_a=contact_scale(scene),
        as_epsilon=as_epsilon(g("numerics.as_epsilon"),
                              initial_smoothing_length(scene) / g("particles.spacing")),
        plane_stress=g("domain.plane") == "stress", dim=g("domain.dim"),
        **{key: g(f"numerics.{key}") for key in (
            "cfl", "dt_max", "av_alpha", "av_beta", "as_n", "h_min", "h_max", "contact_radius",
            "kinematic_ratio", "energy_runaway_factor", "neighbour_skin")})


PROBE_SCENE = """{model: impact, particles: {spacing: 0.004, diameter_cells: 4},
material: {rho0: 2400.0, bulk_modulus: 1.0, shear_modulus: 1.0}, outputs: {t_end: 1.0e-5},
effects: [elasticity]}"""


def probe_settings(**fields) -> Settings:
    """Settings of a probe that is not a scene (a strip, a pair): those of the smallest scene,
    :data:`PROBE_SCENE` (numerics: the schema's defaults), with ``fields`` replaced."""
    return dataclasses.replace(settings(load_scene_text(PROBE_SCENE, "probe")), **fields)


def initial_state(scene: Scene, specimen: Specimen) -> State:
    rings = specimen.vx is not None  # rings: each moves along x towards the other
    return State.grid(specimen.x, specimen.y, specimen.vx if rings else 0.0,
                      0.0 if rings else -scene.get("particles.impact_velocity"), specimen.mass,
                      scene.get("material.rho0"), initial_smoothing_length(scene), z=specimen.z)


def build_initial_state(scene: Scene, seed: int) -> xr.Dataset:
    sp = build_specimen(scene, seed)
    return xr.Dataset(
        {"x": ("particle", sp.x), "y": ("particle", sp.y), "mass": ("particle", sp.mass),
         "precrack": ("particle", sp.precrack.astype(np.int8))},
        attrs={"spacing": sp.spacing, "radius": sp.radius, "centre_y": sp.centre_y,
               **provenance_attrs(scene, seed, WallClock())})


def derived_numbers(scene: Scene) -> dict[str, object]:
    st = settings(scene)
    mat = st.material
    h0, dt = initial_step(scene, st)
    load = workload(scene)
    bulk = scene.has("contact_bulk")
    return {
        "particles": load["particles"],
        "E [Pa], nu": (mat.young, mat.poisson),
        "dimension": (f"2D plane {scene.get('domain.plane')}" if st.dim == 2 else
                      f"3D, {scene.get('particles.thickness_cells')} layers"),
        "c_p, c_s [m/s]": (st.wave_speed, math.sqrt(mat.shear / st.rho0)),
        "h(0) [m]": h0,
        "artificial stress eps_AS": st.as_epsilon if scene.has("artificial_stress") else None,
        "penalty scale a, k [N/m]": (
            (st.contact_a, bulk_stiffness(st.contact_a, mat.bulk, st.spacing, st.dim)) if bulk
            else (st.contact_a, "a m_i / dt^2") if scene.has("contact_mass") else None),
        "kinematic below m / m_bar": (4.0 * bulk_stiffness(st.contact_a, mat.bulk, st.spacing,
                                                           st.dim)
                                      * dt**2 / (st.rho0 * st.spacing**st.dim) if bulk else None),
        "Drucker-Prager alpha, k [Pa]": mat.dp if scene.has("plasticity") else None,
        "cap model alpha, lambda [Pa], beta [1/Pa], theta, e, X0, kappa0 [Pa]": (
            (mat.cap.alpha, mat.cap.lam, mat.cap.beta, mat.cap.theta, mat.cap.e, mat.cap.X0,
             mat.cap.kappa0)
            if scene.has("cap_plasticity") else None),
        "compressive damage eps_fc": mat.eps_fc if scene.has("compressive_damage") else None,
        "crack band width l_c [m]": mat.band,
        "eps_0, eps_f": (mat.eps_0, mat.eps_f),
        "Hillerborg length [m]": mat.hillerborg_length,
        "initial time step [s]": dt,
        "steps (approx.)": load["units"],
        **prediction_lines("impact", load),
    }


def workload(scene: Scene) -> dict[str, float]:
    """Steps (at the initial stable step), particles and listed neighbours of a run (within
    the list radius 2 h(0) plus the skin, :func:`listed_neighbours`), for the throughput model."""
    st = settings(scene)
    h0, dt = initial_step(scene, st)
    return {"units": math.ceil(scene.get("outputs.t_end") / dt),
            "particles": build_specimen(scene, 0).n,
            "neighbours": listed_neighbours((2.0 + st.neighbour_skin) * h0 / st.spacing,
                                            int(scene.get("domain.dim")))}


def listed_neighbours(radius_cells: float, dim: int) -> float:
    """Neighbours within ``radius_cells`` on a unit grid: the ball's area or volume - 1."""
    return (4.0 / 3.0 * math.pi * radius_cells**3 if dim == 3 else math.pi * radius_cells**2) - 1.0


def initial_step(scene: Scene, st: Settings) -> tuple[float, float]:
    """h(0) and the first stable step (engine docstring, item 7) of a scene."""
    h0 = initial_smoothing_length(scene)
    av = (st.av_alpha * st.wave_speed * 1.2) if scene.has("artificial_viscosity") else 0.0
    speed = scene.get("particles.rings.speed" if scene.get("particles.shape") == "rings"
                      else "particles.impact_velocity")
    return h0, min(st.dt_max, st.cfl * h0 / (st.wave_speed + speed + av))


def softening(eps_max: np.ndarray, mat: Concrete) -> np.ndarray:
    """s = (eps_max - eps_0)/(eps_f - eps_0) in [0, 1]: 1 - residual strength / f_t; 0 without a
    softening law (eps_f <= eps_0: damage off, :meth:`Concrete.validate`)."""
    if not mat.eps_f > mat.eps_0:
        return np.zeros_like(eps_max)
    return np.clip((eps_max - mat.eps_0) / (mat.eps_f - mat.eps_0), 0.0, 1.0)


def crack_indicator(scene: Scene, dmg: np.ndarray, eps_max: np.ndarray) -> np.ndarray:
    damage = scene.get("material.cracked_measure") == "damage"
    return dmg if damage else softening(eps_max, concrete(scene))


SERIES = ("time", "contact_force", "contact_force_penalty", "kinetic", "internal", "elastic",
          "plastic", "damage", "unattributed", "viscous", "artificial_stress", "penalty",
          "kinematic_removed", "balance_error", "momentum_y", "vcm_y", "cracked_fraction",
          "impulse")
SNAPSHOT_FIELDS = ("x", "y", "damage", "softening", "plastic_strain")


class ImpactRun(runner.EngineRun):
    """The impact engine as the runner sees it: one advance is one leapfrog step; health checks
    every 50 steps and at every sample; snapshots at ``outputs.snapshot_times`` and the end."""

    CHECK_EVERY = 50

    def __init__(self, scene: Scene, seed: int) -> None:
        self.scene, self.seed = scene, seed
        self.specimen = build_specimen(scene, seed)
        self.engine = Engine(settings(scene), initial_state(scene, self.specimen))
        self.t_end = float(scene.get("outputs.t_end"))
        self.every = float(scene.get("outputs.series_dt"))
        self.snap_times = sorted(t for t in scene.get("outputs.snapshot_times") if t < self.t_end)
        self.series: dict[str, list] = {k: [] for k in SERIES}
        self.snapshots: dict[str, list] = {k: [] for k in ("time", *SNAPSHOT_FIELDS)}
        self.mass_total = float(self.engine.state.m.sum())
        self.cracked = scene.get("material.cracked_threshold")
        self.last_t = self.last_impulse = 0.0
        self.next_sample = self.every
        self.n_particles = self.specimen.n

    def start(self) -> None:
        self._sample()

    def done(self) -> bool:
        return self.engine.t >= self.t_end * (1 - 1e-12)

    def advance(self) -> None:
        self.engine.step(min(self.engine.dt, self.t_end - self.engine.t))

    def _sample_due(self) -> bool:
        return self.engine.t >= self.next_sample * (1 - 1e-9) or self.done()

    def divergence(self):
        due = self.engine.step_count % self.CHECK_EVERY == 0 or self._sample_due()
        return self.engine.health() if due else None

    def sample(self) -> None:
        eng = self.engine
        taken = len(self.snapshots["time"])
        if taken < len(self.snap_times) and eng.t >= self.snap_times[taken]:
            self._snapshot()
        if self._sample_due():
            self._sample()
            self.next_sample += self.every

    def _sample(self) -> None:
        eng, series = self.engine, self.series
        dt_int = eng.t - self.last_t
        series["time"].append(eng.t)
        series["contact_force"].append((eng.impulse - self.last_impulse) / dt_int
                                       if dt_int > 0 else eng.force)
        series["contact_force_penalty"].append(eng.force)
        for key, val in eng.energies().items():
            series[key].append(val)
        series["balance_error"].append(eng.balance_error())
        py = eng.momentum()[1]
        series["momentum_y"].append(py)
        series["vcm_y"].append(py / self.mass_total)
        crack = crack_indicator(self.scene, eng.state.dmg, eng.state.eps_max)
        series["cracked_fraction"].append(float(np.mean(crack >= self.cracked)))
        series["impulse"].append(eng.impulse)
        self.last_t, self.last_impulse = eng.t, eng.impulse

    def _snapshot(self) -> None:
        st = self.engine.state
        self.snapshots["time"].append(self.engine.t)
        for key, value in (("x", st.x.copy()), ("y", st.y.copy()), ("damage", st.dmg.copy()),
                           ("softening", softening(st.eps_max, self.engine.s.material)),
                           ("plastic_strain", st.epsp.copy())):
            self.snapshots[key].append(value)

    def finish(self) -> None:
        """The final health check and field snapshot."""
        self.engine.check_health()
        self._snapshot()

    def parts(self) -> dict[str, object]:
        """What evolves, by checkpoint prefix: the engine, its particles and this run."""
        return {"engine_": self.engine, "particles_": self.engine.state, "model_": self}

    def result(self):
        return (self.specimen, self.engine, {k: np.asarray(v) for k, v in self.series.items()},
                self.snapshots)

    def options(self) -> dict:
        """The runner's end time, label and time unit (microseconds) of this run."""
        return {"t_end": self.t_end, "desc": f"impact {self.scene.name} seed {self.seed}",
                "time_unit": "us", "time_scale": 1e6}


def run(scene: Scene, out: Path, seed: int, init: Path | None = None, **checkpoints) -> Path:
    """Simulate ``scene`` and write the run dataset to ``out`` (through the runner;
    ``checkpoints``: the options of :func:`craquelure.runner.run_to_file`)."""
    clock = WallClock()
    model = ImpactRun(scene, seed)
    return runner.run_to_file(
        model, scene, seed, out, lambda: run_dataset(scene, seed, *model.result()), clock,
        **model.options(), **checkpoints)


def run_dataset(scene, seed, sp, eng, series, snapshots) -> xr.Dataset:
    st = eng.state
    fields = {"x0": sp.x, "y0": sp.y, "mass": sp.mass, "precrack": sp.precrack.astype(np.int8),
              "x": st.x, "y": st.y, "vx": st.vx, "vy": st.vy, "damage": st.dmg,
              "softening": softening(st.eps_max, eng.s.material), "plastic_strain": st.epsp,
              "plastic_compaction": st.epsv, "h": st.h, "rho": st.rho}
    if sp.dim == 3:
        fields.update(z0=sp.z, z=st.z, vz=st.vz)
    data = {k: ("particle", v) for k, v in fields.items()}
    data |= {f"series_{key}": ("time", arr) for key, arr in series.items() if key != "time"}
    data |= {f"snap_{key}": (("snapshot_time", "particle"), np.stack(snapshots[key]))
             for key in SNAPSHOT_FIELDS}
    ds = xr.Dataset(data, coords={"time": series["time"], "snapshot_time": snapshots["time"]})
    ds.attrs["dim"] = sp.dim
    ds["series_contact_force"].attrs.update(
        units="N/m" if sp.dim == 2 else "N",
        long_name=("base contact force per metre" if sp.dim == 2 else "base contact force")
        + " (interval average of the impulse)")
    # What the run used and what only the running engine saw; every measurement is the
    # analysis's (craquelure.impact.analysis), from these fields, series and the stored scene.
    ds.attrs.update({
        "spacing": sp.spacing, "radius": sp.radius, "centre_y": sp.centre_y, "n_particles": sp.n,
        "as_epsilon": eng.s.as_epsilon, "crack_band_width": eng.s.material.band,
        "contact_a": eng.s.contact_a, "material_model": material_model(scene),
        "run_dt_min": eng.dt_min_seen, "run_energy_initial": eng.e0,
        "run_max_penetration": eng.max_penetration, "run_kinematic_impulse": eng.impulse_kin,
        "run_contact_force_peak_step": eng.force_peak,  # steps: the runner's run_steps
    })
    load, unit = splitting_load(scene, sp)
    ds["static_splitting_load"] = ((), load, {
        "units": unit, "long_name": "static splitting load pi D t f_t / 2 of the disc"
        + (" per metre of thickness (t = 1 m)" if sp.dim == 2 else "")})
    ds["strength_to_load"] = ((), float(np.max(series["contact_force"], initial=0.0)) / load, {
        "units": "1", "long_name": "peak contact force over the static splitting load"})
    return ds


def splitting_load(scene: Scene, sp) -> tuple[float, str]:
    """The disc's static splitting (Brazilian) load pi D t f_t / 2: 3D t = thickness_cells x spacing
    [N]; 2D per metre of thickness [N/m], the unit of the 2D contact force."""
    thick = scene.get("particles.thickness_cells") * sp.spacing if sp.dim == 3 else 1.0
    load = math.pi * 2.0 * sp.radius * thick * scene.get("material.f_t") / 2.0
    return load, "N" if sp.dim == 3 else "N/m"
