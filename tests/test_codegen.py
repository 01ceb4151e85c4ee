"""One cache root for every engine's generated kernels ($CRAQUELURE_CACHE)."""

from __future__ import annotations

import ast
import importlib
import inspect
import subprocess
from pathlib import Path

import numpy as np
import pytest

from craquelure import codegen, registry
from craquelure.errors import SceneError
from craquelure.io import open_dataset
from craquelure.registry import kernel_parameters, known_effects, parameter_vector


def test_generated_dir_is_a_subfolder_of_the_cache_root(tmp_path, monkeypatch):
    monkeypatch.setenv("CRAQUELURE_CACHE", str(tmp_path / "root"))
    path = codegen.generated_dir("sph")
    assert path == tmp_path / "root" / "sph"
    assert path.is_dir()


def test_import_generated_writes_atomically_and_imports(tmp_path):
    path = tmp_path / "mod_a.py"
    module = codegen.import_generated("VALUE = 42\n", "craquelure_test_generated_a", path)
    assert module.VALUE == 42
    assert path.read_text() == "VALUE = 42\n"
    assert [p.name for p in tmp_path.iterdir()] == ["mod_a.py"]  # no temporary file left


def _package(root, fragment_body):
    pkg = root / "craquelure_codegen_probe"
    pkg.mkdir(exist_ok=True)
    (pkg / "__init__.py").write_text("")
    (pkg / "fragment.py").write_text(fragment_body)
    (pkg / "template.py").write_text(
        "from craquelure_codegen_probe.fragment import term\n\n"
        "# BEGIN FLAGS\nGRAVITY = True\n# END FLAGS\n\n\n"
        "def rate(x):\n    return term(x) if GRAVITY else 0.0\n")


def test_changed_fragment_source_makes_a_new_module(tmp_path, monkeypatch):
    monkeypatch.setenv("CRAQUELURE_CACHE", str(tmp_path / "cache"))
    monkeypatch.syspath_prepend(str(tmp_path))
    _package(tmp_path, "def term(x):\n    return 2.0 * x\n")
    codegen.specialise.cache_clear()
    first = codegen.specialise("craquelure_codegen_probe.template", {"GRAVITY": True}, "probe")
    assert codegen.specialise("craquelure_codegen_probe.template", {"GRAVITY": True},
                              "probe") is first
    _package(tmp_path, "def term(x):\n    return 3.0 * x\n")  # edit the fragment only
    codegen.specialise.cache_clear()
    second = codegen.specialise("craquelure_codegen_probe.template", {"GRAVITY": True}, "probe")
    assert second.__name__ != first.__name__
    assert Path(second.__file__) != Path(first.__file__)
    # same template text: the new name comes from the fragment's source alone
    assert Path(second.__file__).read_text() == Path(first.__file__).read_text()
    assert sorted(p.name for p in (tmp_path / "cache" / "probe").glob("*.py")) == sorted(
        [Path(first.__file__).name, Path(second.__file__).name])
    codegen.specialise.cache_clear()


def test_flags_must_match_the_template(tmp_path, monkeypatch):
    monkeypatch.syspath_prepend(str(tmp_path))
    _package(tmp_path, "def term(x):\n    return x\n")
    with pytest.raises(RuntimeError, match="GRAVITY"):
        codegen.generate("craquelure_codegen_probe.template", {"GRAVITY": True, "DRAG": False})
    with pytest.raises(RuntimeError, match="flag block"):
        codegen.generate("craquelure_codegen_probe.template", {})


TEMPLATES = {
    "drying": ("craquelure.drying.kernel_template", {"KERNEL": 0}),
    "impact": ("craquelure.impact.kernel_template", {"PERIODIC": False, "PLANE_STRESS": False,
                                                      "DIM": 2}),
    "lattice": ("craquelure.lattice.kernel_template", {
        "PERIODIC_X": False, "NODE_AVERAGED": False, "BENDING": False, "PARALLEL": False}),
    "softdyn": ("craquelure.softdyn.kernel_template", {"LITERAL_DEFLECTION": False}),
}


