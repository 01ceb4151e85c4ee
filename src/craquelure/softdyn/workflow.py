"""Helpers of ``workflow/rules/softdyn.smk`` (kept here: the linter forbids functions next to
rules in a Snakefile)."""

from __future__ import annotations

from craquelure.scene import load_scene
from craquelure.softdyn.studies import sweep_batches, sweep_points

_SECTION: dict = {}


def configure(section: dict) -> None:
    """Remember the workflow config's ``softdyn`` section (its ``set`` overrides)."""
    _SECTION.clear()
    _SECTION.update(section)


def overrides() -> list[str]:
    return list(_SECTION.get("set", []))


def scene_path(wildcards) -> str:
    return f"config/scenes/softdyn/{wildcards.scene}.yaml"


def n_batches() -> int:
    return int(_SECTION.get("sweep_batches", 1))


def batch_points(scene_file: str, batch: int) -> list[tuple[int, int]]:
    """The (i, j) grid points of one sweep batch."""
    batches = sweep_batches(load_scene(scene_file, overrides()), n_batches())
    return batches[batch]


def sweep_batch_files(wildcards) -> list[str]:
    """One dataset per batch of grid points (``sweep_batches`` jobs, balanced by cost)."""
    scene = load_scene(scene_path(wildcards), overrides())
    n = len(sweep_batches(scene, n_batches()))
    return [f"results/softdyn/{wildcards.scene}/batches/b{b}.nc" for b in range(n)]


def sweep_point_files(wildcards) -> list[str]:
    """One dataset per grid point inside the scene's window."""
    scene = load_scene(scene_path(wildcards), overrides())
    return [f"results/softdyn/{wildcards.scene}/points/p{i}_{j}.nc"
            for i, j in sweep_points(scene)]
