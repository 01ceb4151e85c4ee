"""The core scene rules (craquelure.scene_rules): NaN, inf and integers beyond 64 bits are found
anywhere in a scene mapping, a step count a run cannot finish is named, and the memory check
refuses what the machine cannot hold."""

from __future__ import annotations

import math

import pytest

from craquelure import scene_rules
from craquelure.errors import SceneError
from craquelure.scene import load_scene


def test_non_finite_values_are_found_in_lists_and_nested_mappings():
    data = {"a": 1.0, "b": [0.0, math.nan, {"c": math.inf}], "d": {"e": -math.inf},
            "f": 2**63, "g": 2**63 - 1, "h": True, "i": "nan"}
    found = scene_rules.non_finite_values(data)
    assert [where for where, _ in found] == ["b[1]", "b[2].c", "d.e", "f"]


def test_steps_problem_names_the_key_and_the_step_count():
    assert scene_rules.steps_problem("numerics.dt", 1.0, 1e-3) is None
    assert "must be > 0" in scene_rules.steps_problem("numerics.dt", 1.0, 0.0)
    message = scene_rules.steps_problem("numerics.dt", 1.0, 1e-13)
    assert message.startswith("numerics.dt: the run would need 1e+13 steps")


def test_memory_problem_compares_the_estimate_with_the_memory_available():
    data = load_scene("drying/ci").data
    need, _ = scene_rules.memory_estimate(data)
    assert need > 0
    plenty = 2 * need / scene_rules.MEMORY_FRACTION
    assert scene_rules.memory_problem(data, available=plenty) is None
    assert "of memory" in scene_rules.memory_problem(data, available=need)


def test_memory_estimate_refuses_a_scene_that_cannot_fit_and_says_how_much():
    with pytest.raises(SceneError, match=r"needs about [\d.e+]+ GiB of memory"):
        load_scene("impact/ci", ["particles.diameter_cells=1000000000000"])
    with pytest.raises(SceneError, match="Shepard mesh"):
        load_scene("drying/ci", ["domain.box_length=1000"])


def test_optional_is_the_value_or_none_when_the_scene_does_not_set_it():
    """``optional`` reads a parameter the schema leaves optional: its value when set (a falsy
    one too), None when absent; ``get`` of the same absent key raises."""
    scene = load_scene("drying/onset_fixed_f")
    assert scene.optional("material.drying_stress_cap") == 5.0e-3
    assert scene.optional("numerics.step_control.dt_max") == 0.2  # nested, schema default
    assert scene.optional("particles.excluded_bands") == []
    assert scene.optional("outputs.times") is not None
    view = scene_rules.SceneView({"model": "drying", "effects": [], "outputs": {"t_end": 1.0},
                                  "material": {"eta": 0.0}})
    assert view.optional("material.eta") == 0.0
    assert view.optional("material.lame_lambda") is None
    assert view.optional("domain.box_length") is None  # a section the data does not have
    with pytest.raises(KeyError):
        view.get("material.lame_lambda")
