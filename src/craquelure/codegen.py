"""Generated-source modules shared by every engine's effects-on-demand mechanism.

An engine writes a copy of its kernel template with its effect flags set as module constants
(numba folds them, so absent effects compile out), names it by a hash of the generated text and
of the fragment sources, and imports it here. The file is written atomically (temporary name,
then rename), so Snakemake jobs that generate the same module at once never read half a file;
``@njit(cache=True)`` then caches the machine code beside it for later processes.

All engines keep their generated modules under one root, ``$CRAQUELURE_CACHE`` (default
``~/.cache/craquelure``), one folder per engine (:func:`generated_dir`).
"""

from __future__ import annotations

import importlib.util
import os
import sys
from pathlib import Path
from types import ModuleType

from craquelure.threads import single_threaded_libraries


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
    spec = importlib.util.spec_from_file_location(module_name, path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[module_name] = module
    spec.loader.exec_module(module)
    return module
