"""Effect registry: declarations are complete and consistent with the models' schemas."""

from __future__ import annotations

import sys
import textwrap

import pytest

from craquelure import registry
from craquelure.errors import SceneError
from craquelure.registry import Effect, get_effect, known_effects
from craquelure.scene import MODELS, model_schema


def schema_node(schema: dict, dotted: str) -> dict | None:
    node = schema
    for key in dotted.split("."):
        props = node.get("properties", {})
        if key not in props:
            return None
        node = props[key]
    return node


@pytest.mark.parametrize("model", MODELS)
def test_effect_declarations(model):
    effects = known_effects(model)
    if not effects:
        pytest.skip(f"model {model} declares no effects yet")
    schema = model_schema(model)
    for name, effect in effects.items():
        assert effect.name == name and effect.model == model
        assert effect.description and "\n" not in effect.description
        for dotted in effect.requires:
            node = schema_node(schema, dotted)
            # The parameter exists in the schema (a typo here would make the effect
            # impossible to use). Without a schema default, a scene listing the effect must
            # set it; with one (e.g. the paper's XSPH epsilon) the default is the value used.
            assert node is not None, f"{model}/{name} needs {dotted}: not in the schema"
        for other in effect.conflicts:
            assert other in effects, f"{model}/{name} conflicts with unknown {other!r}"


def test_get_effect_lists_known_effects():
    assert get_effect("drying", "viscosity").requires == ("material.eta",)
    with pytest.raises(SceneError, match="known effects: continuity, drying, elasticity"):
        get_effect("drying", "gravity")


def test_broken_effect_module_is_not_silently_ignored(tmp_path, monkeypatch):
    pkg = tmp_path / "fake_effects_pkg"
    pkg.mkdir()
    (pkg / "__init__.py").write_text("")
    (pkg / "good.py").write_text(textwrap.dedent("""
        from craquelure.registry import Effect
        EFFECT = Effect(model="drying", name="good", flag=None, description="fine")
    """))
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.setitem(registry.EFFECT_PACKAGES, "drying", "fake_effects_pkg")
    registry._effects_in_package.cache_clear()
    try:
        assert list(known_effects("drying")) == ["good"]
        (pkg / "bad.py").write_text("import no_such_module_xyz\n")
        registry._effects_in_package.cache_clear()
        with pytest.raises(ModuleNotFoundError, match="no_such_module_xyz"):
            known_effects("drying")
        # Every model has an effects package: a missing one is an error, not an empty registry.
        monkeypatch.setitem(registry.EFFECT_PACKAGES, "drying", "fake_effects_pkg.absent")
        with pytest.raises(ModuleNotFoundError, match="fake_effects_pkg.absent"):
            known_effects("drying")
    finally:
        registry._effects_in_package.cache_clear()
        for mod in [m for m in sys.modules if m.startswith("fake_effects_pkg")]:
            del sys.modules[mod]


def test_effect_is_frozen():
    effect = Effect(model="drying", name="x", flag=None, description="d")
    with pytest.raises(AttributeError):
        effect.name = "y"


def test_flag_is_the_effect_name_in_capitals():
    assert Effect(model="drying", name="xsph", flag="XSPH", description="d").flag == "XSPH"
    with pytest.raises(ValueError, match="'HAS_XSPH'; the flag is the name in capitals, 'XSPH'"):
        Effect(model="drying", name="xsph", flag="HAS_XSPH", description="d")
