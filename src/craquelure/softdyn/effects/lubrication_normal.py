r"""Normal lubrication (Poiseuille squeeze/pull of the film), softdyn spec section 3.

.. math::
    f^{visc}_n = -\zeta_n\, n\cdot u_{ij}, \qquad
    \zeta_n = c_n\, \eta\, a^4 / h^3 \quad (c_n = 3\pi/2)

``a`` is the interaction radius: with the ``hertz`` effect :math:`a^2 = R(h + |s|)`, without it
(rigid spheres) :math:`a^2 = R h`, for which :math:`\zeta_n = (3\pi/2)\eta R^2/h` is Reynolds'
result for two equal rigid spheres. The film carries the normal force in series with the elastic
response, so the gap obeys :math:`\dot h = -f_n/\zeta_n` exactly (the gap law).

Decision [D]: this effect is the base of the model (it is the only normal coupling of a pair), so
every softdyn scene must list it; :mod:`craquelure.softdyn.engine` says so when it is missing.
"""

from numba import njit

from craquelure.registry import Effect, Param

# flag None: always compiled in or handled outside the kernel
EFFECT = Effect("softdyn", "lubrication_normal", None,
                "Poiseuille squeeze film, zeta_n = c_n eta a^4 / h^3",
                params=(Param("eta", "material.viscosity", "viscosity"),
                        Param("c_n", "material.c_n")))


@njit(inline="always", cache=True)
def zeta_normal(eta, c_n, a2, h):
    """Normal friction coefficient zeta_n = c_n eta a^4 / h^3 (``a2`` = a^2)."""
    return c_n * eta * a2 * a2 / (h * h * h)
