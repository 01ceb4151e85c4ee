"""Soft Dynamics scene rules a schema cannot state (each refusal names the key) and the memory
estimate, linear in the number of study points."""

import re

import pytest

from craquelure.errors import SceneError
from craquelure.scene import load_scene
from craquelure.softdyn import rules


@pytest.mark.parametrize("scene, overrides, message", [
    ("softdyn/t1_single_ci", ["numerics.integrator=heun", "numerics.dt=200.0"],
     r"numerics\.dt: 200\.0 is not allowed; the step must not be longer than outputs\.t_end"),
    ("softdyn/t1_sweep_ci", ["study.window=[30.0, 0.5]"],
     r"study\.window: \[30\.0, 0\.5\] must be increasing"),
])
def test_cross_field_problems_name_the_key(scene, overrides, message):
    with pytest.raises(SceneError, match=message):
        load_scene(scene, overrides)


def test_the_rules_accept_the_built_in_scenes():
    for name in ("t1_single_ci", "t1_sweep_ci", "t1_phase_ci", "t1_accuracy_ci",
                 "two_sphere_approach", "two_sphere_separation"):
        assert rules.scene_problems(load_scene(f"softdyn/{name}").data) == []


def test_memory_estimate_is_linear_in_the_study_points():
    two = load_scene("softdyn/t1_sweep_ci")
    three = load_scene("softdyn/t1_sweep_ci", ["study.h0=[0.03, 0.1, 0.3]"])
    need2, what2 = rules.memory_estimate(two.data)
    need3, what3 = rules.memory_estimate(three.data)
    points = [int(re.search(r"x (\d+) study points", w).group(1)) for w in (what2, what3)]
    assert points == [2 * 2, 3 * 2]  # h0 x reduced_force
    assert (need3 - 1e6) / (need2 - 1e6) == pytest.approx(1.5, rel=1e-12)
