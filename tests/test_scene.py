"""Scene loading: validation messages, ``--set`` overrides, defaults, and the same through
the CLI (``craquelure check`` exits non-zero with the message on stderr); a property-based
test of the validation over every built-in scene (its own section below)."""

from __future__ import annotations

import re
from functools import cache
from pathlib import Path

import numba
import pytest
import yaml
from hypothesis import event, given, settings
from hypothesis import strategies as st

from craquelure import cli
from craquelure.api import check
from craquelure.commands.check import format_number
from craquelure.drying.rules import run_step as drying_run_step
from craquelure.errors import CraquelureError, SceneError
from craquelure.lattice.rules import step_estimate as lattice_step_estimate
from craquelure.models import stage
from craquelure.registry import known_effects
from craquelure.scene import (
    apply_override,
    list_scenes,
    load_scene,
    load_scene_text,
    model_schema,
    overrides_from_file,
    parse_override,
    scenes_dir,
)
from craquelure.scene_rules import memory_estimate

CI_SCENE = scenes_dir() / "drying" / "ci.yaml"
NUMERICS = model_schema("drying")["properties"]["numerics"]["properties"]
INTEGRATORS = ", ".join(NUMERICS["integrator"]["enum"])
KERNELS = ", ".join(NUMERICS["kernel"]["enum"])


def ci_text(replace: tuple[str, str] | None = None) -> str:
    text = CI_SCENE.read_text()
    if replace is not None:
        assert replace[0] in text
        text = text.replace(*replace)
    return text


def scene_error(text: str, overrides=()) -> str:
    with pytest.raises(SceneError) as info:
        load_scene_text(text, name="bad", overrides=overrides)
    return str(info.value)


# (description, scene text edit or override, fragments the message must contain)
INVALID = [
    ("unknown top-level key", ("domain:", "colour: red\ndomain:"), None,
     ["unknown key 'colour'", "allowed keys:", "particles"]),
    ("unknown nested key", ("  h: 0.2\n", "  h: 0.2\n  hh: 0.3\n"), None,
     ["numerics: unknown key 'hh'", "allowed keys:", "kernel"]),
    ("unknown effect", ("effects: [elasticity,", "effects: [gravity, elasticity,"), None,
     ["unknown effect 'gravity'", "known effects:", *known_effects("drying")]),
    ("negative h", ("  h: 0.2\n", "  h: -0.2\n"), None, ["numerics.h", "-0.2", "> 0"]),
    ("zero box", ("  box_length: 2.0\n", "  box_length: 0\n"), None,
     ["domain.box_length", "must be > 0"]),
    ("missing effect parameter", ("  eta: 1.0\n", ""), None,
     ["effect 'viscosity' needs material.eta", "does not set"]),
    ("missing required key", ("  h: 0.2\n", ""), None, ["numerics", "'h' is a required"]),
    ("bad enum", ("  kernel: quintic\n", "  kernel: gaussian\n"), None,
     ["numerics.kernel", "'gaussian'", f"allowed values: {KERNELS}", "wendland_c2"]),
    ("bad type", ("  n: 1600\n", "  n: many\n"), None,
     ["particles.n", "'many'", "type integer"]),
    ("bad model", ("model: drying", "model: baking"), None,
     ["model: 'baking'", "allowed values: drying, impact, lattice, softdyn"]),
    ("effect listed twice", ("effects: [elasticity,", "effects: [xsph, elasticity,"), None,
     ["listed twice", "xsph"]),
    ("override: unknown key", None, ["numerics.hh=1"], ["numerics: unknown key 'hh'"]),
    ("override: bad value", None, ["numerics.integrator=euler"],
     ["numerics.integrator", "'euler'", f"allowed values: {INTEGRATORS}", "abm4"]),
    ("override: missing parameter", None, ["material.yield_stress=null"],
     ["material.yield_stress", "None"]),
    ("override: not a section", None, ["numerics.h.x=1"], ["numerics.h is 0.2, not a section"]),
    ("override: no '='", None, ["numerics.h"], ["--set 'numerics.h'", "key.path=value"]),
    ("override: bad YAML", None, ["numerics.h=[1"], ["not valid YAML"]),
    ("override: empty key", None, ["=3"], ["empty key"]),
]


