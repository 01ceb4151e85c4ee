"""craquelure: reproducible particle simulations of fracture and soft matter.

Data flows one way: scene file -> validated scene (:mod:`craquelure.scene`) -> initial
state (model ``init``) -> effects + integrator (model ``run``) -> run dataset ->
analysis dataset -> figure / report. The functions below (:mod:`craquelure.api`) are the
command line's verbs:

    import craquelure as cq

    short = {"outputs.t_end": 0.4, "outputs.times": [0.2, 0.4]}
    ds = cq.run(cq.load_scene("drying/ci", overrides=short), seed=1)
    frag = cq.fragments(ds)
"""

__version__ = "0.1.0"

# Threads of a run (numba's OpenMP workers sleep while waiting; see craquelure.threads): set on
# the package's import, before anything can start numba's thread pool.
from craquelure import threads as _threads  # noqa: E402,F401

__all__ = ["CraquelureError", "check", "export", "fragments", "initial_state", "load_scene",
           "run", "run_to_file", "scenes"]


def __getattr__(name: str):
    """The API's functions (:mod:`craquelure.api`), imported on first use: ``import
    craquelure`` stays light for the modules that only need ``__version__``."""
    if name in __all__:
        import importlib

        module = "craquelure.errors" if name == "CraquelureError" else "craquelure.api"
        return getattr(importlib.import_module(module), name)
    raise AttributeError(f"module 'craquelure' has no attribute {name!r}")
