"""craquelure: reproducible particle simulations of fracture and soft matter.

Data flows one way: scene file -> validated scene (:mod:`craquelure.scene`) -> initial
state (model ``init``) -> effects + integrator (model ``run``) -> run dataset ->
analysis dataset -> figure / report.
"""

__version__ = "0.1.0"
