"""Scene rules that a JSON schema cannot state: finite numbers, true integers, cross-field
consistency and the memory a run needs.

:func:`craquelure.scene.validate_scene_data` applies them after the schema, so ``check`` and
``run`` refuse the same scenes, before anything is built. Every error names the key.

- :func:`non_finite_values`: NaN and +-inf anywhere (lists and nested mappings included);
  JSON-schema bounds let NaN through (every comparison with NaN is false) and YAML reads
  ``1e400`` as inf.
- :func:`cross_field_problems`: drying output times within ``t_end``, a step shorter than the run, a
  step count a run can finish, ``h_min < h_max``, excluded bands with ``lo < hi``.
- :func:`memory_estimate` / :func:`memory_problem`: bytes of the largest arrays a run
  allocates (particles, neighbour pairs, mesh, series, snapshots), from the scene alone;
  a scene whose estimate exceeds the memory available is refused, saying how much it needs.
- :func:`initial_state_problems`: an ``--init`` state must hold the scene's particles in the
  scene's box.
"""

from __future__ import annotations

import math
from typing import Any

from craquelure.errors import SceneError

# Step counts beyond this are not runs but typos (1e12 steps of the cheapest model take
# years on this machine); above 2**53 a float step counter stops advancing.
MAX_STEPS = 1e12
# Fraction of the available memory a run may plan to use (the rest: Python, numba, caches).
MEMORY_FRACTION = 0.8


INT64_MAX = 2**63 - 1


def _leaves(node: Any, path: str = ""):
    """(dotted path such as ``outputs.times[2]``, value) of every number or string under
    ``node`` (lists and nested mappings included)."""
    if isinstance(node, dict):
        for key, value in node.items():
            yield from _leaves(value, f"{path}.{key}" if path else str(key))
    elif isinstance(node, list | tuple):
        for k, value in enumerate(node):
            yield from _leaves(value, f"{path}[{k}]")
    else:
        yield path, node


def non_finite_values(node: Any, path: str = "") -> list[tuple[str, float]]:
    """(path, value) of every NaN or infinite number under ``node``, and of every integer
    beyond 64 bits (no machine integer holds it: numba, numpy)."""
    return [(where or "(top level)", v) for where, v in _leaves(node, path)
            if (isinstance(v, float) and not math.isfinite(v))
            or (isinstance(v, int) and not isinstance(v, bool) and abs(v) > INT64_MAX)]


def _get(data: dict, dotted: str, default: Any = None) -> Any:
    node: Any = data
    for key in dotted.split("."):
        if not isinstance(node, dict) or key not in node:
            return default
        node = node[key]
    return node


class SceneAccess:
    """Read access to a scene's resolved mapping ``self.data``: shared by
    :class:`~craquelure.scene.Scene` and :class:`SceneView`."""

    _MISSING = object()

    def get(self, dotted: str, default: Any = _MISSING) -> Any:
        value = _get(self.data, dotted, self._MISSING)
        if value is self._MISSING:
            if default is self._MISSING:
                raise KeyError(dotted)
            return default
        return value

    def has(self, effect: str) -> bool:
        return effect in self.data["effects"]

    @property
    def model(self) -> str:
        return self.data["model"]

    @property
    def effects(self) -> tuple[str, ...]:
        return tuple(self.data["effects"])


class SceneView(SceneAccess):
    """The ``get``/``has`` of :class:`~craquelure.scene.Scene` over validated data, so that the
    models' own formulas (stable steps, beam constants) serve the rules before a Scene exists."""

    def __init__(self, data: dict) -> None:
        self.data = data

    name = "scene"


def _steps_problem(key: str, t_end: float, dt: float) -> str | None:
    if not dt > 0:
        return f"{key}: the step the run would take is {dt!r}; it must be > 0"
    steps = t_end / dt
    if steps > MAX_STEPS:
        return (f"{key}: the run would need {steps:.3g} steps of {dt:.3g} to reach "
                f"outputs.t_end = {t_end:g} (more than {MAX_STEPS:.0e}); raise the step or "
                f"shorten the run")
    return None


