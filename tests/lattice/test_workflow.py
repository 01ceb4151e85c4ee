"""Workflow helpers of the lattice rules: overrides from the config build valid scenes."""

import yaml

from craquelure.lattice.workflow import Jobs
from craquelure.scene import load_scene, project_root

from .test_analysis import overrides_of


def test_every_profile_builds_valid_run_scenes():
    for profile in ("config", "ci", "paper"):
        cfg = yaml.safe_load((project_root() / "config" / f"{profile}.yaml").read_text())
        jobs = Jobs(cfg["lattice"], profile)
        for scene in cfg["lattice"]["runs"]:
            args = jobs.run_set(type("W", (), {"scene": scene}))
            load_scene(f"lattice/{scene}", overrides_of(args) if args else [])
        assert "results/lattice/glen/glen.png" in jobs.targets()
