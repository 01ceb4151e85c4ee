"""Model dispatch: every model provides a run stage; unknown models are named; every model has
the contract's files; no core module imports a model and the import graph has no cycle; the
tests mirror the package (tests/<path>/test_<module>.py)."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

from craquelure import models, registry


@pytest.mark.parametrize("model", models.MODELS)
def test_every_model_runs_through_a_run_stage(model):
    assert callable(models.stage(model, "run"))


def test_unknown_model_lists_the_allowed_ones():
    with pytest.raises(models.CraquelureError, match="allowed values"):
        models.model_api("fluid")


# -- the model contract and the import graph ------------------------------------------------
PACKAGE = Path(models.__file__).parent
CONTRACT = {"__init__.py", "api.py", "rules.py", "metadata.py", "kernel_template.py",
            "initial_state.py", "engine.py", "analysis.py", "figures.py", "claims.py",
            "workflow.py", "effects"}


@pytest.mark.parametrize("model", models.MODELS)
def test_every_model_has_the_contract_files(model):
    assert CONTRACT <= {p.name for p in (PACKAGE / model).iterdir()}
    effects = PACKAGE / model / "effects"
    assert (effects / "__init__.py").is_file()
    assert registry.known_effects(model), f"{model} declares no effect"


def test_every_model_package_is_listed():
    packages = {p.parent.name for p in PACKAGE.glob("*/api.py")}
    assert packages == set(models.MODELS)


def _module_name(path: Path) -> str:
    parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def import_graph() -> dict[str, set[str]]:
    """{module: craquelure modules it imports} over every import statement (function-level
    imports included) of every module of the package."""
    files = {_module_name(p): p for p in PACKAGE.rglob("*.py")}
    graph = {}
    for name, path in files.items():
        package = name if path.name == "__init__.py" else name.rpartition(".")[0]
        found = set()
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.Import):
                found |= {a.name for a in node.names}
            elif isinstance(node, ast.ImportFrom):
                base = node.module or ""
                if node.level:
                    up = package.split(".")[: len(package.split(".")) - node.level + 1]
                    base = ".".join(up + ([base] if base else []))
                for a in node.names:
                    found.add(f"{base}.{a.name}" if f"{base}.{a.name}" in files else base)
        graph[name] = {m for m in found if m in files and m != name}
    return graph


def _is_model(module: str) -> bool:
    parts = module.split(".")
    return len(parts) > 1 and parts[1] in models.MODELS


def test_no_core_module_imports_a_model():
    graph = import_graph()
    assert len(graph) > 50  # the walk found the package
    offending = sorted(f"{a} -> {b}" for a, deps in graph.items() if not _is_model(a)
                       for b in deps if _is_model(b))
    assert offending == []


def find_cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """Import circles of ``graph``, each as the path that closes it (depth-first search)."""
    state: dict[str, int] = {}  # 1: on the current path, 2: done
    cycles = []

    def visit(node, path):
        state[node] = 1
        for dep in sorted(graph.get(node, ())):
            if state.get(dep) == 1:
                cycles.append(path[path.index(dep):] + [dep])
            elif dep not in state:
                visit(dep, path + [dep])
        state[node] = 2

    for node in sorted(graph):
        if node not in state:
            visit(node, [node])
    return cycles


def test_import_graph_has_no_cycle():
    assert find_cycles(import_graph()) == []


def test_the_graph_sees_function_level_imports_and_circles():
    # the two checks above cannot pass vacuously: an import inside a function is an edge, a
    # planted circle is found
    graph = import_graph()
    assert "craquelure.api" in graph["craquelure.commands.fragments"]  # inside main()
    assert "craquelure.drying.integrators" in graph["craquelure.drying.rules"]
    planted = {**graph, "craquelure.models": graph["craquelure.models"] | {"craquelure.scene"}}
    assert [set(c) for c in find_cycles(planted)] == [{"craquelure.models", "craquelure.scene"}]


# -- tests mirror the package ---------------------------------------------------------------
# The tests of src/craquelure/<path>/<module>.py are tests/<path>/test_<module>.py, and every
# test file under tests/ is named after the module it tests. The exceptions, each with its
# reason (keep the list short; a module gets a test file as soon as it gets a test):
NOT_MIRRORED = {
    "__main__.py": "`python -m craquelure` is cli.main: tests/test_cli.py runs it in a process",
    "errors.py": "exception classes only; each message is asserted where it is raised",
    # the command-line wrappers: argparse to one call of the module that does the work, each
    # run through cli.main in the tests of that module
    "commands/campaign.py": "tests/test_io.py, tests/drying/test_analysis.py",
    "commands/export.py": "tests/test_export_formats.py",
    "commands/fragments.py": "tests/test_io.py, tests/drying/test_analysis.py",
    "commands/init.py": "tests/test_io.py, tests/test_cf.py",
    "commands/run.py": "tests/test_io.py, tests/killed_run.py (every model's test_api.py)",
    "commands/scenes.py": "tests/test_cli.py",
    "commands/verify.py": "tests/test_archive.py",
    # data tables (units, long names): tests/test_cf.py checks every model's variables
    "drying/metadata.py": "tests/test_cf.py",
    "impact/metadata.py": "tests/test_cf.py",
    "lattice/metadata.py": "tests/test_cf.py",
    "softdyn/metadata.py": "tests/test_cf.py",
    # figures of the workflow's results: drawn end to end by tests/workflow (the CI profile)
    "lattice/figures.py": "tests/workflow",
    "softdyn/figures.py": "tests/workflow",
    "lattice/bench.py": "engine set-up of the lattice benchmarks (benchmarks/lattice_*.py)",
}
# package markers; commands/__init__.py's shared --set/--set-file arguments are tested in
# tests/test_scene.py (test_set_file_*)
NOT_MIRRORED_NAMES = {"__init__.py"}
# test suites organised by purpose, not by module
SUITES = {"workflow", "hard_cases", "reference"}
TESTS_OF_NO_MODULE = {"test_docs.py": "the documentation site and the paths it names",
                      "test_defaults.py": "one default per parameter, read from every module"}
TESTS = Path(__file__).parent


def test_every_module_has_its_test_file():
    modules = {str(p.relative_to(PACKAGE)) for p in PACKAGE.rglob("*.py")}
    assert len(modules) > 100  # the walk found the package
    missing = sorted(m for m in modules - set(NOT_MIRRORED)
                     if Path(m).name not in NOT_MIRRORED_NAMES
                     and not (TESTS / Path(m).parent / f"test_{Path(m).name}").is_file())
    assert missing == [], "add tests/<path>/test_<module>.py (or a reason to NOT_MIRRORED)"
    assert sorted(set(NOT_MIRRORED) - modules) == []  # no stale exception
    mirrored = sorted(m for m in NOT_MIRRORED
                      if (TESTS / Path(m).parent / f"test_{Path(m).name}").is_file())
    assert mirrored == []  # an exception that has its file is no longer one


def test_every_test_file_is_named_after_its_module():
    files = [p.relative_to(TESTS) for p in TESTS.rglob("test_*.py")
             if p.relative_to(TESTS).parts[0] not in SUITES]
    assert len(files) > 100
    stray = sorted(str(f) for f in files if str(f) not in TESTS_OF_NO_MODULE
                   and not (PACKAGE / f.parent / f.name.removeprefix("test_")).is_file())
    assert stray == [], "name the file tests/<path>/test_<module>.py after the module it tests"
