"""The accuracy probe of the impact workflow (P-wave mode frequency, lattice gradient factor)."""

import pytest

from craquelure.impact.experiments import crack_band_bar, lattice_gradient_factor, p_wave_mode


def test_lattice_gradient_factor_tends_to_one_with_wide_kernels():
    # a kernel many spacings wide samples the continuum integral -∫ x ∂W/∂x = 1
    assert lattice_gradient_factor(4.0) == pytest.approx(1.0, abs=1e-3)
    assert lattice_gradient_factor(1.0) == pytest.approx(0.99079, abs=1e-5)
    assert lattice_gradient_factor(0.7) < lattice_gradient_factor(1.0)


def test_lattice_gradient_factor_in_3d():
    """On the cubic lattice the continuum limit is 1 too; at kappa = 0.7 the 3D floor is lower
    than the 2D one (long waves 10 % slow against 8 %), at kappa = 1 it is the 0.982 that the
    3D P-wave check (check 4, 1.8 % slow) measured."""
    assert lattice_gradient_factor(3.0, dim=3) == pytest.approx(1.0, abs=2e-3)
    assert lattice_gradient_factor(1.0, dim=3) == pytest.approx(0.982, abs=1e-3)
    assert lattice_gradient_factor(0.7, dim=3) == pytest.approx(0.900, abs=1e-3)
    assert lattice_gradient_factor(0.7, dim=3) < lattice_gradient_factor(0.7)


def test_p_wave_mode_error_converges_to_the_lattice_floor():
    """Error = (1 - g) + C (k Delta)^2: halving Delta divides the distance to the floor by ~4
    (second-order SPH dispersion at fixed h/Delta); measured 2026-11-22 at kappa = 1:
    0.01263 (4 mm), 0.01006 (2 mm), floor 0.00921."""
    floor = 1.0 - lattice_gradient_factor(1.0)
    coarse = p_wave_mode(0.004)["error"] - floor
    fine = p_wave_mode(0.002)["error"] - floor
    assert coarse > 0 and fine > 0
    assert coarse / fine == pytest.approx(4.0, rel=0.25)


# -- crack band ----------------------------------------------------------------------------
# Check 7 (spec section 10): crack band in SPH, G_F ± 20 % at Δ = 4 and 2 mm.
#
# Notched bar :func:`craquelure.impact.experiments.crack_band_bar` at end speed 0.05 m/s (the spec's
# bound). Δ = 4 mm: the spec's 200 × 40 mm bar (10 rows). Δ = 2 mm: a 200 × 20 mm bar (10 rows):
# in uniaxial tension the dissipation per crack area does not depend on the height, the crack
# crosses the net section whatever its height, and halving it keeps the run at ~15 s; what must
# converge with Δ (band width in columns, ℓ_c = 2Δ) is resolved along the bar, which keeps its
# spec length. κ = 1.5 checks the 3-column band (ℓ_c = 3Δ) of the crack-band rule.
# Measured 2026-11-22: 1.048 (4 mm), 1.041 (2 mm), κ = 1.5 at 4 mm 1.140; ~30 s for the three.
# Re-measured 2026-12-02 with the damage dissipation booked by its own law (the secant energy
# the damage growth releases, no longer the internal energy's remainder): 1.0505 (4 mm),
# 1.0439 (2 mm). The target (a bar pulled apart through one crack band dissipates G_F A
# within 5 %) is met at 2 mm and missed at 4 mm by 0.05 percentage points: the 4 mm bar and the
# 3-column band at κ = 1.5 (ℓ_c = 3Δ, 1.14) keep the spec's check-7 tolerance of 20 %.

@pytest.mark.slow
@pytest.mark.parametrize("spacing,height_cells,kappa,columns,tolerance", [
    (0.004, 10, 1.0, 2, 0.2), (0.002, 10, 1.0, 2, 0.05), (0.004, 10, 1.5, 3, 0.2)])
def test_crack_band_dissipates_fracture_energy(spacing, height_cells, kappa, columns, tolerance,
                                               capsys):
    out = crack_band_bar(spacing, height_cells, kappa)
    with capsys.disabled():
        print(f"\n[check 7] Delta = {spacing * 1e3:g} mm, kappa = {kappa}: dissipation / "
              f"(G_F A) = {out['ratio']:.3f}, band {out['band_columns']} columns "
              f"(l_c = {out['band_width'] * 1e3:g} mm), elastic left "
              f"{out['elastic_left']:.3f}, {out['steps']} steps")
    assert out["ratio"] == pytest.approx(1.0, abs=tolerance)
    # one crack at the notch, fully open: the band is the calibrated width, nothing else
    # softened, and the elastic energy left is small against G_F A
    assert out["band_columns"] == columns
    assert -2 <= out["band_first"] <= out["band_last"] <= 2
    assert out["max_softening_outside"] < 0.05
    assert out["elastic_left"] < 0.1
