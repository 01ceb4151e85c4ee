"""Effect registry: declarations are complete and consistent with the models' schemas."""

from __future__ import annotations

import sys
import textwrap

import pytest

from craquelure import registry
from craquelure.errors import SceneError
from craquelure.registry import Effect, Param, get_effect, known_effects
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
    # every declared parameter's scene path (model-wide ones too) is in the schema
    for name, (param, _) in registry.kernel_parameters(model).items():
        assert param.path is None or schema_node(schema, param.path) is not None, (model, name)


def test_get_effect_lists_known_effects():
    assert get_effect("drying", "viscosity").requires == ("material.eta",)
    with pytest.raises(SceneError, match="known effects: " + ", ".join(known_effects("drying"))):
        get_effect("drying", "gravity")


def test_declared_diagnostics_are_run_variables():
    """The diagnostics an effect declares are variables of its model's run dataset."""
    from craquelure.drying.api import SERIES_VARS, SNAPSHOT_VARS

    declared = {d for e in known_effects("drying").values() for d in e.diagnostics}
    assert declared and declared <= set(SERIES_VARS) | set(SNAPSHOT_VARS)


def test_a_parameters_scene_path_is_required():
    """The paths of an effect's non-optional parameters join its ``requires``."""
    effect = Effect(model="drying", name="x", flag=None, description="d",
                    requires=("material.a",),
                    params=(Param("b", "material.b"), Param("c", "material.c", optional=True)))
    assert effect.requires == ("material.a", "material.b")


THROWAWAY = """
from craquelure.registry import Effect, Param

EFFECT = Effect("drying", "spin", None, "a throwaway effect read nowhere",
                params=(Param("omega", "material.rho0", neutral=-7.0),),
                energy=lambda engine: 123.0)
"""


def test_a_new_effect_needs_no_list_elsewhere(tmp_path, monkeypatch):
    """An effect module added to the drying effects (here a copy of the package plus one new
    module, nothing else edited) is picked up by the registry, the kernel's PARAMS and index
    constants, the engine's packing with its neutral value, and the runaway guard's bound."""
    import importlib
    import pkgutil

    import craquelure.drying.effects as real
    from craquelure import codegen
    from craquelure.drying import engine, kernel_template

    from .drying.conftest import drying_scene as make_scene
    from .drying.conftest import lattice_engine as make_lattice_engine

    pkg = tmp_path / "copied_effects"
    pkg.mkdir()
    (pkg / "__init__.py").write_text("from craquelure.drying.effects import PARAMS  # noqa\n")
    for info in pkgutil.iter_modules(real.__path__):
        (pkg / f"{info.name}.py").write_text(
            f"from craquelure.drying.effects.{info.name} import EFFECT  # noqa\n")
    (pkg / "spin.py").write_text(THROWAWAY)
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.setitem(registry.EFFECT_PACKAGES, "drying", "copied_effects")
    registry._effects_in_package.cache_clear()
    codegen.specialise.cache_clear()
    try:
        importlib.reload(kernel_template)
        assert "spin" in known_effects("drying")
        assert "omega" in kernel_template.PARAMS
        assert kernel_template.PARAMS == registry.parameter_names("drying")
        # the index constants follow the new order
        for const, name in (("P_ETA", "eta"), ("P_THICK", "thickness"), ("P_BODY", "body_force")):
            assert getattr(kernel_template, const) == kernel_template.PARAMS.index(name)
        omega = kernel_template.PARAMS.index("omega")
        off = make_scene(effects=["elasticity", "viscosity"])
        on = make_scene(effects=["elasticity", "viscosity", "spin"])
        neutral = registry.kernel_parameters("drying")["omega"][0].neutral
        assert engine.parameters(off)[omega] == neutral
        assert engine.parameters(on)[omega] == on.get("material.rho0")
        assert engine.parameters(on)[kernel_template.P_ETA] == on.get("material.eta")
        bound = make_lattice_engine(on).energy_bound - make_lattice_engine(off).energy_bound
        assert bound == pytest.approx(123.0, rel=1e-9)
    finally:
        registry._effects_in_package.cache_clear()
        codegen.specialise.cache_clear()
        for mod in [m for m in sys.modules if m.startswith("copied_effects")]:
            del sys.modules[mod]
        monkeypatch.undo()
        importlib.reload(kernel_template)


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