def drying_run_step(data: dict) -> float:
    """The step a drying run takes: ``numerics.dt`` halved while above 0.6 of the viscous
    stability limit (``numerics.adapt_dt``, drying spec section 8); as the engine does, with the
    spec's estimate 6.7 eta/(rho0 h^2) of the viscous spectral radius. rkc2 with adapt_dt:
    ``step_control.dt_max``, the step between removal events."""
    from craquelure.drying.api import viscous_spectral_radius
    from craquelure.drying.integrators import REAL_AXIS_LIMIT

    dt = float(_get(data, "numerics.dt"))
    if not _get(data, "numerics.adapt_dt", True):
        return dt
    if _get(data, "numerics.integrator") == "rkc2":
        # error-controlled, not bound by the viscous limit: at dt_max between removal events
        return float((_get(data, "numerics.step_control", None) or {}).get("dt_max", 0.2))
    radius = viscous_spectral_radius(SceneView(data))
    if not radius > 0:
        return dt
    limit = REAL_AXIS_LIMIT[_get(data, "numerics.integrator")] / radius
    while dt > 0.6 * limit and dt > 0:
        dt *= 0.5
    return dt


def _drying_rules(data: dict) -> list[str]:
    out = []
    t_end = float(_get(data, "outputs.t_end"))
    times = _get(data, "outputs.times") or []
    late = [t for t in times if t > t_end * (1 + 1e-12)]
    if late:
        out.append(f"outputs.times: {late[0]!r} is after outputs.t_end = {t_end!r}; snapshot "
                   f"times must lie in [0, t_end]")
    dt = float(_get(data, "numerics.dt"))
    if dt > t_end:
        out.append(f"numerics.dt: {dt!r} is not allowed; the step must not be longer than "
                   f"outputs.t_end = {t_end!r} (the run would take no step)")
    else:
        problem = _steps_problem("numerics.dt", t_end, drying_run_step(data))
        if problem:
            out.append(problem)
    h, length = float(_get(data, "numerics.h")), float(_get(data, "domain.box_length"))
    radius = h * (1 + float(_get(data, "numerics.neighbour_skin", 0.1)))
    if _get(data, "domain.periodic", True) and length < 2 * radius:
        out.append(f"domain.box_length: {length!r} is not allowed; the periodic box must be at "
                   f"least twice the neighbour search radius numerics.h x (1 + "
                   f"numerics.neighbour_skin) = {radius:g}")
    for k, band in enumerate(_get(data, "particles.excluded_bands") or []):
        if band["lo"] >= band["hi"]:
            out.append(f"particles.excluded_bands[{k}]: lo = {band['lo']!r} must be below "
                       f"hi = {band['hi']!r}")
    return out


def _impact_rules(data: dict) -> list[str]:
    out = []
    t_end = float(_get(data, "outputs.t_end"))
    # snapshot_times after t_end are documented as dropped (the end time is always stored)
    h_min, h_max = _get(data, "numerics.h_min"), _get(data, "numerics.h_max")
    if h_min >= h_max:
        out.append(f"numerics.h_min: {h_min!r} must be below numerics.h_max = {h_max!r}")
    if _get(data, "domain.dim") == 3:
        if _get(data, "domain.plane") == "stress":
            out.append("domain.plane: 'stress' is not allowed with domain.dim = 3; allowed "
                       "values: strain (the default; a 3D body has no plane assumption)")
        if _get(data, "particles.shape") == "rings":
            out.append("particles.shape: 'rings' is not allowed with domain.dim = 3; allowed "
                       "values: disc, rectangle")
    precrack = _get(data, "particles.precrack")
    layouts = _get(data, "precracks") or {}
    if precrack != "none" and precrack not in layouts:
        out.append(f"particles.precrack: {precrack!r} is not allowed; allowed values: none, "
                   f"{', '.join(layouts)} (the layouts under precracks)")
    if "damage" in data["effects"]:
        from craquelure.impact.api import concrete

        try:
            concrete(SceneView(data)).check()
        except ArithmeticError as exc:
            out.append(f"material.f_t, material.G_F: the softening law cannot be computed from "
                       f"these magnitudes ({exc})")
        except SceneError as exc:
            out.append(str(exc))
    series = _get(data, "outputs.series_dt")
    if t_end / series > MAX_STEPS:
        out.append(f"outputs.series_dt: {series!r} gives {t_end / series:.3g} samples")
    return out


def lattice_step_estimate(data: dict) -> float:
    """A lower bound of the lattice step dt_factor 2/omega_est (lattice spec section 5) from
    the scene alone: six bonds of the stiffest constant on the lightest disc."""
    from craquelure.lattice.initial_state import beam_constants

    c = beam_constants(SceneView(data))
    spacing = float(_get(data, "particles.spacing", 1.0))
    mass = float(_get(data, "particles.density", 1.0)) * math.pi * spacing**2 / 4
    inertia = mass * spacing**2 / 8
    k = max(c.kn, 2.0 * (c.a + c.b) / spacing**2)
    w2 = max(2 * 6 * k / mass, 2 * 6 * c.a / inertia)
    return float(_get(data, "numerics.dt_factor")) * 2 / math.sqrt(w2) if w2 > 0 else math.inf


