r"""Penalty contact with the rigid base, mass-based stiffness (source eq. 10; spec section 5).

.. math::
    k_i = a\, m_i/\Delta t^2, \qquad F^c_i = k_i g_i \hat e_y, \qquad a = 0.1 \text{ (SOFSCL)}.

:math:`\sqrt{k_i/m_i}\Delta t = \sqrt a` for any mass, so it is always stable, and the repelling
acceleration :math:`a g_i/\Delta t^2` does not depend on :math:`m_i`; but :math:`k_i \to 0` as
:math:`m_i \to 0`, and at :math:`m_i = 0` the acceleration 0/0 is guarded to 0, so zero-mass
particles pass through the base: the documented failure mode (check 10). Kept as the option
the tests show failing. ``numerics.contact_a: auto`` gives it the spec's a = 0.1.
"""

from numba import njit

from craquelure.registry import Effect, Param

EFFECT = Effect("impact", "contact_mass", "CONTACT_MASS",
                "rigid-base penalty contact, k_i = a m_i / dt^2 (fails for zero masses)",
                requires=("numerics.contact_a",), conflicts=("contact_bulk",),
                params=(Param("contact_a"),))

# LS-DYNA's SOFSCL default (spec section 5), the value of ``contact_a: auto`` for this formula
DEFAULT_SCALE = 0.1


@njit(inline="always", cache=True)
def mass_penalty(gap, mass, a, dt):
    """Returns (force, energy) for penetration ``gap`` > 0."""
    k = a * mass / (dt * dt)
    return k * gap, 0.5 * k * gap * gap
