"""The one list of models and the only way the core reaches one: every model is a package
``craquelure.<model>`` with the same files in the same roles (``api``, ``rules``, ``metadata``,
``effects/``, ``kernel_template``, ``initial_state``, ``engine``, ``analysis``, ``figures``,
``claims``, ``workflow``); the core names a model from :data:`MODELS` and loads the module of a
role with :func:`model_module`, never importing a model.

An API module may define (each optional, the CLI says so when one is missing):
``build_initial_state(scene, seed) -> xarray.Dataset``, ``derived_numbers(scene) -> dict``,
``workload(scene) -> dict`` (units, particles, neighbours: what :mod:`craquelure.throughput`
predicts the wall time from) and ``run(scene, out, seed, init=None, resume=False) -> Path``
(through :func:`craquelure.runner.run`, so every model checkpoints and ``--resume`` continues).
"""

import importlib
from types import ModuleType

from craquelure.errors import CraquelureError

MODELS = ("drying", "impact", "lattice", "softdyn")


def model_module(model: str, role: str) -> ModuleType:
    """The module ``craquelure.<model>.<role>`` of a model in :data:`MODELS`."""
    if model not in MODELS:
        raise CraquelureError(f"model: {model!r} is not allowed; allowed values: "
                              f"{', '.join(MODELS)}")
    return importlib.import_module(f"craquelure.{model}.{role}")


def model_api(model: str) -> ModuleType:
    return model_module(model, "api")  # every model has one (tests/test_models.py)


def stage(model: str, name: str):
    api = model_api(model)
    fn = getattr(api, name, None)
    if fn is None:
        raise CraquelureError(f"model {model!r} does not provide the stage {name!r}")
    return fn
