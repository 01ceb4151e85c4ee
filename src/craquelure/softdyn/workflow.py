"""DAG helpers of ``workflow/rules/softdyn.smk`` (kept here: the linter forbids functions next
to rules in a Snakefile), bound to the config's ``softdyn`` section (no module state)."""

from __future__ import annotations

from craquelure.scene import load_scene
from craquelure.softdyn.studies import sweep_batches, sweep_points


class Jobs:
    """Config-bound helpers for the Snakemake rules (input functions take ``wildcards``)."""

    def __init__(self, section: dict) -> None:
        self.section = section

    def overrides(self) -> list[str]:
        return list(self.section.get("set", []))

    @staticmethod
    def scene_path(wildcards) -> str:
        return f"config/scenes/softdyn/{wildcards.scene}.yaml"

    def n_batches(self) -> int:
        return int(self.section.get("sweep_batches", 1))

    def sweep_batch_files(self, wildcards) -> list[str]:
        """One dataset per batch of grid points (``sweep_batches`` jobs, balanced by cost)."""
        scene = load_scene(self.scene_path(wildcards), self.overrides())
        n = len(sweep_batches(scene, self.n_batches()))
        return [f"results/softdyn/{wildcards.scene}/batches/b{b}.nc" for b in range(n)]

    def sweep_point_files(self, wildcards) -> list[str]:
        """One dataset per grid point inside the scene's window."""
        scene = load_scene(self.scene_path(wildcards), self.overrides())
        return [f"results/softdyn/{wildcards.scene}/points/p{i}_{j}.nc"
                for i, j in sweep_points(scene)]