@pytest.mark.parametrize("case", INVALID, ids=[c[0] for c in INVALID])
def test_invalid_scenes_name_the_problem(case):
    _, edit, overrides, fragments = case
    message = scene_error(ci_text(edit), overrides or ())
    for fragment in fragments:
        assert fragment in message, (fragment, message)


def test_not_yaml_or_not_a_mapping():
    assert "not valid YAML" in scene_error("model: [drying\n")
    assert "must be a mapping" in scene_error("- drying\n")


def test_unknown_scene_reference():
    with pytest.raises(SceneError, match="not found.*craquelure scenes"):
        load_scene("drying/no_such_scene")


def test_defaults_are_filled_and_written_into_the_resolved_text():
    scene = load_scene("drying/ci")
    assert scene.model == "drying" and scene.name == "ci"
    assert scene.get("numerics.xsph_epsilon") == 0.5
    assert scene.get("numerics.mass_solve") == {
        "method": "truncated_cg", "rtol": 3e-3, "min_mass_fraction": 0.1,
        "max_iterations": 500, "shepard_spacing": 0.02}
    assert scene.get("domain.periodic") is True
    assert scene.get("particles.excluded_bands") == []
    resolved = yaml.safe_load(scene.text)
    assert resolved == scene.data
    assert resolved["numerics"]["mass_solve"]["rtol"] == 3e-3
    assert scene.has("viscosity") and not scene.has("gravity")
    assert scene.effects[0] == "elasticity"
    assert scene.get("numerics.nothing", 7) == 7
    with pytest.raises(KeyError):
        scene.get("numerics.nothing")


def test_overrides_nested_numbers_lists_and_mappings():
    scene = load_scene("drying/ci", [
        "numerics.h=0.25",
        "numerics.dt=1e-3",  # YAML 1.1 would read this as a string
        "material.yield_stress=5.0e-3",
        "particles.n=900",
        "numerics.mass_solve.rtol=0.01",
        "outputs.times=[1, 2.5, 4]",
        "effects=[elasticity, viscosity]",
        "particles.excluded_bands=[{axis: x, lo: 0.5, hi: 1.0}]",
        "description=a scene with = in it",
        "numerics.kernel=wendland_c2",
    ])
    assert scene.get("numerics.h") == 0.25
    assert scene.get("numerics.dt") == pytest.approx(1e-3)
    assert isinstance(scene.get("numerics.dt"), float)
    assert scene.get("particles.n") == 900 and isinstance(scene.get("particles.n"), int)
    assert scene.get("numerics.mass_solve.rtol") == 0.01
    assert scene.get("numerics.mass_solve.max_iterations") == 500  # sibling default kept
    assert scene.get("outputs.times") == [1, 2.5, 4]
    assert scene.effects == ("elasticity", "viscosity")
    assert scene.get("particles.excluded_bands") == [{"axis": "x", "lo": 0.5, "hi": 1.0}]
    assert scene.get("description") == "a scene with = in it"
    assert scene.get("numerics.kernel") == "wendland_c2"
    assert "h: 0.25" in scene.text
    assert scene.overrides[0] == "numerics.h=0.25"
    # The later override wins; with_overrides stacks on the existing ones.
    assert load_scene("drying/ci", ["numerics.h=0.3", "numerics.h=0.4"]).get("numerics.h") == 0.4
    again = scene.with_overrides(["numerics.h=0.5"])
    assert again.get("numerics.h") == 0.5 and again.get("particles.n") == 900


def test_parse_and_apply_override():
    assert parse_override("a.b.c=1e-3") == (["a", "b", "c"], 1e-3)
    assert parse_override("a= x ") == (["a"], "x")
    assert parse_override("a=") == (["a"], "")
    data = {"a": {"b": 1}}
    apply_override(data, "a.c.d=[1, 2]")
    assert data == {"a": {"b": 1, "c": {"d": [1, 2]}}}