def _lattice_rules(data: dict) -> list[str]:
    out = []
    if _get(data, "domain.pad") is not None and _get(data, "domain.periodic_x"):
        out.append("domain.pad cannot be used with domain.periodic_x")
    if _get(data, "material.youngs_modulus") is not None \
            and _get(data, "material.poisson_ratio") is None:
        out.append("material.youngs_modulus needs material.poisson_ratio")
        return out
    t_end = float(_get(data, "outputs.t_end"))
    problem = _steps_problem("numerics.dt_factor", t_end, lattice_step_estimate(data))
    return out + ([problem] if problem else [])


def _softdyn_rules(data: dict) -> list[str]:
    out = []
    t_end = float(_get(data, "outputs.t_end"))
    dt = _get(data, "numerics.dt")
    if dt is not None and dt > t_end:
        out.append(f"numerics.dt: {dt!r} is not allowed; the step must not be longer than "
                   f"outputs.t_end = {t_end!r} (the run would take no step)")
    elif dt is not None and _get(data, "numerics.integrator") == "heun":
        problem = _steps_problem("numerics.dt", t_end, dt)
        if problem:
            out.append(problem)
    window = _get(data, "study.window")
    if window and window[0] >= window[1]:
        out.append(f"study.window: {window!r} must be increasing")
    try:
        _softdyn_setup(SceneView(data))
    except SceneError as exc:
        out.append(str(exc))
    return out


def _softdyn_setup(view: SceneView) -> None:
    """What Soft Dynamics checks while building a run (effects, stop rule, loads, study
    lists), done here so that ``check`` refuses what ``run`` would."""
    from craquelure.softdyn import studies
    from craquelure.softdyn.initial_state import build

    kind = view.get("study.kind")
    build(view).stop_function()
    if kind == "sweep":
        studies.sweep_grid(view)
    elif kind == "phase":
        studies.phase_points(view)
    elif kind == "accuracy" and not (view.get("study.rtol", None) or view.get("study.dt", None)):
        raise SceneError("study.rtol / study.dt: an accuracy study needs at least one list")


RULES = {"drying": _drying_rules, "impact": _impact_rules, "lattice": _lattice_rules,
         "softdyn": _softdyn_rules}


def cross_field_problems(data: dict) -> list[str]:
    """Messages (each naming its key) for the cross-field rules of the scene's model."""
    try:
        return RULES[data["model"]](data)
    except (ArithmeticError, ValueError) as exc:  # finite inputs whose products overflow
        keys = ", ".join(extreme_values(data)) or "the scene's numbers"
        return [f"{keys}: these magnitudes overflow when combined ({type(exc).__name__}: "
                f"{exc}); use values in a physical range"]


def extreme_values(node: Any, path: str = "", bound: float = 1e100) -> list[str]:
    """Dotted paths of numbers beyond 1e100 or below 1e-100 in magnitude (but not 0): the
    suspects when finite inputs overflow in a formula."""
    return [where for where, v in _leaves(node, path) if isinstance(v, int | float)
            and not isinstance(v, bool) and v != 0 and not 1 / bound <= abs(v) <= bound]


# -- memory --------------------------------------------------------------------------------
def _drying_memory(data: dict) -> tuple[float, str]:
    n = int(_get(data, "particles.n"))
    length, h = float(_get(data, "domain.box_length")), float(_get(data, "numerics.h"))
    skin = float(_get(data, "numerics.neighbour_skin", 0.1))
    pairs = n * min(n, n * math.pi * (h * (1 + skin)) ** 2 / length**2 + 1)
    shepard = float(_get(data, "numerics.mass_solve.shepard_spacing", 0.02)) * h
    mesh = (length / shepard) ** 2
    snaps = len(_get(data, "outputs.times") or range(10)) + 1
    rsa = 0.0
    if _get(data, "particles.placement") == "rsa":  # cell grid of side min-separation / sqrt 2
        rsa = 2 * n / float(_get(data, "particles.rsa_min_separation")) ** 2
        mesh = max(mesh, rsa)
    # state (9 vars) x (4 ABM4 history + 4 stages + working copies) + 30 per-particle arrays;
    # pair list and kernel values (3 x 8 bytes); mesh field and its labels; snapshots
    need = n * 8 * (9 * 12 + 30) + pairs * 24 + mesh * 8 * 3 + snaps * n * 8 * 8
    what = "RSA grid" if rsa >= mesh and rsa > 0 else "Shepard mesh"
    return need, f"{n} particles, {pairs:.3g} neighbour pairs, a {mesh:.3g}-cell {what}"


