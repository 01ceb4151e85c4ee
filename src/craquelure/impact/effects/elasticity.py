r"""Hypo-elastic effective stress with the Jaumann rate, bulk/shear moduli K, G (spec section 2.1).

.. math::
    \dot p = -K\,\mathrm{tr}D, \qquad
    \dot s = 2G\,(D - \tfrac13 \mathrm{tr}D\,\mathbf 1) + \Omega s - s\Omega, \qquad
    \tilde\sigma = -p\mathbf 1 + s,

with :math:`L_{ab} = \partial v_a/\partial x_b`, :math:`D = (L+L^T)/2`, :math:`\Omega = (L-L^T)/2`.
Components: xx, yy, xy, zz, and in 3D (``domain.dim: 3``) xz, yz (tension positive; the
fragments take all six, 2D passes zeros for xz, yz). Plane strain: :math:`D_{zz} = 0` and
:math:`\tilde\sigma_{zz}` evolves (the material point driver of check 6 passes a non-zero
:math:`D_{zz}` to make the z direction stress-free). Plane stress (``domain.plane: stress``, the
spec's open doubt 5): the kernel passes the :math:`D_{zz}` that keeps :math:`\tilde\sigma_{zz} = 0`
through the trial and the plastic return (``plane_stress_dzz`` in the kernel template); the P-wave
speed is then :math:`\sqrt{E/((1-\nu^2)\rho)}`. With :math:`w = \Omega_{xy}`:
:math:`(\Omega\sigma-\sigma\Omega)_{xx} = 2w\sigma_{xy}`, :math:`(\ldots)_{yy} = -2w\sigma_{xy}`,
:math:`(\ldots)_{xy} = w(\sigma_{yy}-\sigma_{xx})`, zz unaffected by an in-plane spin. 3D, with
the full spin :math:`(\Omega_{xy}, \Omega_{xz}, \Omega_{yz})`:
:math:`(\Omega\sigma-\sigma\Omega)_{ab} = \sum_k \Omega_{ak}\sigma_{kb} - \sigma_{ak}\Omega_{kb}`,
written out in :func:`jaumann_trial`. The increment is explicit (forward Euler over the step
with the mid-step gradient).
"""

from numba import njit

from craquelure.impact.effects import BULK, SHEAR
from craquelure.registry import Effect

EFFECT = Effect("impact", "elasticity", "ELASTICITY",
                "hypo-elastic effective stress, Jaumann rate (K, G), plane strain or stress",
                params=(BULK, SHEAR))


@njit(inline="always", cache=True)
def jaumann_trial(s, d, w, bulk, shear, dt):
    """Trial effective stress after ``dt``. ``s`` and the strain rate ``d`` are symmetric
    tensors (xx, yy, xy, zz, xz, yz), ``w`` the spin (Ω_xy, Ω_xz, Ω_yz); in 2D the xz, yz
    components and Ω_xz, Ω_yz are zero and the extra terms add exact zeros."""
    sxx, syy, sxy, szz, sxz, syz = s
    dxx, dyy, dxy, dzz, dxz, dyz = d
    wxy, wxz, wyz = w
    tr = dxx + dyy + dzz
    lam = bulk - 2.0 * shear / 3.0
    # (Ωσ − σΩ) for Ω antisymmetric, σ symmetric, component by component
    nxx = sxx + dt * (lam * tr + 2.0 * shear * dxx + 2.0 * wxy * sxy + 2.0 * wxz * sxz)
    nyy = syy + dt * (lam * tr + 2.0 * shear * dyy - 2.0 * wxy * sxy + 2.0 * wyz * syz)
    nxy = sxy + dt * (2.0 * shear * dxy + wxy * (syy - sxx) + (wxz * syz + wyz * sxz))
    nzz = szz + dt * (lam * tr + 2.0 * shear * dzz - 2.0 * (wxz * sxz + wyz * syz))
    nxz = sxz + dt * (2.0 * shear * dxz + wxz * (szz - sxx) + (wxy * syz - wyz * sxy))
    nyz = syz + dt * (2.0 * shear * dyz + wyz * (szz - syy) - (wxy * sxz + wxz * sxy))
    return nxx, nyy, nxy, nzz, nxz, nyz


@njit(inline="always", cache=True)
def secant_energy_density(nom, s, bulk, shear):
    """Recoverable (secant) elastic energy density ½ σ : C⁻¹σ̃ of a damaged point (J/m³): the
    nominal stress σ = ``nom`` times the effective elastic strain C⁻¹σ̃ of the effective stress σ̃ =
    ``s`` (both (xx, yy, xy, zz, xz, yz)). Unloading is secant, so this is what the point gives
    back: p²/(2K) + s:s/(4G) undamaged, nothing across a fully open crack, the whole compressive
    energy of a cracked point in compression."""
    pn = -(nom[0] + nom[1] + nom[3]) / 3.0
    ps = -(s[0] + s[1] + s[3]) / 3.0
    dev = ((nom[0] + pn) * (s[0] + ps) + (nom[1] + pn) * (s[1] + ps)
           + (nom[3] + pn) * (s[3] + ps)
           + 2.0 * (nom[2] * s[2] + nom[4] * s[4] + nom[5] * s[5]))
    return 0.5 * pn * ps / bulk + 0.25 * dev / shear