def test_set_file_overrides_in_order_among_set(tmp_path):
    """`--set-file` adds a file's `set` list where it stands among the `--set` arguments: the
    scene (and the overrides its datasets record) as with the same items given as `--set`."""
    path = tmp_path / "settings.yaml"
    path.write_text(yaml.safe_dump({"note": 1, "set": ["numerics.h=0.3", "outputs.times=[1, 2]"]}))
    args = cli.build_parser().parse_args(["run", "drying/ci", "--out", "x.nc",
                                          "--set", "numerics.h=0.2", "--set-file", str(path),
                                          "--set", "outputs.t_end=4"])
    expected = ["numerics.h=0.2", "numerics.h=0.3", "outputs.times=[1, 2]", "outputs.t_end=4"]
    assert args.overrides == expected
    scene = load_scene("drying/ci", args.overrides)
    assert scene.get("numerics.h") == 0.3 and scene.get("outputs.times") == [1, 2]
    assert scene.overrides == tuple(expected)


@pytest.mark.parametrize("text,fragment", [
    ("set: numerics.h=0.3\n", "expected a mapping whose `set` is a list"),
    ("- numerics.h=0.3\n", "expected a mapping whose `set` is a list"),
    ("set: [numerics.h]\n", "--set 'numerics.h': expected key.path=value"),
    ("set: [a: b\n", "not valid YAML"),
])
def test_set_file_errors_name_the_file(tmp_path, capsys, text, fragment):
    path = tmp_path / "settings.yaml"
    path.write_text(text)
    with pytest.raises(SceneError, match="settings.yaml"):
        overrides_from_file(path)
    with pytest.raises(SystemExit) as stop:
        cli.main(["check", "drying/ci", "--set-file", str(path)])
    assert stop.value.code == 2
    err = capsys.readouterr().err
    assert f"--set-file: {path}" in err and fragment in err, err
    with pytest.raises(SystemExit):
        cli.main(["check", "drying/ci", "--set-file", str(tmp_path / "missing.yaml")])
    assert "missing.yaml" in capsys.readouterr().err


def test_builtin_scenes_are_valid_and_listed():
    listed = dict(list_scenes())
    assert "drying/ci" in listed and "drying/default" in listed
    for name, description in listed.items():
        assert description, name
        scene = load_scene(name)
        assert scene.model == name.split("/")[0]


# -- property-based validation -----------------------------------------------------------------
# Property-based test of scene validation over every built-in scene of every model.
#
# A mutation (a value of another type, NaN/inf/huge/zero/negative numbers, a missing or unknown
# key, an edited effect list, broken YAML syntax or bytes) must end in one of two ways:
#
# - a :class:`SceneError` whose message names a key of the scene (or says the YAML is broken),
#   never another exception;
# - an accepted scene whose derived numbers ``craquelure check`` prints without raising and
#   that a short run (a few steps) handles: it finishes, or stops with a
#   :class:`~craquelure.errors.CraquelureError` (the guard's message); either way it leaves no
#   file but its dataset.
#
# CI cost: the default (derandomised) profile draws 400 validation examples (~15 s) and 30
# short runs on the small scenes (~30 s once the kernels are compiled); `pytest
# --hypothesis-profile thorough tests/test_scene.py -k mutated` draws ten times as many at random.
# Short runs keep the built-in effect list (a new list compiles new kernels, ~20 s each); the
# validation examples mutate effect lists freely.

SCENES = [name for name, _ in list_scenes()]
# small scenes for the short runs (every model, a few seconds each)
RUN_SCENES = ["drying/ci", "drying/accuracy", "impact/ci", "lattice/glen", "lattice/creep_slab",
              "softdyn/t1_single_ci", "softdyn/two_sphere_approach",
              "softdyn/two_sphere_separation"]

VALUES = [".nan", ".inf", "-.inf", "1e400", "-1e400", "1e300", "-1e300", "1e-300", "0", "-1",
          "0.0", "1.5", "1.6e3", "100000000000000000000", "9223372036854775808", "abc", "''",
          "true", "null", "[]", "{}", "[1, .nan]", "[.inf]", "{a: 1}", "'5'", "2", "7", "-0.5",
          "1e12", "1e-12", "3"]
BROKEN_CHARS = list(":{}[]&*!|>'\"%@`\t-?,#\x00\ufeff\x85")


def leaf_paths(node, prefix=""):
    """Dotted paths of the mapping leaves of a resolved scene (lists are leaves)."""
    if isinstance(node, dict):
        for key, value in node.items():
            yield from leaf_paths(value, f"{prefix}.{key}" if prefix else str(key))
    elif prefix:
        yield prefix


