"""DAG helpers of ``workflow/rules/lattice.smk``: file names, ``--set`` arguments and titles
from the config. Nothing here loads a scene or computes physics (that happens in the jobs)."""

SCENE_DIR = "config/scenes/lattice"


class Jobs:
    """Config-bound helpers for the Snakemake rules (input functions take ``wildcards``)."""

    def __init__(self, cfg: dict, profile: str) -> None:
        self.cfg, self.profile = cfg, profile

    @property
    def glen_scene_file(self) -> str:
        return f"{SCENE_DIR}/{self.cfg['glen']['scene']}.yaml"

    def run_set(self, wildcards) -> str:
        return " ".join(f"--set {item}" for item in self.cfg["runs"][wildcards.scene])

    def glen_points(self, kind: str) -> list[str]:
        n = len(self.cfg["glen"]["stresses" if kind == "glen" else "frozen_stresses"])
        return [f"results/lattice/glen/{kind}/tau{k}.nc" for k in range(n)]

    def title(self, what: str) -> str:
        return f"profile {self.profile}, scene lattice/{what}"

    def targets(self) -> list[str]:
        scenes = list(self.cfg["runs"])
        return ["results/lattice/glen/glen.png", "results/lattice/glen/summary.json",
                *[f"results/lattice/{s}/{s}.png" for s in scenes],
                *[f"results/lattice/{s}/summary.json" for s in scenes],
                "results/lattice/scaling/scaling.png", "results/lattice/accuracy/accuracy.png"]

    def scene_title(self, wildcards) -> str:
        return self.title(wildcards.scene)
