"""Scene loading: validation messages, ``--set`` overrides, defaults, and the same through
the CLI (``craquelure check`` exits non-zero with the message on stderr)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest
import yaml

from craquelure import cli
from craquelure.errors import SceneError
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


# --- the same through the CLI -------------------------------------------------------------


def write_scene(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "scene.yaml"
    path.write_text(text)
    return path


@pytest.mark.parametrize("case", INVALID, ids=[c[0] for c in INVALID])
def test_cli_check_rejects_invalid_scenes(case, tmp_path, capsys):
    _, edit, overrides, fragments = case
    path = write_scene(tmp_path, ci_text(edit))
    argv = ["check", str(path)]
    for item in overrides or ():
        argv += ["--set", item]
    assert cli.main(argv) == 2
    out, err = capsys.readouterr()
    assert err.startswith("craquelure check: error: ")
    for fragment in fragments:
        assert fragment in err, (fragment, err)
    assert "valid" not in out


def test_cli_check_valid_scene_prints_resolved_scene_effects_and_numbers(capsys):
    assert cli.main(["check", "drying/ci", "--set", "numerics.dt=2e-3"]) == 0
    out, _ = capsys.readouterr()
    assert "# scene ci (model drying): valid" in out
    assert "dt: 0.002" in out
    assert "xsph_epsilon: 0.5" in out  # defaults are shown
    for name in load_scene("drying/ci").effects:
        assert f"  {name} " in out
    assert "neighbours per particle: 49.2" in out  # N pi h^2 / L^2 - 1 = 1600 pi 0.04 / 4 - 1
    assert "steps: 4000" in out  # t_end / dt = 8 / 0.002


def test_cli_subprocess_exit_code_and_stderr(tmp_path):
    path = write_scene(tmp_path, ci_text(("  h: 0.2\n", "  h: -0.2\n")))
    proc = subprocess.run([sys.executable, "-m", "craquelure", "check", str(path)],
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode != 0
    assert "numerics.h: -0.2 is not allowed; must be > 0" in proc.stderr
    assert "Traceback" not in proc.stderr
    proc = subprocess.run([sys.executable, "-m", "craquelure", "scenes"],
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0 and "drying/ci" in proc.stdout
