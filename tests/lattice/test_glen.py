"""Glen's law from melting-freezing: spec section 12 check 8 (Glen exponent, Newtonian control,
mu ~ 1/A); check 9 (bounded strain without melting, steady creep with it) is in
effects/test_melting.py."""

import numpy as np
import pytest

from craquelure.lattice import glen
from craquelure.scene import load_scene

SMALL = ["domain.nx=12", "domain.ny=10"]


@pytest.fixture(scope="module")
def scene():
    return load_scene("lattice/glen", SMALL)


@pytest.mark.slow
def test_viscosity_slope_is_minus_two(scene):
    taus = np.geomspace(2e-3, 2e-2, 4)
    mu = [glen.measure(scene, t)["mu"] for t in taus]
    slope, _ = glen.fit_power_law(taus, mu)
    assert slope == pytest.approx(-2.0, abs=0.2)


def test_frozen_rate_is_newtonian(scene):
    frozen = scene.with_overrides([f"melting.frozen_rate={glen.melt_rate_estimate(scene, 1e-2)}"])
    taus = np.geomspace(2e-3, 2e-2, 3)
    mu = [glen.measure(frozen, t)["mu"] for t in taus]
    slope, _ = glen.fit_power_law(taus, mu)
    assert slope == pytest.approx(0.0, abs=0.2)


def test_viscosity_inversely_proportional_to_rate_factor(scene):
    mu1 = glen.measure(scene, 1e-2)["mu"]
    mu2 = glen.measure(scene.with_overrides(["melting.rate_factor=50.0"]), 1e-2)["mu"]
    # same number of relaxation times in both runs; statistical scatter ~5 %
    assert mu1 / mu2 == pytest.approx(2.0, rel=0.15)