def mapping_paths(node, prefix=""):
    if isinstance(node, dict):
        yield prefix
        for key, value in node.items():
            yield from mapping_paths(value, f"{prefix}.{key}" if prefix else str(key))


@cache
def schema_keys(model: str) -> set[str]:
    """Every property name of the model's schema (a message naming one names a key)."""
    names: set[str] = set()

    def walk(node):
        if isinstance(node, dict):
            names.update(node.get("properties", {}))
            for value in node.values():
                walk(value)
        elif isinstance(node, list):
            for value in node:
                walk(value)

    walk(model_schema(model))
    return names | {"model", "effects", "precracks"}


def names_a_key(message: str, model: str | None, mutated: str | None) -> bool:
    if "YAML" in message or "duplicate key" in message or "top level" in message:
        return True
    if message.startswith("scene too large"):
        return True  # no single key: the message says how much memory the scene needs
    if mutated and mutated.split(".")[-1] in message:
        return True
    keys = schema_keys(model) if model in ("drying", "impact", "lattice", "softdyn") else {
        "model"}
    return any(re.search(rf"(^|[\s.'\"]){re.escape(k)}([.:\[\s'\"]|$)", message) for k in keys)


@cache
def builtin(name: str):
    return load_scene(name)


def scene_data(name: str) -> tuple[dict, str]:
    scene = builtin(name)
    return yaml.safe_load(scene.source_text), scene.source_text


def _delete(data: dict, path: str) -> None:
    keys = path.split(".")
    node = data
    for key in keys[:-1]:
        node = node[key]
    del node[keys[-1]]


def _node(data: dict, path: str) -> dict:
    for key in [k for k in path.split(".") if k]:
        data = data[key]
    return data


SCALES = [0.0, 1e-12, 1e-3, 0.5, 2.0, 10.0, 1e3, 1e6, -1.0]


def numeric_paths(node, prefix=""):
    """Dotted paths of the numbers (not booleans) among the mapping leaves."""
    for path in leaf_paths(node, prefix):
        value = _node_value(node, path)
        if isinstance(value, int | float) and not isinstance(value, bool):
            yield path


def _node_value(data, path):
    for key in path.split("."):
        data = data[key]
    return data


