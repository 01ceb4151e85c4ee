"""The accuracy probe of the impact workflow (P-wave mode frequency, lattice gradient factor)."""

import pytest

from craquelure.impact.experiments import lattice_gradient_factor, p_wave_mode


def test_lattice_gradient_factor_tends_to_one_with_wide_kernels():
    # a kernel many spacings wide samples the continuum integral -∫ x ∂W/∂x = 1
    assert lattice_gradient_factor(4.0) == pytest.approx(1.0, abs=1e-3)
    assert lattice_gradient_factor(1.0) == pytest.approx(0.99079, abs=1e-5)
    assert lattice_gradient_factor(0.7) < lattice_gradient_factor(1.0)


def test_p_wave_mode_error_converges_to_the_lattice_floor():
    """Error = (1 - g) + C (k Delta)^2: halving Delta divides the distance to the floor by ~4
    (second-order SPH dispersion at fixed h/Delta); measured 2026-11-22 at kappa = 1:
    0.01263 (4 mm), 0.01006 (2 mm), floor 0.00921."""
    floor = 1.0 - lattice_gradient_factor(1.0)
    coarse = p_wave_mode(0.004)["error"] - floor
    fine = p_wave_mode(0.002)["error"] - floor
    assert coarse > 0 and fine > 0
    assert coarse / fine == pytest.approx(4.0, rel=0.25)