def _impact_memory(data: dict) -> tuple[float, str]:
    d = int(_get(data, "particles.diameter_cells"))
    n = d * int(_get(data, "particles.height_cells", 1)) \
        if _get(data, "particles.shape") == "rectangle" else math.pi / 4 * d * d
    three_d = _get(data, "domain.dim") == 3
    if three_d:
        n *= int(_get(data, "particles.thickness_cells"))
    kappa, hf = float(_get(data, "numerics.kappa", 1.0)), float(_get(data, "numerics.h_factor"))
    h_max = float(_get(data, "numerics.h_max", 2.0))
    support = 2 * kappa * hf * max(1.0, h_max) * (1 + float(_get(data, "numerics.neighbour_skin")))
    pairs = n * min(n, 4.0 / 3.0 * math.pi * support**3 if three_d else math.pi * support**2)
    t_end, series_dt = float(_get(data, "outputs.t_end")), float(_get(data, "outputs.series_dt"))
    samples = t_end / series_dt + 2
    snaps = len(_get(data, "outputs.snapshot_times") or []) + 1
    need = n * 8 * 80 + pairs * 32 + samples * 17 * 8 * 2 + snaps * n * 5 * 8
    return need, f"{n:.3g} particles, {pairs:.3g} neighbour pairs, {samples:.3g} series samples"


def _lattice_memory(data: dict) -> tuple[float, str]:
    n = int(_get(data, "domain.nx")) * int(_get(data, "domain.ny"))
    bonds = 3 * n
    steps = float(_get(data, "outputs.t_end")) / lattice_step_estimate(data)
    rows = steps / int(_get(data, "numerics.series_every", 100)) + 2
    frames = int(_get(data, "outputs.frames", 5)) + 1
    need = n * 8 * 40 + bonds * 8 * 30 + rows * 17 * 8 * 3 + frames * n * 3 * 8
    return need, f"{n} particles, {bonds} bonds, {rows:.3g} energy-series rows"


def _softdyn_memory(data: dict) -> tuple[float, str]:
    samples = int(_get(data, "outputs.n_samples", 400))
    grid = 1
    for key in ("h0", "reduced_force", "fh_over_fv", "rtol", "dt"):
        grid *= max(1, len(_get(data, f"study.{key}") or []))
    need = samples * 64 * 8 * grid + 1e6
    return need, f"{samples} samples x {grid} study points"


MEMORY = {"drying": _drying_memory, "impact": _impact_memory, "lattice": _lattice_memory,
          "softdyn": _softdyn_memory}


def memory_estimate(data: dict) -> tuple[float, str]:
    """(bytes, what dominates) of the largest arrays a run of the scene allocates."""
    try:
        return MEMORY[data["model"]](data)
    except ArithmeticError:
        return math.inf, "numbers too large to count"


def available_memory() -> float:
    """Bytes of memory available to a new process (MemAvailable), inf when unknown."""
    try:
        import psutil

        return float(psutil.virtual_memory().available)
    except Exception:  # noqa: BLE001 - no psutil or no /proc: do not refuse on a guess
        return math.inf


def _gib(x: float) -> str:
    return f"{x / 2**30:.3g} GiB" if math.isfinite(x) else "more than any machine has"


def memory_problem(data: dict, available: float | None = None) -> str | None:
    need, what = memory_estimate(data)
    available = available_memory() if available is None else available
    if need > MEMORY_FRACTION * available:
        return (f"the run needs about {_gib(need)} of memory ({what}); "
                f"this machine has {_gib(available)} available")
    return None


# -- initial states -------------------------------------------------------------------------
def initial_state_problems(scene, ds, path) -> list[str]:
    """An ``--init`` state must be of the scene's model and hold the scene's particles in the
    scene's box (its provenance would otherwise describe another run)."""
    out = []
    model = ds.attrs.get("model")
    if model is not None and model != scene.model:
        out.append(f"{path}: an initial state of model {model!r}, not {scene.model!r}")
        return out
    if scene.model == "drying":
        n, length = int(scene.get("particles.n")), float(scene.get("domain.box_length"))
        n_file = int(ds.sizes.get("particle", 0))
        if n_file != n:
            out.append(f"{path}: holds {n_file} particles; the scene's particles.n is {n}")
        box = ds.attrs.get("box_length")
        if box is not None and not math.isclose(float(box), length, rel_tol=1e-12):
            out.append(f"{path}: box length {float(box):g}; the scene's domain.box_length is "
                       f"{length:g}")
    return out