@st.composite
def mutations(draw, names=SCENES, effect_mutations=True, syntax=True, kinds=None):
    """(scene name, YAML text, overrides, mutated key or None, kind). Kinds: ``value`` (a
    special value or another type), ``scale`` (a number times 0, 1e-12 ... 1e6 or -1),
    ``delete``, ``unknown`` (key), ``effects``, ``syntax`` (YAML text or bytes)."""
    name = draw(st.sampled_from(names))
    raw, text = scene_data(name)
    resolved = builtin(name).data
    if kinds is None:
        kinds = ["value", "value", "scale", "delete", "unknown"]
        if effect_mutations:
            kinds += ["effects"]
        if syntax:
            kinds += ["syntax"]
    kind = draw(st.sampled_from(kinds))
    overrides: list[str] = []
    mutated = None
    if kind == "scale":
        for _ in range(draw(st.integers(1, 2))):
            mutated = draw(st.sampled_from(sorted(numeric_paths(resolved))))
            value = _node_value(resolved, mutated) * draw(st.sampled_from(SCALES))
            if isinstance(_node_value(resolved, mutated), int):
                value = int(value)
            overrides.append(f"{mutated}={value!r}")
    elif kind == "value":
        mutated = draw(st.sampled_from(sorted(leaf_paths(resolved))))
        if mutated == "effects" or mutated == "model":
            mutated = "model" if draw(st.booleans()) else "effects"
        count = draw(st.integers(1, 2))
        for _ in range(count):
            overrides.append(f"{mutated}={draw(st.sampled_from(VALUES))}")
        if draw(st.booleans()):  # a second key changed as well
            other = draw(st.sampled_from(sorted(leaf_paths(resolved))))
            overrides.append(f"{other}={draw(st.sampled_from(VALUES))}")
    elif kind == "delete":
        mutated = draw(st.sampled_from(sorted(leaf_paths(raw))))
        _delete(raw, mutated)
        text = yaml.safe_dump(raw, sort_keys=False)
    elif kind == "unknown":
        parent = draw(st.sampled_from(sorted(mapping_paths(raw))))
        mutated = draw(st.sampled_from(["bogus_key", "dt", "n", "t_end", "yield_stress"]))
        _node(raw, parent)[mutated] = draw(st.sampled_from([1.0, "x", None, [1], {"a": 1}]))
        text = yaml.safe_dump(raw, sort_keys=False)
    elif kind == "effects":
        mutated = "effects"
        effects = list(raw["effects"])
        model = raw["model"]
        choice = draw(st.sampled_from(["empty", "duplicate", "unknown", "drop", "other",
                                       "not_a_list"]))
        if choice == "empty":
            effects = []
        elif choice == "duplicate":
            effects.append(draw(st.sampled_from(effects)))
        elif choice == "unknown":
            effects.append("warp_drive")
        elif choice == "drop" and len(effects) > 1:
            effects.remove(draw(st.sampled_from(effects)))
        elif choice == "other":
            effects.append(draw(st.sampled_from(sorted(known_effects(model)))))
        else:
            effects = draw(st.sampled_from(["elasticity", 3, None, {"a": 1}]))
        raw["effects"] = effects
        text = yaml.safe_dump(raw, sort_keys=False)
    else:
        how = draw(st.sampled_from(["truncate", "insert", "bytes", "duplicate_line", "nul"]))
        if how == "truncate":
            text = text[: draw(st.integers(0, len(text)))]
        elif how == "insert":
            at = draw(st.integers(0, len(text)))
            text = text[:at] + draw(st.sampled_from(BROKEN_CHARS)) + text[at:]
        elif how == "bytes":
            text = draw(st.binary(min_size=0, max_size=200)).decode("latin-1")
        elif how == "duplicate_line":
            lines = text.splitlines(keepends=True)
            at = draw(st.integers(0, len(lines) - 1))
            lines.insert(at, lines[at])
            text = "".join(lines)
        else:
            text = "\x00" + text
    return name, text, overrides, mutated, kind


def validate(name: str, text: str, overrides: list[str], mutated: str | None):
    """The accepted scene, or None after checking that the SceneError names a key; any other
    exception fails the test."""
    try:
        return load_scene_text(text, name=name.split("/")[-1], overrides=overrides)
    except SceneError as exc:
        message = str(exc)
        model = name.split("/")[0]
        assert names_a_key(message, model, mutated), message
        return None


@given(mutations())
def test_mutated_scene_is_rejected_naming_the_key_or_checkable(case):
    name, text, overrides, mutated, _ = case
    scene = validate(name, text, overrides, mutated)
    if scene is None:
        return
    numbers = check(scene)  # must not raise
    for value in numbers.values():
        format_number(value)


def short_version(scene):
    """The same scene run for a few steps (the step it would take, times 3-5)."""
    model, g = scene.model, scene.get
    if model == "drying":
        t = 3 * drying_run_step(scene.data)
        return scene.with_overrides([f"outputs.t_end={t!r}", f"outputs.times=[{t!r}]"])
    if model == "impact":
        from craquelure.impact.api import settings as impact_settings
        from craquelure.impact.initial_state import initial_smoothing_length

        s = impact_settings(scene)
        dt = min(s.dt_max, s.cfl * initial_smoothing_length(scene)
                 / (s.wave_speed + abs(g("particles.impact_velocity"))))
        return scene.with_overrides([f"outputs.t_end={min(g('outputs.t_end'), 5 * dt)!r}",
                                     "outputs.snapshot_times=[]"])
    if model == "lattice":
        t = min(g("outputs.t_end"), 5 * lattice_step_estimate(scene.data))
        return scene.with_overrides([f"outputs.t_end={t!r}", "outputs.frames=1",
                                     "numerics.checkpoint_every=0"])
    t = min(g("outputs.t_end"), 0.01)
    if g("numerics.integrator") == "heun" and g("numerics.dt", None):
        t = min(g("outputs.t_end"), 5 * g("numerics.dt"))
    return scene.with_overrides([f"outputs.t_end={t!r}", "study.kind=single"])


