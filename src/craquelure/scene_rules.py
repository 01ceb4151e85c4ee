"""Scene rules that a JSON schema cannot state: finite numbers, true integers, cross-field
consistency and the memory a run needs.

:func:`craquelure.scene.validate_scene_data` applies them after the schema, so ``check`` and
``run`` refuse the same scenes, before anything is built. Every error names the key. JSON-schema
bounds let NaN through (every comparison with NaN is false) and YAML reads ``1e400`` as inf,
hence :func:`non_finite_values`; the model's own rules and memory estimate are
``scene_problems(data)`` and ``memory_estimate(data)`` of ``craquelure.<model>.rules``.
"""

import math
from typing import Any

from craquelure.models import model_module

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


def lookup(data: dict, dotted: str, default: Any = None) -> Any:
    """The value at ``dotted`` (``"numerics.dt"``) of a scene mapping, ``default`` if absent."""
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
        value = lookup(self.data, dotted, self._MISSING)
        if value is self._MISSING:
            if default is self._MISSING:
                raise KeyError(dotted)
            return default
        return value

    def optional(self, dotted: str) -> Any | None:
        """The value of a parameter the schema leaves optional, None when the scene does not
        set it: the caller states what its absence means (its schema description says)."""
        return lookup(self.data, dotted)

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


def steps_problem(key: str, t_end: float, dt: float) -> str | None:
    """The message when a run of steps ``dt`` to ``t_end`` takes none or too many steps."""
    if not dt > 0:
        return f"{key}: the step the run would take is {dt!r}; it must be > 0"
    steps = t_end / dt
    if steps > MAX_STEPS:
        return (f"{key}: the run would need {steps:.3g} steps of {dt:.3g} to reach "
                f"outputs.t_end = {t_end:g} (more than {MAX_STEPS:.0e}); raise the step or "
                f"shorten the run")
    return None


def cross_field_problems(data: dict) -> list[str]:
    """Messages (each naming its key) for the cross-field rules of the scene's model."""
    try:
        return model_module(data["model"], "rules").scene_problems(data)
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
def memory_estimate(data: dict) -> tuple[float, str]:
    """(bytes, what dominates) of the largest arrays a run of the scene allocates."""
    try:
        return model_module(data["model"], "rules").memory_estimate(data)
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


