r"""Beams between two rotating particles (lattice spec sections 3 and 4).

Local dofs of one beam are :math:`(u_1, v_1, \varphi_1, u_2, v_2, \varphi_2)`: ``u`` along the
axis from node 1 to node 2, ``v`` normal to it, :math:`\varphi` rotation. Both bond models of
the spec are one energy in the chord frame,

.. math::
    U = \tfrac12 k_n e^2 + \tfrac12 a(\varphi_1'^2 + \varphi_2'^2) + b\,\varphi_1'\varphi_2',
    \quad e = \ell - L_0,\ \varphi_k' = (\theta_k - \theta_{k,0}) - \Delta\alpha,

with :math:`\Delta\alpha = \alpha - \alpha_0` the chord rotation (wrapped to (-pi, pi]) and

* Euler-Bernoulli beam: :math:`k_n = E_b A/L`, :math:`a = 4E_bI/L`, :math:`b = 2E_bI/L`
  (the 6x6 matrix of section 3 is exactly :math:`B^T D B`: ``tests/lattice/linear_beam.py``,
  the linear model the tests check the kernel against);
* shear-beam potential: :math:`k_n`, :math:`a = k_r`, :math:`b = 0` (section 4).

End moments :math:`M_1 = a\varphi_1' + b\varphi_2'`, :math:`M_2 = b\varphi_1' + a\varphi_2'`,
axial force :math:`N = k_n e`, shear :math:`V = (M_1 + M_2)/\ell`. The beam acts on node 2 with
:math:`F_2 = -N\,\hat e + V\,\hat e_\perp` and on node 1 with :math:`F_1 = -F_2`, and with the
torques :math:`-M_1`, :math:`-M_2`.

Decision [D]: the spec's path-independent form divides by :math:`L_0` in V; we divide by the
current chord :math:`\ell`, which makes the force exactly :math:`-\nabla U` and conserves the
angular momentum :math:`\sum r\times F + \tau` to round-off (with :math:`L_0` it is off by
:math:`(\ell/L_0 - 1)(M_1 + M_2)`); both agree to first order, so the linear matrix is the
spec's.

Macroscopic constants of the triangular lattice (section 4, affine):
:math:`E = 2\sqrt3 k_n(k_n+k_s)/(3k_n+k_s)`, :math:`\nu = (k_n-k_s)/(3k_n+k_s)` with the
equivalent tangential stiffness :math:`k_s = 2(a+b)/L^2` (E-B: :math:`12E_bI/L^3`; shear-beam:
:math:`2k_r/L^2`).
"""

import math
from dataclasses import dataclass

SQRT3 = math.sqrt(3.0)


@dataclass(frozen=True)
class BeamConstants:
    """Per-bond constants of one bond model: k_n, a, b (see module docstring), plus the beam
    cross-section (A, I, w) used for stresses in the fracture criterion and E_b."""

    model: str
    kn: float
    a: float
    b: float
    E_b: float
    width: float
    area: float
    inertia: float
    L: float

    @property
    def ks(self) -> float:
        return 2.0 * (self.a + self.b) / self.L**2


def euler_bernoulli(E_b: float, width: float, L: float = 1.0,  # noqa: N803
                    thickness: float = 1.0) -> BeamConstants:
    A, I = width * thickness, thickness * width**3 / 12.0  # noqa: N806
    return BeamConstants("euler_bernoulli", E_b * A / L, 4 * E_b * I / L, 2 * E_b * I / L,
                         E_b, width, A, I, L)


def shear_beam(kn: float, ks: float, L: float = 1.0, thickness: float = 1.0) -> BeamConstants:
    """Shear-beam potential with k_r = k_s L^2/2; its E_b and w are those of the E-B beam with
    the same (k_n, k_s) (w = L sqrt(k_s/k_n), E_b = k_n L/(w b)), used for stresses."""
    width = L * math.sqrt(ks / kn) if ks > 0 else L
    A = width * thickness  # noqa: N806
    return BeamConstants("shear_beam", kn, 0.5 * ks * L**2, 0.0, kn * L / A, width, A,
                         thickness * width**3 / 12.0, L)


def lattice_moduli(kn: float, ks: float) -> dict[str, float]:
    """E, nu, Lame lambda, mu and the P-wave modulus of the triangular lattice (section 4)."""
    E = 2 * SQRT3 * kn * (kn + ks) / (3 * kn + ks)  # noqa: N806
    nu = (kn - ks) / (3 * kn + ks)
    lam, mu = SQRT3 / 4 * (kn - ks), SQRT3 / 4 * (kn + ks)
    return {"E": E, "nu": nu, "lambda": lam, "mu": mu, "M": lam + 2 * mu}


def stiffness_from_moduli(E: float, nu: float) -> tuple[float, float]:  # noqa: N803
    """Inverse mapping (k_n, k_s) for macroscopic E, nu (needs -1 < nu <= 1/3)."""
    if not -1.0 < nu <= 1.0 / 3.0:
        raise ValueError(f"poisson_ratio {nu} is outside (-1, 1/3] reachable by the lattice")
    kn = E / (SQRT3 * (1 - nu))
    return kn, kn * (1 - 3 * nu) / (1 + nu)


def cell_area(L: float = 1.0) -> float:  # noqa: N803
    """Area per particle of the triangular lattice, sqrt(3)/2 L^2."""
    return SQRT3 / 2 * L * L
