"""Helpers of ``workflow/rules/softdyn.smk`` (kept here: the linter forbids functions next to
rules in a Snakefile)."""

from __future__ import annotations

from craquelure.scene import load_scene
from craquelure.softdyn.studies import sweep_points

_SECTION: dict = {}


def configure(section: dict) -> None:
    """Remember the workflow config's ``softdyn`` section (its ``set`` overrides)."""
    _SECTION.clear()
    _SECTION.update(section)


def overrides() -> list[str]:
    return list(_SECTION.get("set", []))


def scene_path(wildcards) -> str:
    return f"config/scenes/softdyn/{wildcards.scene}.yaml"


def sweep_point_files(wildcards) -> list[str]:
    """One dataset per grid point inside the scene's window."""
    scene = load_scene(scene_path(wildcards), overrides())
    return [f"results/softdyn/{wildcards.scene}/points/p{i}_{j}.nc"
            for i, j in sweep_points(scene)]
