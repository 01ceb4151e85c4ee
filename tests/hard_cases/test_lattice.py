"""Lattice hard cases: the step around the critical one, and steps far below it.

- 0.9x and 1.2x the critical step of the central-difference update (2/omega_max from a dense
  eigen-solve of the scene's own lattice, undamped): the first runs and conserves energy, the
  second is stopped by the energy guard with its message, writing nothing.
- dt_factor = 2e-6 (a step a million times below the usual): the energy guard must not fire.
  It did, with and without gravity: the implicit mass-damping update was written in absolute
  positions, so x (1 + h2)/fl(1 + h2) != x at rest acted as a spurious force eps |x| m/dt^2
  that outgrew gravity at dt ~ 1e-6; the update is now an increment of x.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.linalg

from craquelure.errors import SimulationDiverged
from craquelure.lattice.api import run as lattice_run
from craquelure.lattice.engine import stable_step_estimate
from craquelure.lattice.initial_state import make_engine
from craquelure.scene import load_scene

from ..lattice import linear_beam

# a 12 x 6 block, bottom row clamped, under gravity, no damping: a clean critical step
BLOCK = ["domain.nx=12", "domain.ny=6", "material.g=1.0e-3", "numerics.bond_damping=0.0",
         "numerics.mass_damping=0.0", "numerics.series_every=10", "outputs.frames=2",
         "numerics.checkpoint_every=0"]


def critical_dt_factor(scene) -> float:
    """dt_factor of the true critical step: (2/omega_max) / (2/omega_est), omega_max from the
    stiffness of the free dofs (clamped dofs removed) scaled by the masses."""
    engine, _ = make_engine(scene, 0)
    s = engine.system
    stiffness = linear_beam.assemble_global(s.x, s.y, s.bi, s.bj, s.kn, s.ka, s.kb).toarray()
    m = np.column_stack([s.mass, s.mass, s.inertia]).ravel()
    free = ~np.asarray(s.fix, bool).T.ravel()
    k = (stiffness / np.sqrt(np.outer(m, m)))[np.ix_(free, free)]
    omega_max = math.sqrt(scipy.linalg.eigvalsh(k)[-1])
    return (2.0 / omega_max) / stable_step_estimate(s)


@pytest.fixture(scope="module")
def critical():
    return critical_dt_factor(load_scene("lattice/gravity_block", BLOCK))


def test_critical_step_is_above_the_quick_estimate(critical):
    assert 1.0 < critical < 1.6  # the estimate is safe (spec section 5: by 1.16-1.37)


def test_0_9_of_the_critical_step_is_stable(critical, tmp_path):
    scene = load_scene("lattice/gravity_block", [*BLOCK, f"numerics.dt_factor={0.9 * critical}",
                                                 "outputs.t_end=400.0"])
    out = lattice_run(scene, tmp_path / "run.nc", seed=0)
    from craquelure.io import open_dataset

    ds = open_dataset(out)
    assert ds.attrs["steps"] > 500
    total, mech = ds["total"].values, ds["kinetic"].values + ds["elastic"].values
    assert np.isfinite(total).all()
    assert np.abs(total - total[0]).max() < 0.05 * mech.max()


def test_1_2_of_the_critical_step_is_stopped_by_the_guard(critical, tmp_path):
    scene = load_scene("lattice/gravity_block", [*BLOCK, f"numerics.dt_factor={1.2 * critical}",
                                                 "outputs.t_end=400.0"])
    with pytest.raises(SimulationDiverged, match="check failed at step .*reduce "
                                                 "numerics.dt_factor"):
        lattice_run(scene, tmp_path / "run.nc", seed=0)
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("g", [0.0, 1.0e-4])
@pytest.mark.parametrize("mass_damping", [0.0, 0.15])
def test_energy_guard_is_quiet_at_tiny_steps(g, mass_damping):
    """dt_factor 2e-6 and 2e-7, 2000 steps: the guard stays quiet; with g = 0 nothing moves
    (to 1e-15); with gravity nothing moves further than 2x free fall g t^2/2 (before the fix the
    mass-damping round-off pushed the block ~5x faster than gravity). Note: at these steps
    the gravity increment g dt^2 ~ 1e-16 is below the resolution of positions of order 5, so
    the block does not fall at all: positions are absolute (a known limit, not a blow-up)."""
    for factor in (2.0e-6, 2.0e-7):
        scene = load_scene("lattice/gravity_block", [
            "domain.nx=16", "domain.ny=6", f"material.g={g}", f"numerics.dt_factor={factor}",
            f"numerics.mass_damping={mass_damping}", "numerics.series_every=50",
            "outputs.t_end=1.0"])
        engine, _ = make_engine(scene, 0)
        q0 = engine.q.copy()
        engine.run(2000)  # raises SimulationDiverged if the guard fires
        moved = np.abs(engine.q - q0).max()
        free_fall = g * engine.dt**2 * 2000 * 2001 / 2
        # 2x: the per-step increment is a few ulps, so it is rounded by up to ~50 %
        assert moved <= max(1e-15, 2.0 * free_fall)


def test_guard_at_an_unresolvable_step_asks_for_a_larger_one():
    """Calving block (buoyancy, bed, drag, contact) at dt_factor 2e-6: per-step increments of
    a few rounding units of the positions distort the motion by tens of percent, so the energy
    budget fails; the guard must then say the step is too small, never advise a smaller one."""
    scene = load_scene("lattice/calving", ["domain.nx=24", "domain.ny=8",
                                           "domain.water_level=5.0", "numerics.dt_factor=2e-6",
                                           "numerics.series_every=50", "outputs.t_end=1.0"])
    engine, _ = make_engine(scene, 0)
    try:
        engine.run(2000)
    except SimulationDiverged as exc:
        assert "increase numerics.dt_factor" in str(exc), str(exc)
        assert "reduce numerics.dt_factor" not in str(exc)
