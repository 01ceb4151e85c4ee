"""Effects on demand, one mechanism for every engine.

A kernel template is an ordinary module with one flag block::

    # BEGIN FLAGS
    ELASTICITY = True
    KERNEL = 0
    # END FLAGS

:func:`specialise` copies the template with that block rewritten for one scene (the effect
flags come from the registry, :func:`effect_flags`) and imports the copy. Numba treats module
globals as compile-time constants, so ``if ELASTICITY:`` with ``ELASTICITY = False`` is pruned:
an absent effect is compiled out, not skipped at run time.

The copy is named by a hash of its text and of every craquelure module the template imports
(transitively), so editing any of them gives a fresh numba cache; it is written atomically
under ``$CRAQUELURE_CACHE`` (default ``~/.cache/craquelure``), one folder per engine.

Every process runs the cached machine code, the one that compiled it included: a signature not
in the cache yet is compiled in a child process, then loaded from the cache. Why: numba links
each callee into its caller as a weak copy optimised again there, and the JIT resolves a weak
symbol to its first definition, so the compiling process would run the callees' own copies and
a process loading the cache the copies inside the caller; where a kernel reassociates sums
(``fastmath`` ``reassoc``) the two round differently in the last bits.
"""

import hashlib
import importlib
import importlib.util
import os
import pickle
import re
import subprocess
import sys
from collections.abc import Iterable, Mapping
from functools import cache
from pathlib import Path
from types import ModuleType

from numba.core.caching import FunctionCache
from numba.core.dispatcher import Dispatcher

from craquelure.threads import single_threaded_libraries

_FLAG_BLOCK = re.compile(r"^# BEGIN FLAGS[^\n]*\n(.*?)^# END FLAGS[^\n]*$", re.S | re.M)
_FLAG_LINE = re.compile(r"^([A-Z][A-Z0-9_]*) = ", re.M)
_IMPORT = re.compile(r"^(?:from (craquelure[\w.]*) import (\([^)]*\)|[^\n]*)"
                     r"|import (craquelure[\w.]*))", re.M)


def generated_dir(engine: str) -> Path:
    """``$CRAQUELURE_CACHE/<engine>`` (default ``~/.cache/craquelure/<engine>``), created."""
    root = os.environ.get("CRAQUELURE_CACHE")
    path = (Path(root) if root else Path.home() / ".cache" / "craquelure") / engine
    path.mkdir(parents=True, exist_ok=True)
    return path


def import_generated(source: str, module_name: str, path: Path) -> ModuleType:
    """Write ``source`` to ``path`` (unless it already holds exactly that) and import it as
    ``module_name`` (reusing an already imported module of that name)."""
    single_threaded_libraries()  # no library thread pool inside a time step (threads.py)
    if module_name in sys.modules:
        return sys.modules[module_name]
    path.parent.mkdir(parents=True, exist_ok=True)
    if not path.is_file() or path.read_text() != source:
        tmp = path.with_name(f".{path.name}.tmp-{os.getpid()}")
        tmp.write_text(source)
        os.replace(tmp, path)
    module = _load_module(module_name, path)
    for value in vars(module).values():
        if (isinstance(value, Dispatcher) and value.__module__ == module_name
                and isinstance(value._cache, FunctionCache)):
            value.compile = _compile_via_cache(value, module_name, path)
    return module


