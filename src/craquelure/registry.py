"""Registry of physical effects.

Every effect is one small module (``craquelure/<model>/effects/<name>.py``) that declares
``EFFECT = Effect(...)`` (:class:`Effect`, :class:`Param`); the parameters every effect set uses
are the ``PARAMS`` of the model's effects package (``effects/__init__.py``). From these
declarations alone come scene validation (an unknown effect or a missing parameter is rejected
before anything runs), the kernel flags (:func:`craquelure.codegen.effect_flags`), the kernel's
parameter tuple and index constants (:func:`parameter_names`) and the packed parameter vector
(:func:`parameter_vector`), so a new effect is its module, its schema entries, the kernel lines
where it enters the equations and its test.
"""

import importlib
import math
import pkgutil
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from functools import cache
from typing import Any

import numpy as np

from craquelure.errors import SceneError
from craquelure.models import MODELS


@dataclass(frozen=True)
class Param:
    """One entry (``size`` > 1: a vector of entries) of a kernel's parameter vector.

    ``path``: the dotted scene path it is read from when an effect that declares it is on
    (``convert`` applied; ``None``: the engine computes it and passes it by name);
    ``optional``: the scene may leave the path unset, which means ``neutral``; ``neutral``: the
    value when every effect that declares it is off (its branch is compiled out; the value
    keeps what the engine reads of the vector finite and inert); ``kernel=False``: a constant
    the effect's model reads outside the kernel (a material law's), not in the vector."""

    name: str
    path: str | None = None
    unit: str = "1"
    neutral: float = 0.0
    size: int = 1
    optional: bool = False
    convert: Callable[[Any], float] = float
    kernel: bool = True

    def value(self, scene: Any, on: bool) -> Any:
        """The value of a scene: its path's (converted) when ``on``, else the neutral one."""
        if scene is None or not on or self.path is None:
            return self.neutral
        read = scene.optional(self.path) if self.optional else scene.get(self.path)
        return self.neutral if read is None else self.convert(read)


@dataclass(frozen=True)
class Effect:
    """Declaration of one physical effect of one model.

    ``requires`` are the dotted scene paths the effect needs (e.g. ``("material.eta",)``);
    the paths of its non-optional ``params`` are added to them. ``conflicts`` names effects it
    cannot run with. ``flag`` is the compile-time constant of the engine's kernel template that
    switches the effect on (:func:`craquelure.codegen.effect_flags`), the effect's name in
    capitals (``xsph`` -> ``XSPH``); ``None`` for an effect that is always compiled in or acts
    outside the kernel. ``energy(engine)``: the energy the effect can supply over a run, added
    to the runaway guard's bound. ``diagnostics``: the run dataset's variables it adds.
    """

    model: str
    name: str
    flag: str | None
    description: str
    requires: tuple[str, ...] = ()
    conflicts: tuple[str, ...] = ()
    params: tuple[Param, ...] = ()
    energy: Callable[[Any], float] | None = None
    diagnostics: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        if self.flag not in (None, self.name.upper()):
            raise ValueError(f"effect {self.name!r}: flag {self.flag!r}; the flag is the name "
                             f"in capitals, {self.name.upper()!r}")
        paths = [p.path for p in self.params if p.path and not p.optional]
        object.__setattr__(self, "requires", tuple(dict.fromkeys((*self.requires, *paths))))


# The package whose modules declare each model's effects: ``craquelure.<model>.effects``.
EFFECT_PACKAGES = {model: f"craquelure.{model}.effects" for model in MODELS}


@cache
def _effects_in_package(package: str) -> dict[str, Effect]:
    pkg = importlib.import_module(package)  # every model has one (the model contract)
    found: dict[str, Effect] = {}
    for info in pkgutil.iter_modules(pkg.__path__):
        module = importlib.import_module(f"{package}.{info.name}")
        effect = getattr(module, "EFFECT", None)
        if isinstance(effect, Effect):
            if effect.name in found:
                raise RuntimeError(f"effect {effect.name!r} declared twice in {package}")
            found[effect.name] = effect
    return found


