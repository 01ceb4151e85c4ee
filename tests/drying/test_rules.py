"""Drying scene rules (craquelure.drying.rules): the step a run takes is numerics.dt halved
until it is below 0.6 of the viscous stability limit, and the rules refuse what a run cannot do."""

from __future__ import annotations

import math

import pytest

from craquelure.drying import rules
from craquelure.drying.integrators import REAL_AXIS_LIMIT
from craquelure.errors import SceneError
from craquelure.scene import load_scene


@pytest.mark.parametrize("eta", [0.5, 2.0, 8.0, 40.0])
def test_run_step_is_dt_halved_below_the_viscous_limit(eta):
    scene = load_scene("drying/ci", [f"material.eta={eta}"])
    dt0, dt = scene.get("numerics.dt"), rules.run_step(scene.data)
    limit = REAL_AXIS_LIMIT[scene.get("numerics.integrator")] / rules.viscous_spectral_radius(scene)
    halvings = math.log2(dt0 / dt)
    assert halvings == pytest.approx(round(halvings), abs=1e-12)  # dt0 / 2^k
    assert dt <= 0.6 * limit < 2 * dt or dt == dt0 <= 0.6 * limit  # the first step below


def test_run_step_without_adaptation_is_numerics_dt():
    scene = load_scene("drying/ci", ["material.eta=40.0", "numerics.adapt_dt=false"])
    assert rules.run_step(scene.data) == scene.get("numerics.dt")


def test_late_snapshot_and_small_periodic_box_are_refused():
    with pytest.raises(SceneError, match=r"outputs\.times: 99.0 is after outputs\.t_end"):
        load_scene("drying/ci", ["outputs.times=[1.0, 99.0]"])
    with pytest.raises(SceneError, match=r"domain\.box_length: .* at least twice"):
        load_scene("drying/ci", ["domain.box_length=0.3"])
