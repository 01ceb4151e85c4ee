"""Lattice scene rules: a scene whose step count is out of bounds is refused, naming the key."""

from __future__ import annotations

import pytest

from craquelure.errors import SceneError
from craquelure.scene import load_scene


def test_lattice_step_count_is_bounded():
    with pytest.raises(SceneError, match="numerics.dt_factor: the run would need"):
        load_scene("lattice/glen", ["particles.spacing=1e-9"])
