"""Glen's law from melting-freezing: spec section 12 check 8 (Glen exponent, Newtonian control,
mu ~ 1/A); check 9 (bounded strain without melting, steady creep with it) is in
effects/test_melting.py."""

import math

import numpy as np
import pytest

from craquelure.lattice import glen
from craquelure.lattice.initial_state import make_engine
from craquelure.scene import Scene, load_scene
from tests.lattice.blocks import block_height

SMALL = ["domain.nx=12", "domain.ny=10"]


def measure(scene: Scene, tau: float, seed: int = 0) -> dict[str, float]:
    """Run one stress of the sweep in memory and return tau, rates and mu."""
    sc = scene.with_overrides(glen.overrides(scene, tau))
    engine, _ = make_engine(sc, seed)
    engine.run(int(math.ceil(sc.get("outputs.t_end") / engine.dt)))
    series = engine.series_array()
    out = glen.strain_rate(series[:, 0], series[:, 13], block_height(sc))
    out.update(tau=tau, mu=glen.viscosity(tau, out["gamma_dot"]),
               melt_rate=float(series[-1, 12] / (series[-1, 0] * engine.system.bi.size)))
    return out


@pytest.fixture(scope="module")
def scene():
    return load_scene("lattice/glen", SMALL)


@pytest.mark.slow
def test_viscosity_slope_is_minus_two(scene):
    taus = np.geomspace(2e-3, 2e-2, 4)
    mu = [measure(scene, t)["mu"] for t in taus]
    slope, _ = glen.fit_power_law(taus, mu)
    assert slope == pytest.approx(-2.0, abs=0.2)


def test_frozen_rate_is_newtonian(scene):
    frozen = scene.with_overrides([f"melting.frozen_rate={glen.melt_rate_estimate(scene, 1e-2)}"])
    taus = np.geomspace(2e-3, 2e-2, 3)
    mu = [measure(frozen, t)["mu"] for t in taus]
    slope, _ = glen.fit_power_law(taus, mu)
    assert slope == pytest.approx(0.0, abs=0.2)


def test_viscosity_inversely_proportional_to_rate_factor(scene):
    mu1 = measure(scene, 1e-2)["mu"]
    mu2 = measure(scene.with_overrides(["melting.rate_factor=50.0"]), 1e-2)["mu"]
    # same number of relaxation times in both runs; statistical scatter ~5 %
    assert mu1 / mu2 == pytest.approx(2.0, rel=0.15)
