"""One default per parameter, in the schema (docs/adding-an-effect.md): the code reads the
resolved scene and keeps no default of its own. Read from the source (ast), so that a second
default is caught when it is written, whether or not a test scene ever reaches it."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

from craquelure.models import MODELS
from craquelure.scene import model_schema

PACKAGE = Path(__file__).resolve().parents[1] / "src" / "craquelure"
# the modules that build a run from a resolved scene: their fields and keywords are parameters
BUILDERS = ("engine.py", "api.py", "initial_state.py")


def schema_defaults(model: str) -> dict[str, object]:
    """Dotted path -> default of every schema parameter that has one and is in every resolved
    scene (its sections are required or have a default themselves: a parameter of an optional
    section without one is absent with its section)."""
    out: dict[str, object] = {}

    def walk(node: dict, prefix: str) -> None:
        for key, sub in (node.get("properties") or {}).items():
            if "default" in sub:
                out[prefix + key] = sub["default"]
            if "default" in sub or key in node.get("required", ()):
                walk(sub, f"{prefix}{key}.")

    walk(model_schema(model), "")
    return out


def fallback_reads(tree: ast.AST):
    """(line, dotted path) of every ``x.get("a.b", fallback)``, ``g("a.b", fallback)`` and
    ``lookup(data, "a.b", fallback)``."""
    for node in ast.walk(tree):
        if not isinstance(node, ast.Call):
            continue
        name = getattr(node.func, "attr", None) or getattr(node.func, "id", None)
        args = node.args[1:] if name == "lookup" else node.args
        if name in ("get", "g", "lookup") and len(args) == 2 and isinstance(
                args[0], ast.Constant) and isinstance(args[0].value, str) \
                and "." in args[0].value:
            yield node.lineno, args[0].value


def defaulted_names(tree: ast.AST):
    """(line, name) of every class field and function keyword that has a default."""
    for node in ast.walk(tree):
        if isinstance(node, ast.ClassDef):
            for item in node.body:
                if isinstance(item, ast.AnnAssign) and item.value is not None \
                        and isinstance(item.target, ast.Name):
                    yield item.lineno, item.target.id
        elif isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
            a = node.args
            positional = a.posonlyargs + a.args
            for arg in positional[len(positional) - len(a.defaults):]:
                yield node.lineno, arg.arg
            for arg, default in zip(a.kwonlyargs, a.kw_defaults, strict=True):
                if default is not None:
                    yield node.lineno, arg.arg


def second_defaults(model: str, files) -> list[str]:
    defaults = schema_defaults(model)
    leaves = {path.rsplit(".", 1)[-1] for path in defaults}
    found = []
    for path in files:
        tree = ast.parse(path.read_text())
        where = path.relative_to(PACKAGE.parent)
        found += [f"{where}:{line}: reads {dotted} with a fallback; the schema's default is "
                  f"{defaults[dotted]!r}" for line, dotted in fallback_reads(tree)
                  if dotted in defaults]
        if path.name in BUILDERS:
            found += [f"{where}:{line}: `{name}` has a default; the scene parameter of that name "
                      "has its default in the schema" for line, name in defaulted_names(tree)
                      if name in leaves]
    return found


@pytest.mark.parametrize("model", MODELS)
def test_each_parameter_has_one_default(model):
    """No scene read of a parameter passes a fallback (the resolved scene, a stored one too,
    has the schema's default), and no field or keyword of an engine, API or initial state
    named as a parameter carries a default of its own."""
    files = sorted((PACKAGE / model).rglob("*.py"))
    assert files
    found = second_defaults(model, files)
    assert not found, "second defaults:\n" + "\n".join(found)


# names a scene is read through in the package: a two-argument ``get`` on one is a fallback
SCENE_NAMES = {"scene", "sc", "view"}


def scene_fallbacks(tree: ast.AST):
    """(line, key) of every fallback read of a scene: :func:`fallback_reads`, and
    ``scene.get(key, x)`` / ``self.scene.get(key, x)`` whatever the key expression."""
    yield from fallback_reads(tree)
    for node in ast.walk(tree):
        if isinstance(node, ast.Call) and getattr(node.func, "attr", None) == "get" \
                and len(node.args) == 2 and not isinstance(node.args[0], ast.Constant):
            owner = node.func.value
            name = getattr(owner, "attr", None) or getattr(owner, "id", None)
            if name in SCENE_NAMES:
                yield node.lineno, ast.unparse(node.args[0])


def test_no_scene_read_has_a_fallback():
    """No read of a scene value anywhere in the package passes a fallback, for a parameter with
    a schema default or without one: a parameter without one is either read inside its
    effect's ``if scene.has(...)`` (the effect requires it; the kernel packs a neutral value
    otherwise) or optional, read with ``scene.optional`` where its absence is given a meaning."""
    found = [f"{path.relative_to(PACKAGE.parent)}:{line}: {key}"
             for path in sorted(PACKAGE.rglob("*.py"))
             for line, key in scene_fallbacks(ast.parse(path.read_text()))]
    assert not found, "scene reads with a fallback:\n" + "\n".join(found)


def test_the_fallback_check_finds_every_form():
    tree = ast.parse("scene.get('material.eta', 0.0)\ng(\n    'domain.pad', None)\n"
                     "self.scene.get(path, None)\nscene.get(key)\nds.attrs.get('seed', 0)\n")
    assert sorted(scene_fallbacks(tree)) == [(1, "material.eta"), (2, "domain.pad"),
                                             (4, "path")]


def test_the_check_finds_a_second_default(tmp_path):
    """Each of the three forms is found in a module written for the purpose."""
    module = tmp_path / "engine.py"
    module.write_text(
        "from dataclasses import dataclass\n"
        "def step(scene, data):\n"
        "    return scene.get('numerics.cfl', 0.3), lookup(data, 'numerics.dt_max', 1e-5)\n"
        "@dataclass\n"
        "class Settings:\n"
        "    h_min: float = 0.2\n"
        "def kernels(effects, dim=2):\n"
        "    pass\n")
    global PACKAGE
    saved, PACKAGE = PACKAGE, tmp_path.parent
    try:
        found = second_defaults("impact", [module])
    finally:
        PACKAGE = saved
    assert sorted(f.split(": ", 1)[0].rsplit(":", 1)[1] for f in found) == ["3", "3", "6", "7"]
    assert any("numerics.cfl" in f for f in found) and any("`dim`" in f for f in found)
