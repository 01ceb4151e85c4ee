r"""Fracture: elliptical criterion, per beam or node-averaged (lattice spec section 6).

Per beam [C, Zhang & Eckert 2005]: remove the beam when
:math:`(\sigma/\sigma_0)^2 + (\tau/\tau_0)^2 \ge 1`, :math:`\sigma = N/A` (tension > 0; in
compression the first term is 0 [D]), :math:`\tau = |V|/A`; with ``bending`` [D]
:math:`\sigma = N/A + \max(|M_1|,|M_2|)\,w/(2I)`. Stresses use the elastic forces (damping
excluded) at the start of the step; a beam that fails carries no force in that step.

Node-averaged [R]: :math:`\sigma_i = \frac{1}{2V_i}\sum_j \frac12(\ell_{ij} e_{ij}\otimes f_{ij} +
f_{ij}\otimes \ell_{ij} e_{ij})`, :math:`V_i = \frac{\sqrt3}{2}L^2 b`, :math:`p = \mathrm{tr}\,
\sigma_i/2`, :math:`\tau_i = \sqrt{\frac12 s:s}`; when :math:`(\max(p,0)/\sigma_0)^2 +
(\tau_i/\tau_0)^2 \ge 1` the beam at i with the largest single-beam ratio breaks (one per node
per step) [D].

Each broken beam's stored energy is booked as fracture energy. Fracture is off before
``fracture.start_time`` (settling) and never breaks beams flagged unbreakable (the pad).
"""

import math

from numba import njit

from craquelure.registry import Effect, Param

EFFECT = Effect("lattice", "fracture", "FRACTURE",
                "remove beams on the elliptical (sigma/sigma0)^2 + (tau/tau0)^2 >= 1 criterion",
                params=(Param("sigma0", "material.sigma0", "stress", neutral=1.0),
                        Param("tau0", "material.tau0", "stress", neutral=1.0),
                        Param("fracture_start", "fracture.start_time", "time")))


@njit(inline="always", cache=True)
def beam_ratio_scaled(n, v, m1, m2, inv_area, bend, inv_sigma0, inv_tau0, bending):
    """(sigma/sigma0)^2 + (tau/tau0)^2 of one beam (tension positive, compression -> 0), with
    the constant factors precomputed (1/A, w/(2I), 1/sigma0, 1/tau0): no division per beam in
    the kernel."""
    sigma = n * inv_area
    if bending:
        sigma += max(abs(m1), abs(m2)) * bend
    sigma = max(sigma, 0.0) * inv_sigma0
    tau = abs(v) * inv_area * inv_tau0
    return sigma * sigma + tau * tau


@njit(inline="always", cache=True)
def node_ratio(sxx, syy, sxy, sigma0, tau0):
    """(max(p, 0)/sigma0)^2 + (tau_i/tau0)^2 of a node stress."""
    p = 0.5 * (sxx + syy)
    dxx, dyy = sxx - p, syy - p
    tau = math.sqrt(0.5 * (dxx * dxx + dyy * dyy + 2.0 * sxy * sxy))
    return (max(p, 0.0) / sigma0) ** 2 + (tau / tau0) ** 2
