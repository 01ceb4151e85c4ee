"""Scene files: load, override, validate.

A scene is a YAML file ``config/scenes/<model>/<name>.yaml`` with the sections ``model``,
``description``, ``domain``, ``particles``, ``material``, ``numerics``, ``outputs`` and an
explicit ``effects`` list. Each model has a JSON schema (``craquelure/schemas/<model>.yaml``)
that rejects unknown keys and out-of-range values; the effect registry
(:mod:`craquelure.registry`) rejects unknown effects and effects whose parameters are missing.
Every error names the key, the bad value and what is allowed. Defaults from the schema are
filled in, so the resolved scene (``Scene.text``) states every number a run used.
"""

from __future__ import annotations

import copy
import re
from dataclasses import dataclass, field
from functools import cache
from importlib import resources
from pathlib import Path
from typing import Any

import jsonschema
import yaml

from craquelure import scene_rules
from craquelure.errors import SceneError
from craquelure.models import MODELS
from craquelure.registry import known_effects


class _SceneLoader(yaml.SafeLoader):
    """SafeLoader that also reads ``1e-3`` and ``1.0e6`` as floats (YAML 1.2; PyYAML's YAML 1.1
    resolver needs a dot and a signed exponent) and refuses a key given twice in one mapping."""

    def construct_mapping(self, node, deep=False):
        seen: dict[Any, int] = {}
        for key_node, _ in node.value:
            key = self.construct_object(key_node, deep=True)
            try:
                hash(key)
            except TypeError:
                continue  # the base class reports unhashable keys
            line = key_node.start_mark.line + 1
            if key in seen:
                raise SceneError(f"{key}: duplicate key (lines {seen[key]} and {line}); "
                                 f"give each key once")
            seen[key] = line
        return super().construct_mapping(node, deep=deep)


_SceneLoader.add_implicit_resolver("tag:yaml.org,2002:float", re.compile(
    r"^[-+]?(?:[0-9][0-9_]*(?:\.[0-9_]*)?|\.[0-9_]+)[eE][-+]?[0-9]+$"), list("-+0123456789."))


def _load_yaml(text: str):
    return yaml.load(text, Loader=_SceneLoader)  # a SafeLoader subclass: no arbitrary objects


def _is_integer(checker, instance) -> bool:
    """A true integer: JSON schema's own ``integer`` accepts 1600.0 (and YAML reads 1.6e3 as a
    float), which crashed ``np.empty`` later; booleans are not integers either."""
    return isinstance(instance, int) and not isinstance(instance, bool)


_Validator = jsonschema.validators.extend(jsonschema.Draft202012Validator, type_checker=(
    jsonschema.Draft202012Validator.TYPE_CHECKER.redefine("integer", _is_integer)))


def project_root() -> Path:
    """The checkout this package lives in (editable install), else the working directory."""
    root = Path(__file__).resolve().parents[2]
    return root if (root / "config" / "scenes").is_dir() else Path.cwd()


def scenes_dir() -> Path:
    return project_root() / "config" / "scenes"


@dataclass(frozen=True)
class Scene(scene_rules.SceneAccess):
    """A validated scene: ``data`` is the resolved mapping (defaults and overrides applied)."""

    name: str
    data: dict[str, Any]
    source_text: str
    overrides: tuple[str, ...] = ()
    path: Path | None = None
    text: str = field(default="", compare=False)

    def with_overrides(self, overrides: list[str] | tuple[str, ...]) -> Scene:
        """A new validated scene with more ``key.path=value`` overrides applied."""
        return load_scene_text(self.source_text, name=self.name,
                               overrides=(*self.overrides, *overrides), path=self.path)


@cache
def model_schema(model: str) -> dict[str, Any]:
    text = resources.files("craquelure").joinpath(f"schemas/{model}.yaml").read_text()
    return yaml.safe_load(text)


def schema_default(model: str, dotted: str) -> Any:
    """The default the model's schema gives ``dotted`` (e.g. ``contact.skin``); KeyError if it
    gives none."""
    node = model_schema(model)
    for key in dotted.split("."):
        node = node.get("properties", {}).get(key)
        if node is None:
            raise KeyError(f"{model} schema has no field {dotted!r}")
    if "default" not in node:
        raise KeyError(f"{model} schema gives {dotted!r} no default")
    return copy.deepcopy(node["default"])


