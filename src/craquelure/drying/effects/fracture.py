r"""Fracture by particle removal (drying spec section 4).

Mean stress of the total 2D stress :math:`\bar\sigma = \mathrm{tr}\,\sigma/2` (viscous + elastic
+ drying, evaluated with the rates of the accepted state). After every accepted step, every
particle with :math:`\bar\sigma > \sigma_Y` is deleted: it keeps its index with ``alive = 0``,
leaves the neighbour search, and its mass, momentum and history vanish. The multistep integrator
then restarts (its history is invalid)."""

import numpy as np
from numba import njit

from craquelure.registry import Effect

# flag None: acts between steps (engine), not in the rate kernel
EFFECT = Effect("drying", "fracture", None,
                "remove particles whose mean stress tr(sigma)/2 exceeds sigma_Y",
                requires=("material.yield_stress",))


@njit(cache=True)
def particles_to_remove(mean_stress, alive, yield_stress):
    """Indices of live particles with mean stress strictly above the yield stress."""
    return np.nonzero(alive & (mean_stress > yield_stress))[0]
