"""Model dispatch: ``craquelure.<model>.api`` modules implement the stages for one model.

An API module may define (each optional, the CLI says so when one is missing):
``build_initial_state(scene, seed) -> xarray.Dataset``,
``derived_numbers(scene) -> dict``,
``workload(scene) -> dict`` (units, particles, neighbours: what :mod:`craquelure.throughput`
predicts the wall time from) and
``run(scene, out, seed, init=None, resume=False) -> Path`` (through
:func:`craquelure.runner.run`, so every model checkpoints and ``--resume`` continues a run).
"""

from __future__ import annotations

import importlib
from types import ModuleType

from craquelure.errors import CraquelureError
from craquelure.scene import MODELS


def model_api(model: str) -> ModuleType:
    if model not in MODELS:
        raise CraquelureError(f"model: {model!r} is not allowed; allowed values: "
                              f"{', '.join(MODELS)}")
    try:
        return importlib.import_module(f"craquelure.{model}.api")
    except ModuleNotFoundError as exc:
        if exc.name == f"craquelure.{model}.api" or exc.name == f"craquelure.{model}":
            raise CraquelureError(f"model {model!r} has no implementation yet") from exc
        raise


def stage(model: str, name: str):
    api = model_api(model)
    fn = getattr(api, name, None)
    if fn is None:
        raise CraquelureError(f"model {model!r} does not provide the stage {name!r}")
    return fn
