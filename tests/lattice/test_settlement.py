"""Elastic gravity check: spec section 12 check 10 (settlement within 5 %, proportional to
H^2)."""

import math

import pytest

from craquelure.lattice import beam, settlement
from craquelure.lattice.initial_state import make_engine
from craquelure.scene import load_scene


def fundamental_rate(kn: float, ks: float, mass: float, ny: int, L: float = 1.0) -> float:  # noqa: N803
    """omega_1 = (pi/2) c_P / H of the clamped-free column."""
    c = math.sqrt(beam.lattice_moduli(kn, ks)["M"] / (mass / beam.cell_area(L)))
    return 0.5 * math.pi * c / settlement.effective_height(ny, L)


def settle(nx, ny, periodic):
    sc = load_scene("lattice/gravity_block", [f"domain.nx={nx}", f"domain.ny={ny}",
                                              f"domain.periodic_x={str(periodic).lower()}"])
    m = math.pi / 4
    w1 = fundamental_rate(1.0, 0.2, m, ny)
    sc = sc.with_overrides([f"numerics.mass_damping={1.5 * w1}"])
    engine, labels = make_engine(sc, 0)
    engine.run(int(25.0 / w1 / engine.dt))
    got = settlement.measured_settlement(engine.qref[1], engine.q[1], labels["row"],
                                         engine.qref[0])
    want = settlement.predicted_settlement(1.0, 0.2, m, sc.get("material.g"), ny)
    # at rest: kinetic energy negligible against the elastic energy
    s = engine.series_array()
    assert s[-1, 1] < 1e-6 * s[-1, 3]
    return got, want


@pytest.mark.parametrize("ny", [10, 20])
def test_settlement_of_laterally_constrained_column(ny):
    got, want = settle(8, ny, periodic=True)
    assert got == pytest.approx(want, rel=0.05)


def test_settlement_scales_with_height_squared():
    a, _ = settle(8, 10, periodic=True)
    b, _ = settle(8, 20, periodic=True)
    ratio = settlement.effective_height(20) ** 2 / settlement.effective_height(10) ** 2
    assert b / a == pytest.approx(ratio, rel=0.05)


def test_wide_free_block_middle_within_5_percent():
    got, want = settle(48, 12, periodic=False)
    assert got == pytest.approx(want, rel=0.05)