@pytest.mark.parametrize("model", sorted(TEMPLATES))
def test_absent_effect_flag_is_false_in_the_generated_module(model, tmp_path, monkeypatch):
    monkeypatch.setenv("CRAQUELURE_CACHE", str(tmp_path))
    template, options = TEMPLATES[model]
    flagged = {name: e.flag for name, e in known_effects(model).items() if e.flag}
    present = sorted(flagged)[0]
    flags = {**codegen.effect_flags(model, [present]), **options}
    module = codegen.specialise(template, flags, model)
    assert getattr(module, flagged[present]) is True
    for name, flag in flagged.items():
        if name != present:
            assert getattr(module, flag) is False, (name, flag)


def test_every_effect_flag_is_a_template_flag():
    """The registry and the templates agree: each declared flag exists in its template."""
    for model, (template, options) in TEMPLATES.items():
        flags = {**codegen.effect_flags(model, []), **options}
        codegen.generate(template, flags)  # raises if the flag sets differ


def test_unknown_effect_is_rejected():
    with pytest.raises(SceneError, match="unknown effect 'gravity'"):
        codegen.effect_flags("softdyn", ["lubrication_normal", "gravity"])


def _index_constants(module) -> dict[str, str]:
    """{constant: parameter name} for every ``A, B = param_indices(PARAMS, "a", "b")`` and
    ``NAME = PARAMS.index("name")`` in a template."""
    found = {}
    for node in ast.parse(inspect.getsource(module)).body:
        if not isinstance(node, ast.Assign) or not isinstance(node.value, ast.Call):
            continue
        targets = node.targets[0]
        names = targets.elts if isinstance(targets, ast.Tuple) else [targets]
        func = node.value.func
        if isinstance(func, ast.Name) and func.id == "param_indices":
            params = node.value.args[1:]
        elif (isinstance(func, ast.Attribute) and func.attr == "index"
              and getattr(func.value, "id", None) == "PARAMS"):
            params = node.value.args
        else:
            continue
        for target, value in zip(names, params, strict=True):
            found[target.id] = value.value
    return found


class EveryEffectScene:
    """Every effect on; each scene path a model declares reads the distinct value ``values``
    gives its parameter (a vector parameter: one per entry)."""

    def __init__(self, model, values):
        self.paths = {p.path: values[name] for name, (p, _) in kernel_parameters(model).items()
                      if p.path and p.kernel}

    def get(self, path):
        return self.paths[path]

    optional = get

    def has(self, effect):
        return True


def _distinct_values(model):
    """{parameter: value}: 0.5, 1.5, ... one per entry; the expected vector."""
    values, expected = {}, []
    for name, (p, _) in kernel_parameters(model).items():
        if p.kernel:
            entries = [0.5 + len(expected) + k for k in range(p.size)]
            values[name] = entries if p.size > 1 else entries[0]
            expected += entries
    return values, np.array(expected)


def _pack_drying(values):
    from craquelure.drying.engine import parameters
    return parameters(EveryEffectScene("drying", values))


def _pack_lattice(values):
    return parameter_vector("lattice", values=values)


def _pack_softdyn(values):
    from craquelure.softdyn.engine import Engine, Flags
    system = Engine(
        x0=np.array([[0.0, 0.0], [2.0, 0.0]]), pairs=np.array([[0, 1]]), F0=np.zeros((2, 2)),
        radius=values["R"], viscosity=values["eta"], young=values["E"], k_n=values["k_n"],
        k_t=values["k_t"], c_n=values["c_n"], c_t=values["c_t"],
        tau_baumgarte=1.0 / values["inv_tau_B"], ramp_time=values["t_r"],
        flags=Flags(("lubrication_normal", "lubrication_tangential", "hertz")),
        linear_solver="dense")
    return system.p


def _pack_impact(values):
    return registry.parameter_vector("impact", values=values)