def resolve_scene_path(ref: str | Path) -> Path:
    """A path to a YAML file, or a built-in scene name such as ``drying/default``."""
    path = Path(ref)
    if path.is_file():
        return path
    builtin = scenes_dir() / f"{ref}.yaml"
    if builtin.is_file():
        return builtin
    raise SceneError(f"scene {str(ref)!r} not found: give a YAML file or a built-in scene "
                     f"(`craquelure scenes` lists them)")


def load_scene(ref: str | Path, overrides: list[str] | tuple[str, ...] = ()) -> Scene:
    path = resolve_scene_path(ref)
    return load_scene_text(path.read_text(), name=path.stem, overrides=overrides, path=path)


def load_scene_text(text: str, name: str = "scene", overrides: list[str] | tuple[str, ...] = (),
                    path: Path | None = None) -> Scene:
    try:
        data = _load_yaml(text)
    except SceneError as exc:
        raise SceneError(f"scene {name}: {exc}") from exc
    except (yaml.YAMLError, ValueError, TypeError, RecursionError) as exc:  # NUL byte, huge date
        raise SceneError(f"scene {name}: not valid YAML: {exc}") from exc
    if not isinstance(data, dict):
        raise SceneError(f"scene {name}: the top level must be a mapping of sections")
    for item in overrides:
        apply_override(data, item)
    data = validate_scene_data(data)
    resolved = yaml.safe_dump(data, sort_keys=False)
    return Scene(name=name, data=data, source_text=text, overrides=tuple(overrides),
                 path=path, text=resolved)


def stored_scene(text: str, name: str = "scene") -> Scene:
    """The resolved scene a dataset carries (its ``scene`` attribute), read back as it was
    written: not re-validated against today's schema (a key renamed since must not make an
    archived dataset unreadable). Only parameters added since are filled in, with the schema's
    default (which keeps the earlier behaviour): readers keep no fallbacks of their own."""
    try:
        data = _load_yaml(text)
    except (yaml.YAMLError, SceneError, ValueError, TypeError) as exc:
        raise SceneError(f"stored scene {name}: not valid YAML: {exc}") from exc
    if not isinstance(data, dict) or "model" not in data:
        raise SceneError(f"stored scene {name}: not a resolved scene (no `model` section)")
    data.setdefault("effects", [])
    if data["model"] in MODELS:
        _fill_defaults(data, model_schema(data["model"]))
    return Scene(name=name, data=data, source_text=text, text=text)


def parse_override(item: str) -> tuple[list[str], Any]:
    if "=" not in item:
        raise SceneError(f"--set {item!r}: expected key.path=value")
    key, raw = item.split("=", 1)
    keys = [k for k in key.strip().split(".") if k]
    if not keys:
        raise SceneError(f"--set {item!r}: empty key")
    try:
        value = _load_yaml(raw) if raw.strip() else ""
    except (yaml.YAMLError, SceneError, ValueError, TypeError, RecursionError) as exc:
        raise SceneError(f"--set {item!r}: value is not valid YAML: {exc}") from exc
    return keys, value


def overrides_from_file(path: str | Path) -> list[str]:
    """The ``set`` list of a YAML file: ``key.path=value`` strings as for ``--set`` (e.g. the
    settings a workflow job derived for a run)."""
    path = Path(path)
    try:
        data = yaml.safe_load(path.read_text())
    except yaml.YAMLError as exc:
        raise SceneError(f"{path}: not valid YAML: {exc}") from exc
    items = data.get("set") if isinstance(data, dict) else None
    if not isinstance(items, list) or not all(isinstance(item, str) for item in items):
        raise SceneError(f"{path}: expected a mapping whose `set` is a list of "
                         f"key.path=value strings")
    for item in items:
        try:
            parse_override(item)
        except SceneError as exc:
            raise SceneError(f"{path}: {exc}") from exc
    return items


def apply_override(data: dict[str, Any], item: str) -> None:
    """Set ``data[a][b][c] = value`` for ``a.b.c=value`` (intermediate mappings are created;
    the schema then rejects keys that do not exist)."""
    keys, value = parse_override(item)
    node = data
    for depth, key in enumerate(keys[:-1]):
        nxt = node.setdefault(key, {})
        if not isinstance(nxt, dict):
            where = ".".join(keys[: depth + 1])
            raise SceneError(f"--set {item!r}: {where} is {nxt!r}, not a section")
        node = nxt
    node[keys[-1]] = value


