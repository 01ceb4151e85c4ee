"""From a validated lattice scene to an :class:`~craquelure.lattice.engine.Engine`.

Geometry (spec sections 2 and 10): an nx x ny triangular block with its bottom row at y = 0
(or resting on the bed: bottom at ``domain.bed_level``), optionally periodic in x; the
fretting pad is a lower half-disc of radius R (its own body, unbreakable beams) whose lowest
row sits one diameter plus ``pad.gap`` above the block's top row; its top row is driven:
x = x_0 + delta sin(2 pi (t - t_p)/T) after the press time t_p, rotation fixed, y free and
loaded with P spread over the row. Loads on the top row of the block: tau_app L (x) and
-p L (y) per particle (Glen test). Stiffness: E-B (E_b, w) or shear-beam (k_n, k_s), or both
from macroscopic (E, nu) through the inverse mapping of section 4.

Time step: dt = dt_factor 2/omega with omega^2 = omega_est^2 (quick beam estimate) +
k_bed/m + k_c/m (bed spring and contact, linearised at an overlap of 0.1 L) [D].
"""

import math

import numpy as np

from craquelure.errors import SceneError
from craquelure.lattice import beam
from craquelure.lattice.engine import (
    PARAMS,
    Engine,
    LatticeState,
    lattice_system,
    schema_owned,
    stable_step_estimate,
)
from craquelure.lattice.geometry import REMOVED, half_disc, remove_fraction, triangular_block
from craquelure.registry import parameter_vector
from craquelure.scene import Scene, load_scene_text, schema_default


def beam_constants(scene: Scene) -> beam.BeamConstants:
    L = scene.get("particles.spacing")  # noqa: N806
    # no bond model (only without beams, which requires one): the E-B constants
    model = scene.optional("material.bond_model")
    E = scene.optional("material.youngs_modulus")  # noqa: N806
    if E is not None:  # with material.poisson_ratio (scene rules)
        kn, ks = beam.stiffness_from_moduli(E, scene.get("material.poisson_ratio"))
        if model == "shear_beam":
            return beam.shear_beam(kn, ks, L)
        w = L * math.sqrt(ks / kn)
        return beam.euler_bernoulli(kn * L / w, w, L)
    if model == "shear_beam":
        kn = scene.get("material.kn")
        return beam.shear_beam(kn, kn * scene.get("material.ks_over_kn"), L)
    return beam.euler_bernoulli(scene.get("material.E_b"), scene.get("material.width") * L, L)


def build_system(scene: Scene, seed: int) -> tuple[LatticeState, dict[str, np.ndarray]]:
    """The particle/bond system of a scene and per-particle labels (body, row, col)."""
    L = scene.get("particles.spacing")  # noqa: N806
    nx, ny = scene.get("domain.nx"), scene.get("domain.ny")
    periodic = scene.get("domain.periodic_x")
    y0 = scene.get("domain.bed_level") + 0.5 * L if scene.has("bed") else 0.0
    x, y, row = triangular_block(nx, ny, L, 0.0, y0)
    col = np.arange(x.size) % nx
    body = np.zeros(x.size, np.int64)
    pad = scene.optional("domain.pad")
    if pad is not None:  # never with domain.periodic_x (scene rules)
        px, py = half_disc(pad["radius"], 0.0, 0.0, L)
        px = px + 0.5 * (x.min() + x.max())
        py = py - py.min() + y.max() + L + pad["gap"]
        x, y = np.concatenate([x, px]), np.concatenate([y, py])
        row = np.concatenate([row, np.full(px.size, -1)])
        col = np.concatenate([col, np.full(px.size, -1)])
        body = np.concatenate([body, np.ones(px.size, np.int64)])
    c = beam_constants(scene)
    system = lattice_system(x, y, L, kn=c.kn, ka=c.a, kb=c.b, rho=scene.get("particles.density"),
                            period_x=nx * L if periodic else 0.0, body=body)
    system.unbreakable[(body[system.bi] == 1)] = 1
    removal = scene.get("particles.bond_removal")
    if removal > 0:
        rng = np.random.default_rng(seed)
        candidates = np.flatnonzero(body[system.bi] == 0)
        gone = candidates[remove_fraction(candidates.size, removal, rng)]
        system.state[gone] = REMOVED
    if scene.get("domain.clamp_bottom"):
        system.fix[:, row == 0] = 1
    if scene.get("domain.fix_back_x"):
        system.fix[0, (col == 0) & (body == 0)] = 1
    top = (row == ny - 1) & (body == 0)
    system.load[0, top] = scene.get("loads.top_shear_stress") * L
    system.load[1, top] = -scene.get("loads.top_normal_stress") * L
    if pad is not None:
        ptop = (body == 1) & (y > y[body == 1].max() - 0.1 * L)
        system.drive[0, ptop] = 1
        system.fix[2, ptop] = 1
        system.load[1, ptop] = -pad["load"] / ptop.sum()
    return system, {"body": body, "row": row, "col": col}