def _load_module(module_name: str, path: Path) -> ModuleType:
    spec = importlib.util.spec_from_file_location(module_name, path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[module_name] = module
    spec.loader.exec_module(module)
    return module


def _compile_via_cache(kernel: Dispatcher, module_name: str, path: Path):
    """``kernel.compile`` that compiles a signature missing from the numba cache in a child
    process (:func:`compile_child`) and then loads it from the cache (module docstring)."""
    compile_here = kernel.compile

    def compile(sig):
        cache = kernel._cache
        key = cache._index_key(sig, kernel.targetctx.codegen())
        if key not in cache._cache_file._load_index():
            job = pickle.dumps((sys.path, module_name, str(path), kernel.__name__, sig))
            subprocess.run([sys.executable, "-c", _CHILD], input=job, check=False)
        return compile_here(sig)  # loads from the cache (compiles here if the child failed)

    return compile


# the child takes the parent's sys.path before it imports craquelure
_CHILD = ("import pickle, sys; job = pickle.load(sys.stdin.buffer); sys.path[:] = job[0]; "
          "from craquelure import codegen; codegen.compile_child(*job[1:])")


def compile_child(module_name: str, path: str, name: str, sig) -> None:
    """In the child process: compile kernel ``name`` of a generated module for ``sig`` into the
    numba cache."""
    single_threaded_libraries()
    getattr(_load_module(module_name, Path(path)), name).compile(sig)


def effect_flags(model: str, effects: Iterable[str]) -> dict[str, bool]:
    """``{flag: effect is in the scene}`` for every effect of ``model`` that declares a flag."""
    from craquelure.registry import get_effect, known_effects

    chosen = set(effects)
    known = known_effects(model)
    for name in sorted(chosen - set(known)):
        get_effect(model, name)  # raises SceneError naming the known effects
    return {e.flag: name in chosen for name, e in known.items() if e.flag}


def _module_file(name: str) -> Path | None:
    try:
        spec = importlib.util.find_spec(name)
    except (ImportError, ValueError):
        return None
    return Path(spec.origin) if spec is not None and spec.origin else None


def dependency_files(template: str) -> list[Path]:
    """The template's file and every craquelure module it imports, transitively, sorted."""
    seen: dict[str, Path] = {}
    todo = [template]
    while todo:
        name = todo.pop()
        if name in seen:
            continue
        path = _module_file(name)
        if path is None or path.suffix != ".py":
            continue
        seen[name] = path
        for frm, names, imp in _IMPORT.findall(path.read_text()):
            if imp:
                todo.append(imp)
                continue
            todo.append(frm)
            package = _module_file(frm)
            if package is not None and package.name == "__init__.py":
                # ``from package import module``: the names may be submodules
                todo += [f"{frm}.{n}" for n in re.findall(r"\w+", names)
                         if _module_file(f"{frm}.{n}") is not None]
    return sorted(seen.values())


def generate(template: str, flags: Mapping[str, bool | int]) -> tuple[str, str]:
    """``(source, digest)`` of ``template`` (a module name) with ``flags`` in its flag block.

    ``flags`` must set exactly the template's flags: a flag the template lacks or a template
    flag left unset is an error (the registry, the engine and the template disagree)."""
    files = dependency_files(template)
    path = _module_file(template)
    text = path.read_text()
    match = list(_FLAG_BLOCK.finditer(text))
    if len(match) != 1:
        raise RuntimeError(f"{template}: needs exactly one '# BEGIN FLAGS' ... '# END FLAGS' block")
    declared = set(_FLAG_LINE.findall(match[0].group(1)))
    if declared != set(flags):
        raise RuntimeError(f"{template}: flags {sorted(flags)} do not match the template's "
                           f"flag block {sorted(declared)}")
    block = "\n".join([f"# BEGIN FLAGS (generated from {template})"]
                      + [f"{name} = {value!r}" for name, value in sorted(flags.items())]
                      + ["# END FLAGS"])
    source = ("# Generated by craquelure.codegen; do not edit.\n"
              + text[:match[0].start()] + block + text[match[0].end():])
    digest = hashlib.sha256(source.encode())
    # the parameter tuple comes from the effect declarations, which the template need not import
    digest.update(repr(getattr(importlib.import_module(template), "PARAMS", ())).encode())
    for dep in files:
        digest.update(dep.read_bytes())
    return source, digest.hexdigest()[:16]


@cache
def _specialise(template: str, key: tuple[tuple[str, bool | int], ...], engine: str) -> ModuleType:
    source, digest = generate(template, dict(key))
    name = f"craquelure_{engine}_{digest}"
    return import_generated(source, name, generated_dir(engine) / f"{name}.py")


def specialise(template: str, flags: Mapping[str, bool | int], engine: str) -> ModuleType:
    """The imported copy of ``template`` (a module name) compiled for ``flags``; generated at
    most once per process, written once per content under ``generated_dir(engine)``."""
    return _specialise(template, tuple(sorted(flags.items())), engine)


specialise.cache_clear = _specialise.cache_clear  # tests: a new process in miniature


def param_indices(names: tuple[str, ...], *wanted: str) -> tuple[int, ...]:
    """Positions of ``wanted`` in a template's parameter tuple ``names``: its index constants,
    each paired with its parameter by name (``A, B = param_indices(PARAMS, "a", "b")``)."""
    return tuple(names.index(name) for name in wanted)