def _fill_defaults(node: Any, schema: dict[str, Any]) -> None:
    if not isinstance(node, dict):
        return
    for key, sub in schema.get("properties", {}).items():
        if key not in node and "default" in sub:
            node[key] = copy.deepcopy(sub["default"])
        if key in node and sub.get("type") == "object":
            _fill_defaults(node[key], sub)


def _path(error: jsonschema.ValidationError) -> str:
    return ".".join(str(p) for p in error.absolute_path) or "(top level)"


def _describe(error: jsonschema.ValidationError) -> str:
    where, value, kind = _path(error), error.instance, error.validator
    if kind == "additionalProperties":
        allowed = sorted(error.schema.get("properties", {}))
        extra = sorted(set(value) - set(allowed))
        return (f"{where}: unknown key {', '.join(map(repr, extra))}; "
                f"allowed keys: {', '.join(allowed)}")
    if kind == "enum":
        return (f"{where}: {value!r} is not allowed; allowed values: "
                f"{', '.join(map(str, error.validator_value))}")
    if kind == "required":
        return f"{where}: {error.message}"
    bounds = {"minimum": ">=", "exclusiveMinimum": ">", "maximum": "<=", "exclusiveMaximum": "<"}
    if kind in bounds:
        return f"{where}: {value!r} is not allowed; must be {bounds[kind]} {error.validator_value}"
    if kind == "type":
        return f"{where}: {value!r} is not allowed; must be of type {error.validator_value}"
    if kind == "anyOf" and "description" in error.schema:
        return f"{where}: {value!r} is not allowed; allowed: {error.schema['description']}"
    return f"{where}: {value!r} is not allowed: {error.message}"


def validate_scene_data(data: dict[str, Any], check_memory: bool = True) -> dict[str, Any]:
    """Validate a scene and return a resolved copy (defaults filled in), in this order:
    finite numbers everywhere, the model's schema (types, true integers, bounds), the effect
    registry, then the cross-field rules and the memory estimate of
    :mod:`craquelure.scene_rules`. Raises :class:`SceneError` naming every bad key."""
    data = copy.deepcopy(data)
    model = data.get("model")
    if model not in MODELS:
        raise SceneError(f"model: {model!r} is not allowed; allowed values: {', '.join(MODELS)}")
    bad = scene_rules.non_finite_values(data)
    if bad:
        raise SceneError("invalid scene:\n  " + "\n  ".join(
            f"{key}: {value!r} is not allowed; must be a finite number (integers within "
            f"+-2^63)" for key, value in bad))
    schema = model_schema(model)
    _fill_defaults(data, schema)
    validator = _Validator(schema)
    errors = sorted(validator.iter_errors(data), key=lambda e: (len(e.absolute_path), _path(e)))
    if errors:
        raise SceneError("invalid scene:\n  " + "\n  ".join(_describe(e) for e in errors))
    _check_effects(data)
    problems = scene_rules.cross_field_problems(data)
    if problems:
        raise SceneError("invalid scene:\n  " + "\n  ".join(problems))
    if check_memory:
        problem = scene_rules.memory_problem(data)
        if problem:
            raise SceneError(f"scene too large: {problem}")
    return data


def _check_effects(data: dict[str, Any]) -> None:
    model, listed = data["model"], data["effects"]
    known = known_effects(model)
    unknown = [e for e in listed if e not in known]
    if unknown:
        raise SceneError(f"effects: unknown effect {', '.join(map(repr, unknown))} for model "
                         f"{model!r}; known effects: {', '.join(known) or '(none)'}")
    if len(set(listed)) != len(listed):
        twice = sorted({e for e in listed if listed.count(e) > 1})
        raise SceneError(f"effects: listed twice: {twice}")
    problems = []
    for name in listed:
        effect = known[name]
        for dotted in effect.requires:
            if scene_rules.SceneView(data).optional(dotted) is None:
                problems.append(f"effect {name!r} needs {dotted}, which the scene does not set")
        for other in effect.conflicts:
            if other in listed:
                problems.append(f"effects {name!r} and {other!r} cannot run together")
    if problems:
        raise SceneError("invalid scene:\n  " + "\n  ".join(problems))


def list_scenes() -> list[tuple[str, str]]:
    """Built-in scenes as (``model/name``, one-line description)."""
    out = []
    for path in sorted(scenes_dir().glob("*/*.yaml")):
        try:
            desc = (yaml.safe_load(path.read_text()) or {}).get("description", "")
        except yaml.YAMLError:
            desc = "(unreadable YAML)"
        out.append((f"{path.parent.name}/{path.stem}", " ".join(str(desc).split())))
    return out