def time_step(scene: Scene, system: LatticeState) -> float:
    dt_beam = stable_step_estimate(system)
    w2 = (2.0 / dt_beam) ** 2 if math.isfinite(dt_beam) else 0.0
    m = float(system.mass.min())
    if scene.has("bed"):
        w2 += scene.get("bed.stiffness") / m
    if scene.has("contact"):
        w2 += 1.5 * scene.get("contact.stiffness") * math.sqrt(0.1 * system.L) / m
    if w2 <= 0:
        raise SceneError("no stiffness in the scene: cannot choose a time step")
    return scene.get("numerics.dt_factor") * 2.0 / math.sqrt(w2)


def engine_params(scene: Scene, system: LatticeState) -> dict[str, float]:
    """The kernel parameters of a scene by name: the scene paths the effects declare
    (:func:`craquelure.registry.parameter_vector`) and the values computed here (beam constants,
    the stable step, damping times)."""
    c = beam_constants(scene)
    m = float(system.mass[0])
    g = scene.get
    computed = dict(
        dt=time_step(scene, system),
        beta=2.0 * g("numerics.bond_damping") * math.sqrt(m / c.kn),
        area=c.area, inertia=c.inertia, width=c.width, E_b=c.E_b, block=system.L,
        cell_area=beam.cell_area(system.L),
        energy_floor=1e-12 * system.n * c.kn * system.L**2,
    )
    if scene.has("bed"):
        computed["bed_damping"] = g("bed.damping_ratio") * 2.0 * math.sqrt(g("bed.stiffness") / m)
    return dict(zip(PARAMS, parameter_vector("lattice", scene, computed).tolist(), strict=True))


def make_engine(scene: Scene, seed: int) -> tuple[Engine, dict[str, np.ndarray]]:
    system, labels = build_system(scene, seed)
    if not scene.has("beams"):
        system.state[:] = REMOVED
    engine = Engine(system, tuple(scene.effects), engine_params(scene, system),
                    seed=seed, **engine_options(scene))
    return engine, labels


def engine_options(scene: Scene) -> dict:
    """The engine's options from the resolved scene; melting off: no re-freezing."""
    melting = scene.has("melting")
    return dict(series_every=scene.get("numerics.series_every"),
                node_averaged=scene.get("fracture.variant") == "node_averaged",
                bending=scene.get("fracture.bending"),
                freeze_every=scene.get("melting.freeze_every") if melting else 0,
                refreeze_radius=scene.get("melting.refreeze_radius") if melting else math.nan)


PROBE_SCENE = """{model: lattice, domain: {nx: 2, ny: 2}, particles: {}, numerics: {},
material: {bond_model: shear_beam}, outputs: {t_end: 1.0}, effects: [beams]}"""


def probe_engine(system: LatticeState, effects, params: dict, **options) -> Engine:
    """An engine for a system that is not a scene's (a column, a test block): the options of
    the smallest scene, :data:`PROBE_SCENE` (the schema's defaults), with ``options`` set, and
    the parameters whose default the schema owns (:func:`.engine.schema_owned`) from the schema
    unless ``params`` sets them."""
    probe = engine_options(load_scene_text(PROBE_SCENE, "probe"))
    owned = {name: schema_default("lattice", path) for name, path in schema_owned().items()}
    return Engine(system, tuple(effects), {**owned, **params}, **{**probe, **options})
