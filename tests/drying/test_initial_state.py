"""Initial states of the drying paste: the minimum gap of the random positions is a scene
parameter, and more disorder than the mass solve can make consistent is refused unless a study
asks for it (``check=False``, benchmarks/drying_initial_disorder.py)."""

from __future__ import annotations

import numpy as np
import pytest

from craquelure.drying.initial_state import build_initial_state
from craquelure.drying.mass_consistency import MassSolveError


def _min_distance(ds, length):
    x, y = ds["x"].values, ds["y"].values
    dx = np.abs(x[:, None] - x[None, :])
    dy = np.abs(y[:, None] - y[None, :])
    dx, dy = np.minimum(dx, length - dx), np.minimum(dy, length - dy)
    d = np.hypot(dx, dy)
    np.fill_diagonal(d, np.inf)
    return d.min()


@pytest.mark.parametrize("gap", [0.8, 0.5])
def test_rsa_gap_is_the_scene_parameter(make_scene, gap):
    """Positions keep at least the scene's gap x L/sqrt(N) (periodic distance) and come close
    to it (RSA fills the plane up to the gap)."""
    scene = make_scene(domain={"box_length": 2.0}, particles={
        "n": 1600, "placement": "rsa", "rsa_min_separation": gap},
        numerics={"mass_solve": {"method": "clamped_cg"}})
    ds = build_initial_state(scene, 1, check=False)
    spacing = 2.0 / np.sqrt(1600)
    assert gap * spacing * (1 - 1e-12) <= _min_distance(ds, 2.0) < 1.05 * gap * spacing


def test_disordered_state_is_refused_unless_unchecked(make_scene):
    """At half the spacing the clamped solve keeps every mass >= 0.1 m_bar but misses check 3:
    the default build refuses it, check=False returns it with the solve's report."""
    scene = make_scene(domain={"box_length": 2.0}, particles={
        "n": 1600, "placement": "rsa", "rsa_min_separation": 0.5},
        numerics={"mass_solve": {"method": "clamped_cg"}})
    with pytest.raises(MassSolveError, match="drying spec 13.3"):
        build_initial_state(scene, 1)
    ds = build_initial_state(scene, 1, check=False)
    m_bar = 4.0 / 1600
    assert ds["mass"].values.min() >= 0.1 * m_bar * (1 - 1e-12)
    assert ds.attrs["masses_at_floor"] > 0 and ds.attrs["stopped_by"] == "rtol"
    assert abs(ds["mass"].values.sum() / 4.0 - 1.0) <= 0.01