@pytest.mark.parametrize(("model", "pack"), [
    ("drying", _pack_drying), ("impact", _pack_impact), ("lattice", _pack_lattice),
    ("softdyn", _pack_softdyn)])
def test_every_parameter_has_one_index_and_packing_puts_it_there(model, pack):
    """Parameters declared once, by the effects: the template's PARAMS are the registry's, its
    index constants name each parameter once, and the engine's packing puts every value (each
    from its scene path or given by name) at the entry its index constant reads."""
    template = importlib.import_module(f"craquelure.{model}.kernel_template")
    assert template.PARAMS == registry.parameter_names(model)
    consts = _index_constants(template)
    firsts = [name for name in template.PARAMS if "[" not in name]
    assert sorted(consts.values()) == sorted(firsts)  # each parameter exactly once
    values, expected = _distinct_values(model)
    assert np.array_equal(pack(values), expected)
    for const, name in consts.items():
        assert pack(values)[getattr(template, const)] == expected[template.PARAMS.index(name)]


def test_parameter_vector_reads_declared_paths_and_neutral_values():
    """An effect's parameter is read from the scene only when the effect is on; otherwise it
    is the declared neutral value; an undeclared name is an error."""
    class Scene(EveryEffectScene):
        def has(self, effect):
            return effect == "drying"

    values, _ = _distinct_values("drying")
    p = registry.parameter_vector("drying", Scene("drying", values))
    names = registry.parameter_names("drying")
    assert p[names.index("drying_rate")] == values["drying_rate"]
    assert p[names.index("support")] == values["support"]  # model-wide: always read
    assert p[names.index("thickness")] == 1.0 and p[names.index("eta")] == 0.0
    with pytest.raises(KeyError, match="unknown drying kernel parameters"):
        registry.parameter_vector("drying", values={"gravity": 1.0})


# One short CI-scale run per model: (scene and options of `craquelure run`).
CACHE_RUNS = {
    "drying": ["drying/ci", "--seed", "1", "--set", "outputs.t_end=0.4",
               "--set", "outputs.times=[0.2, 0.4]"],
    "impact": ["impact/ci", "--seed", "1", "--set", "outputs.t_end=2.0e-5",
               "--set", "outputs.snapshot_times=[1.0e-5]"],
    "lattice": ["lattice/calving", "--seed", "4", "--set", "domain.nx=24", "--set", "domain.ny=8",
                "--set", "domain.water_level=5.0", "--set", "material.g=0.02",
                "--set", "fracture.start_time=30.0", "--set", "numerics.mass_damping_until=30.0",
                "--set", "outputs.t_end=100.0", "--set", "outputs.frames=4"],
    "softdyn": ["softdyn/t1_phase_ci"],
}


@pytest.mark.parametrize("model", sorted(CACHE_RUNS))
def test_compiling_run_equals_cached_run_bit_for_bit(model, tmp_path):
    """A run that compiles its kernels into an empty cache and a run that loads them write the
    same dataset (the drying pair kernels reassociate their sums: compiled in the running
    process, the callees' own copies ran, and vx, vy differed from a cached run by ~1e-19)."""
    from tests.killed_run import ENV, cli, same_dataset

    env = {**ENV, "CRAQUELURE_CACHE": str(tmp_path / "cache")}
    compiled, cached = tmp_path / "compiled.nc", tmp_path / "cached.nc"
    subprocess.run(cli(CACHE_RUNS[model], compiled), env=env, check=True, capture_output=True)
    written = sorted((tmp_path / "cache").rglob("*.nbi"))
    assert written  # the first run compiled into the empty cache
    stamps = [p.stat().st_mtime_ns for p in written]
    subprocess.run(cli(CACHE_RUNS[model], cached), env=env, check=True, capture_output=True)
    assert sorted((tmp_path / "cache").rglob("*.nbi")) == written
    assert [p.stat().st_mtime_ns for p in written] == stamps  # the second run only loaded
    same_dataset(open_dataset(compiled), open_dataset(cached))
