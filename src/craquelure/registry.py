"""Registry of physical effects.

Every effect is one small module (``craquelure/<engine>/effects/<name>.py``) that declares
``EFFECT = Effect(...)``: its model, name, kernel flag, a one-line description and the scene
parameters it needs (dotted paths). Scene validation reads the registry, so an unknown effect or a
missing parameter is rejected before anything runs, and the engine compiles only the effects a
scene lists.
"""

from __future__ import annotations

import importlib
import pkgutil
from dataclasses import dataclass
from functools import cache

from craquelure.models import MODELS


@dataclass(frozen=True)
class Effect:
    """Declaration of one physical effect of one model.

    ``requires`` are the dotted scene paths the effect needs (e.g. ``("material.eta",)``);
    ``conflicts`` names effects it cannot run with. ``flag`` is the compile-time constant of
    the engine's kernel template that switches the effect on
    (:func:`craquelure.codegen.effect_flags`), the effect's name in capitals (``xsph`` ->
    ``XSPH``); ``None`` for an effect that is always compiled in or acts outside the kernel.
    """

    model: str
    name: str
    flag: str | None
    description: str
    requires: tuple[str, ...] = ()
    conflicts: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        if self.flag not in (None, self.name.upper()):
            raise ValueError(f"effect {self.name!r}: flag {self.flag!r}; the flag is the name "
                             f"in capitals, {self.name.upper()!r}")


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
        from craquelure.errors import SceneError

        raise SceneError(
            f"effects: unknown effect {name!r} for model {model!r}; "
            f"known effects: {', '.join(effects) or '(none)'}"
        )
    return effects[name]