def known_effects(model: str) -> dict[str, Effect]:
    """All effects available to ``model``, by name (sorted)."""
    package = EFFECT_PACKAGES.get(model)
    effects = _effects_in_package(package) if package else {}
    return dict(sorted((name, e) for name, e in effects.items() if e.model == model))


def get_effect(model: str, name: str) -> Effect:
    effects = known_effects(model)
    if name not in effects:
        raise SceneError(f"effects: unknown effect {name!r} for model {model!r}; "
                         f"known effects: {', '.join(effects) or '(none)'}")
    return effects[name]


def kernel_parameters(model: str) -> dict[str, tuple[Param, frozenset[str]]]:
    """``{name: (param, effects declaring it)}`` of every declared parameter, in the kernel's
    order: the model-wide ``PARAMS`` of the effects package (no owner: always read), then each
    effect's, by effect name. Two effects may declare the same parameter (both read it) with
    the same declaration."""
    package = importlib.import_module(EFFECT_PACKAGES[model])
    out: dict[str, tuple[Param, frozenset[str]]] = {
        p.name: (p, frozenset()) for p in getattr(package, "PARAMS", ())}
    for name, effect in known_effects(model).items():
        for p in effect.params:
            if p.name not in out:
                out[p.name] = (p, frozenset({name}))
                continue
            known, owners = out[p.name]
            if known != p or not owners:
                raise RuntimeError(f"{model} kernel parameter {p.name!r}: declared differently "
                                   f"by {name} and by {', '.join(owners) or 'the model'}")
            out[p.name] = (p, owners | {name})
    return out


def parameter_names(model: str) -> tuple[str, ...]:
    """The kernel's parameter tuple: one name per entry; a vector parameter ``v`` of size n
    fills n entries, ``v`` then ``v[1]`` .. ``v[n-1]`` (its index constant is its first)."""
    return tuple(name if k == 0 else f"{name}[{k}]"
                 for name, (p, _) in kernel_parameters(model).items() if p.kernel
                 for k in range(p.size))


def parameter_vector(model: str, scene: Any = None,
                     values: Mapping[str, Any] | None = None) -> np.ndarray:
    """The kernel's parameter vector, in the order of :func:`parameter_names`. Each parameter:
    its entry of ``values`` (what the engine computes) if given; else, with a ``scene`` and when
    the model always reads it or an effect that declares it is on, its scene path; else its
    neutral value. A name in ``values`` the model does not declare is an error."""
    params = kernel_parameters(model)
    given = dict(values or {})
    unknown = sorted(set(given) - {name for name, (p, _) in params.items() if p.kernel})
    if unknown:
        raise KeyError(f"unknown {model} kernel parameters {unknown}; known: "
                       f"{', '.join(params)}")
    out: list[float] = []
    for name, (p, owners) in params.items():
        if not p.kernel:
            continue
        value = given[name] if name in given else p.value(scene, _on(scene, owners))
        entries = np.broadcast_to(np.asarray(value, dtype=float), (p.size,))
        out.extend(float(v) for v in entries)
    return np.array(out)


def _on(scene: Any, owners: frozenset[str]) -> bool:
    return scene is not None and (not owners or any(map(scene.has, owners)))


def scene_values(model: str, scene: Any, names: tuple[str, ...]) -> dict[str, Any]:
    """``{name: value}`` of declared parameters (kernel or not) for a scene: the scene's when an
    effect that declares it is on, else its neutral value."""
    params = kernel_parameters(model)
    return {name: params[name][0].value(scene, _on(scene, params[name][1])) for name in names}


def energy_bound(model: str, engine: Any) -> float:
    """The energy the scene's effects can supply over a run (their ``energy`` declarations)."""
    return math.fsum(e.energy(engine) for name, e in known_effects(model).items()
                     if e.energy is not None and name in engine.effects)
