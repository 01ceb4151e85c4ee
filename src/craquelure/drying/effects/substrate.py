r"""Thin-layer substrate resistance (drying spec section 3, Eq. 15):

.. math:: \rho\,\dot{\mathbf v} = \nabla\cdot\sigma - \frac{\mu}{H^2}\,\mathbf u,

with :math:`\mathbf u = \mathbf r - \mathbf r(0)` the displacement of the surface point (no slip
at the bottom, free top, one finite difference across the thickness H). The per-particle
acceleration is :math:`-\mu\,\mathbf u / (H^2 \rho_I)`."""

from numba import njit

from craquelure.registry import Effect, Param

EFFECT = Effect("drying", "substrate", "SUBSTRATE", "thin-layer substrate spring -(mu/H^2) u",
                # H = 1 when off only keeps mu/H^2 finite
                params=(Param("lame_mu", "material.lame_mu", "stress"),
                         Param("thickness", "material.thickness", "length", neutral=1.0)))


@njit(inline="always", cache=True)
def substrate_acceleration(ux, uy, rho, mu, thickness):
    k = mu / (thickness * thickness * rho)
    return -k * ux, -k * uy