BASE_MEMORY = {name: memory_estimate(load_scene(name).data)[0] for name in RUN_SCENES}


# a short run costs ~10x a validation: a quarter of the profile's examples (100 in CI)
@pytest.mark.slow
@settings(max_examples=max(1, settings.default.max_examples // 4))
@given(case=mutations(names=RUN_SCENES, kinds=["scale", "scale", "scale", "value"]))
def test_accepted_mutated_scene_runs_or_stops_with_a_named_error(case, tmp_path_factory):
    name, text, overrides, mutated, _ = case
    scene = validate(name, text, overrides, mutated)
    if scene is None:
        event("rejected with a named SceneError")
        return
    if memory_estimate(scene.data)[0] > 4 * BASE_MEMORY[name] + 2**24:
        event("accepted, too large for a short run")
        return  # a much larger scene: validated and checked above, too slow for a short run
    check(scene)
    try:
        short = short_version(scene)
    except SceneError as exc:  # shortening broke a cross-field rule: still a named error
        assert names_a_key(str(exc), scene.model, mutated), str(exc)
        return
    folder = tmp_path_factory.mktemp("run")
    out = folder / "run.nc"
    numba.set_num_threads(1)
    try:
        stage(short.model, "run")(short, out, seed=1)
    except CraquelureError as exc:  # the guard (SimulationDiverged) or another named stop
        event(f"accepted, run stopped: {type(exc).__name__}")
        assert str(exc).strip()
        assert sorted(p.name for p in folder.iterdir()) == [], "a stopped run left files"
        return
    event("accepted, run finished")
    assert out.exists()
    assert sorted(p.name for p in folder.iterdir()) == ["run.nc"], "left files behind"


def test_mutations_cover_every_model_and_kind():
    """The strategy reaches every model and every kind of mutation (else the property above
    would be vacuous for some)."""
    seen_models, seen_kinds = set(), set()

    @settings(max_examples=200)
    @given(mutations())
    def collect(case):
        seen_models.add(case[0].split("/")[0])
        seen_kinds.add(case[4])

    collect()
    assert seen_models == {"drying", "impact", "lattice", "softdyn"}
    assert seen_kinds == {"value", "scale", "delete", "unknown", "effects", "syntax"}


@pytest.mark.parametrize("override, key", [
    ("material.yield_stress=.nan", "material.yield_stress"),
    ("material.yield_stress=1e400", "material.yield_stress"),
    ("material.lame_lambda=.inf", "material.lame_lambda"),
    ("outputs.times=[1, .nan]", "outputs.times[1]"),
    ("particles.n=1.6e3", "particles.n"),
    ("particles.n=true", "particles.n"),
    ("effects=[]", "effects"),
    ("numerics.dt=8.5", "numerics.dt"),
    ("outputs.times=[2, 9]", "outputs.times"),
])
def test_drying_bad_values_are_named(override, key):
    with pytest.raises(SceneError) as err:
        load_scene("drying/ci", [override])
    assert key in str(err.value)


def test_finite_check_reaches_nested_lists_and_mappings():
    with pytest.raises(SceneError, match=r"precracks\.bad\[0\]\[1\]\[0\]: nan"):
        load_scene("impact/ci", ["precracks.bad=[[[0, 0], [.nan, 1]]]"])
    with pytest.raises(SceneError, match=r"study\.fh_over_fv\[0\]: inf"):
        load_scene("softdyn/t1_phase_ci", ["study.fh_over_fv=[.inf]"])
    with pytest.raises(SceneError, match=r"numerics\.rtol: nan"):
        load_scene("softdyn/t1_single_ci", ["numerics.rtol=.nan"])


def test_duplicate_keys_are_an_error():
    text = Path(load_scene("drying/ci").path).read_text() + "\noutputs: {t_end: 3.0}\n"
    with pytest.raises(SceneError, match="outputs: duplicate key"):
        load_scene_text(text)


def test_schema_default_reads_the_schema_and_names_what_is_missing():
    from craquelure.scene import schema_default

    assert schema_default("lattice", "contact.skin") == 0.2
    with pytest.raises(KeyError, match="no default"):
        schema_default("lattice", "contact.stiffness")
    with pytest.raises(KeyError, match="no field"):
        schema_default("lattice", "contact.nonsense")
