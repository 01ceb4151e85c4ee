"""Compressive (ductile) damage of the CSCM-like concrete: the uniaxial strength of a crushed
point, sigma_u(D), from the damaged shear surface; the crushing strain from G_fc = 100 G_F
regularised by the crack band; D_c linear in the plastic strain, capped at DC_MAX."""

import numpy as np
import pytest

from craquelure.impact.effects.compressive_damage import (
    DC_MAX,
    ductile_damage,
    softening_strain,
    uniaxial_strength,
)
from craquelure.impact.material import standard_concrete

MAT = standard_concrete(band=0.008)


def test_undamaged_uniaxial_strength_is_f_c():
    """Murray's fits reproduce f'c on the uniaxial path within 3 % (the bound of check 6's
    material-point test of the same surface)."""
    assert uniaxial_strength(0.0, MAT.cap) == pytest.approx(MAT.f_c, rel=0.03)


def test_strength_falls_at_least_as_fast_as_one_minus_d():
    """sigma_u/sqrt(3) = (1 - D) F(sigma_u) with F = F_f sqrt(F_c) growing with the pressure
    below the uniaxial point: a weaker point also has less confinement, so
    sigma_u(D) <= (1 - D) sigma_u(0); a fully crushed point (DC_MAX) keeps < 1 % of f'c."""
    d = np.linspace(0.0, DC_MAX, 12)
    sig = np.array([uniaxial_strength(x, MAT.cap) for x in d])
    assert (np.diff(sig) < 0).all()
    assert (sig <= (1 - d) * sig[0] * (1 + 1e-6)).all()
    assert sig[-1] < 0.01 * MAT.f_c


def test_crushing_strain_is_regularised_by_the_band():
    """G_fc per unit area = band x energy density: epsilon_fc ~ G_F / band, so a twice wider
    band halves the strain and twice the fracture energy doubles it (to the root solver's
    1e-6 Pa, i.e. ~1e-12 relative)."""
    eps = softening_strain(MAT.f_c, MAT.G_F, MAT.band, MAT.cap)
    assert softening_strain(MAT.f_c, MAT.G_F, 2 * MAT.band, MAT.cap) == pytest.approx(
        eps / 2, rel=1e-9)
    assert softening_strain(MAT.f_c, 2 * MAT.G_F, MAT.band, MAT.cap) == pytest.approx(
        2 * eps, rel=1e-9)
    # the dissipated energy per area: band eps_fc int sigma_u dD = 100 G_F (trapezoid, 199 pts)
    d = np.linspace(0.0, DC_MAX, 801)
    sig = np.array([uniaxial_strength(x, MAT.cap) for x in d])
    assert MAT.band * eps * np.trapezoid(sig, d) == pytest.approx(100 * MAT.G_F, rel=2e-3)


def test_damage_is_linear_in_the_plastic_strain_up_to_its_cap():
    eps_fc = 0.02
    assert ductile_damage(0.0, eps_fc) == 0.0
    assert ductile_damage(0.25 * eps_fc, eps_fc) == pytest.approx(0.25, rel=1e-15)
    assert ductile_damage(5 * eps_fc, eps_fc) == DC_MAX
