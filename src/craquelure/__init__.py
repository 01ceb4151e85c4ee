"""craquelure: reproducible particle simulations of fracture and soft matter.

Data flows one way: scene file -> validated scene (:mod:`craquelure.scene`) -> initial
state (model ``init``) -> effects + integrator (model ``run``) -> run dataset ->
analysis dataset -> figure / report.
"""

__version__ = "0.1.0"

# Threads of a run (numba's OpenMP workers sleep while waiting; see craquelure.threads): set on
# the package's import, before anything can start numba's thread pool.
from craquelure import threads as _threads  # noqa: E402,F401
