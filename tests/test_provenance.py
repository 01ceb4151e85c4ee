"""Provenance attributes carried by every dataset."""

from __future__ import annotations

import re
import time
from datetime import datetime

import numba
import numpy
import scipy

import craquelure
from craquelure.provenance import WallClock, git_commit, library_versions, provenance_attrs
from craquelure.scene import load_scene


def test_git_commit_is_a_sha_with_optional_dirty_flag():
    assert re.fullmatch(r"[0-9a-f]{40}(-dirty)?|unknown", git_commit())


def test_library_versions():
    v = library_versions()
    assert v["version_numpy"] == numpy.__version__
    assert v["version_numba"] == numba.__version__
    assert v["version_scipy"] == scipy.__version__
    assert v["version_craquelure"] == craquelure.__version__


def test_wall_clock():
    clock = WallClock()
    start = datetime.fromisoformat(clock.start_iso)
    assert start.tzinfo is not None
    t0 = clock.elapsed
    time.sleep(0.01)
    assert clock.elapsed >= t0 + 0.009


def test_a_job_records_the_commit_it_started_with(monkeypatch):
    """A run that outlives a commit ran the code it started with: the dataset names that
    commit, not the one checked out when it is written."""
    from craquelure import provenance

    monkeypatch.setattr(provenance, "git_commit", lambda: "a" * 40)
    clock = WallClock()
    monkeypatch.setattr(provenance, "git_commit", lambda: "b" * 40)
    attrs = provenance_attrs(load_scene("drying/ci"), 1, clock)
    assert attrs["git_commit"] == "a" * 40


def test_provenance_attrs():
    scene = load_scene("drying/ci", ["numerics.dt=2e-3"])
    clock = WallClock()
    attrs = provenance_attrs(scene, 7, clock, extra_wall_time=10.0)
    assert attrs["seed"] == 7
    assert attrs["scene"] == scene.text and "dt: 0.002" in attrs["scene"]
    assert attrs["scene_source"] == scene.source_text
    assert attrs["scene_overrides"] == "numerics.dt=2e-3"
    assert attrs["effects"] == ",".join(scene.effects)
    assert attrs["model"] == "drying" and attrs["scene_name"] == "ci"
    assert attrs["wall_time_s"] >= 10.0
    assert attrs["start_time"] == clock.start_iso
    assert attrs["git_commit"] == git_commit()
    assert provenance_attrs(scene, None, clock, effects=["drying"])["effects"] == "drying"
    assert "seed" not in provenance_attrs(scene, None, clock)
    for value in attrs.values():  # netCDF attributes: str or number only
        assert isinstance(value, str | int | float)
