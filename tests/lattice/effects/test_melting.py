"""Melting-freezing (spec section 12 check 9): bounded strain without melting, steady creep
with it."""

import pytest

from craquelure.lattice import beam, glen
from craquelure.lattice.initial_state import beam_constants, make_engine
from craquelure.scene import load_scene
from tests.lattice.blocks import block_height

SMALL = ["domain.nx=12", "domain.ny=10"]


@pytest.fixture(scope="module")
def scene():
    return load_scene("lattice/glen", SMALL)


def test_without_melting_strain_stays_bounded(scene):
    sc = scene.with_overrides([*glen.overrides(scene, 1e-2), "effects=[beams]"])
    engine, _ = make_engine(sc, 0)
    engine.run(int(sc.get("outputs.t_end") / engine.dt))
    s = engine.series_array()
    t, ux = s[:, 0], s[:, 13]
    c = beam_constants(sc)
    static = 1e-2 / beam.lattice_moduli(c.kn, c.ks)["mu"] * block_height(sc)
    # elastic: bounded by the dynamic overshoot of a ramped load (< 2x static) ...
    assert ux.max() < 2.0 * static
    # ... and no creep: two late windows have the same mean (the shear mode still rings)
    mid = ux[(t > 0.4 * t[-1]) & (t < 0.7 * t[-1])].mean()
    end = ux[t >= 0.7 * t[-1]].mean()
    assert end == pytest.approx(mid, rel=0.02)
    assert end == pytest.approx(static, rel=0.1)


def test_with_melting_steady_strain_rate(scene):
    sc = scene.with_overrides(glen.overrides(scene, 1e-2, relaxations=8.0))
    engine, _ = make_engine(sc, 0)
    engine.run(int(sc.get("outputs.t_end") / engine.dt))
    s = engine.series_array()
    rates = glen.strain_rate(s[:, 0], s[:, 13], block_height(sc), fit_from=0.25)
    assert rates["gamma_dot_second"] == pytest.approx(rates["gamma_dot_first"], rel=0.10)
    assert rates["gamma_dot"] > 0
