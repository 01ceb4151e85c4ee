"""DAG helpers of ``workflow/rules/softdyn.smk`` (kept here: the linter forbids functions next
to rules in a Snakefile), bound to the config's ``softdyn`` section (no module state)."""


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
        return int(self.section["sweep_batches"])  # required by the config schema

    def sweep_batch_files(self, wildcards) -> list[str]:
        """One dataset per batch (``sweep_batches`` jobs): as many as the config asks for; the
        jobs split the scene's grid points by cost when they run (a batch beyond the number
        of points is empty), so no scene is read while the DAG is built."""
        return [f"results/softdyn/{wildcards.scene}/batches/b{b}.nc"
                for b in range(self.n_batches())]
