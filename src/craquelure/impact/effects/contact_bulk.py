r"""Penalty contact with the rigid base, bulk-modulus stiffness (source eq. 11; spec section 5).

Base y = 0, frictionless; contact radius :math:`r_c = \Delta/2`; penetration
:math:`g_i = r_c - y_i > 0` gives :math:`F^c_i = k\,g_i\,\hat e_y` with

.. math::
    k = a K A/\ell_{max}, \quad A = \Delta^{d-1}, \; \ell_{max} = \sqrt2\Delta
    \;\Rightarrow\; k = a K \Delta^{d-2}/\sqrt2,

the same for every particle, zero masses included. Decision [D]: since
:math:`\sqrt{k/m_i}\Delta t` diverges as :math:`m_i \to 0`, particles with
:math:`\sqrt{k/m_i}\Delta t > 0.5` (:math:`m_i < m_{kin} = 4k\Delta t^2`) use a kinematic
constraint instead: after the drift :math:`y_i \leftarrow \max(y_i, r_c - 0.05\Delta)`, around
each half kick :math:`v_{y,i} \leftarrow \max(v_{y,i}, 0)`; the momentum :math:`m_i\Delta v_{y,i}`
taken by the base and the kinetic energy removed on arrival are logged. So every penalty
particle has :math:`\sqrt{k/m_i}\Delta t \le 0.5`, and no separate penalty time-step limit is
needed.
The base receives :math:`-F^c_i`; :math:`F(t) = \sum_i F^c_i` (per metre of thickness in 2D).
Penalty energy :math:`\tfrac12 k g_i^2` enters the energy balance.

Decision on a (``numerics.contact_a: auto``; spec check 9,
``tests/impact/effects/test_contact_bulk.py``). The spec writes formula (2) with LS-DYNA's
default scale factor 0.1, which in 2D gives every particle k = 1.0e9 N/m whatever Δ: a penalty
layer as compliant as a concrete layer 30Δ thick, which then governs the contact instead of the
concrete (at 1 m/s the elastic disc bounces on its springs like a rigid mass; at the paper's
15 m/s it sinks 0.14Δ into the base and the crushed area shrinks 18 %). A penalty stiffness is a
numerical parameter whose results must not depend on it, so ``auto`` takes the stiffness of the
concrete the spring stands for: the contact radius r_c = Δ/2 says the particle's material
reaches Δ/2 below its centre, and that half cell (face A = Δ^{d−1}, height Δ/2, laterally
confined by its neighbours) has the uniaxial-strain stiffness

.. math::
    k = \frac{M A}{\Delta/2} = 2 M \Delta^{d-2}, \quad M = K + \tfrac43 G
    \;(\text{plane strain, 3D}), \quad M = E/(1-\nu^2) \;(\text{plane stress}),

i.e. :math:`a = 2\sqrt2\,M/K` = 6.27 (plane strain; 6.07 plane stress) in the source's
formula, k = 6.3e10 N/m per metre: the peak forces of (1) and (2) agree (check 9) and the
15 m/s results are those of the stiff limit. The price: :math:`m_{kin} = 4k\Delta t^2` rises
from 0.003 m̄ to 0.2 m̄ (κ = 1; 0.5 m̄ at κ = 1.5), so with uniform masses the lightest
10-25 % of the particles that reach the base take the kinematic constraint, whose energy
balance closes as well as with soft springs. A number (e.g. the spec's 0.1) overrides ``auto``.
"""

from numba import njit

from craquelure.impact.effects import BULK, SHEAR
from craquelure.registry import Effect, Param

EFFECT = Effect("impact", "contact_bulk", "CONTACT_BULK",
                "rigid-base penalty contact, k = a K A / l_max, kinematic fallback for m -> 0",
                requires=("numerics.contact_a",), conflicts=("contact_mass",),
                params=(BULK, SHEAR, Param("k_bulk", None, "N/m"), Param("kinematic_ratio")))


def bulk_stiffness(a: float, bulk: float, spacing: float, dim: int = 2) -> float:
    """k = a K Δ^{d-2}/√2 (virtual square segment A = Δ^{d-1}, ℓ_max = √2 Δ)."""
    return a * bulk * spacing ** (dim - 2) / 2.0**0.5


def half_cell_scale(bulk: float, shear: float, plane_stress: bool = False) -> float:
    """a for ``contact_a: auto``: k equal to the confined stiffness 2 M Δ^{d-2} of the half
    cell between a particle's centre and the base, a = 2√2 M/K."""
    if plane_stress:
        young = 9.0 * bulk * shear / (3.0 * bulk + shear)
        poisson = (3.0 * bulk - 2.0 * shear) / (2.0 * (3.0 * bulk + shear))
        modulus = young / (1.0 - poisson**2)
    else:
        modulus = bulk + 4.0 * shear / 3.0
    return 2.0 * 2.0**0.5 * modulus / bulk


@njit(inline="always", cache=True)
def bulk_penalty(gap, mass, k, dt, ratio):
    """Returns (force, energy, kinematic) for penetration ``gap`` > 0: ``kinematic`` when
    sqrt(k/m) dt exceeds ``ratio`` (then force 0 and the constraint is applied instead)."""
    if mass * ratio * ratio < k * dt * dt:
        return 0.0, 0.0, True
    return k * gap, 0.5 * k * gap * gap, False
