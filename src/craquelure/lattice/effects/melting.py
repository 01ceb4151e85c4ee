r"""Melting-freezing: viscous flow obeying Glen's law (lattice spec section 7).

Each intact beam melts in a step with probability :math:`P = 1 - e^{-\lambda\Delta t}`,
:math:`\lambda = 2 A E_b^2 U / a^2` (U: the beam's elastic energy per unit thickness, a = L the
block size, A the rate factor), which gives :math:`\dot\varepsilon \propto A\sigma_e^2 t_D`
(n = 3). With ``melting.frozen_rate`` > 0, :math:`\lambda` is that constant instead
(Newtonian control). A melted beam re-forms at once stress-free: its rest state becomes the
current geometry (:math:`L_0 = \ell`, :math:`\alpha_0 = \alpha`, :math:`\theta_{k,0} =
\theta_k`); its energy U is booked as melting energy. Every ``melting.freeze_every`` steps,
unbonded pairs closer than :math:`r_f` = ``melting.refreeze_radius`` L that never had a
beam broken by fracture get a new stress-free beam.

Random numbers [D]: a counter-based hash (splitmix64 of seed, step, bond), so a run is
reproducible for any number of threads.
"""

import numpy as np
from numba import njit

from craquelure.registry import Effect, Param

EFFECT = Effect("lattice", "melting", "MELTING",
                "random melting of beams at rate 2 A E_b^2 U/a^2, re-forming stress-free",
                params=(Param("melt_rate_factor", "melting.rate_factor"),
                        Param("frozen_rate", "melting.frozen_rate", "1/time")))


@njit(inline="always", cache=True)
def melt_rate(u, rate_factor, e_b, block, frozen_rate):
    if frozen_rate > 0.0:
        return frozen_rate
    return 2.0 * rate_factor * e_b * e_b * u / (block * block)


@njit(inline="always", cache=True)
def uniform01(seed, step, index):
    """Uniform in [0, 1) from (seed, step, index): splitmix64 finaliser."""
    z = (np.uint64(seed) * np.uint64(0x9E3779B97F4A7C15)
         + np.uint64(step) * np.uint64(0xBF58476D1CE4E5B9) + np.uint64(index))
    z = (z ^ (z >> np.uint64(30))) * np.uint64(0xBF58476D1CE4E5B9)
    z = (z ^ (z >> np.uint64(27))) * np.uint64(0x94D049BB133111EB)
    z = z ^ (z >> np.uint64(31))
    return np.float64(z >> np.uint64(11)) * (1.0 / 9007199254740992.0)
