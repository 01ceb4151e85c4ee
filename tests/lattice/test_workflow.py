"""Workflow helpers of the lattice rules: overrides from the config build valid scenes."""

import shlex

import yaml

from craquelure.lattice import glen
from craquelure.lattice.analysis import glen_point_scene
from craquelure.lattice.workflow import Jobs
from craquelure.scene import load_scene, project_root


def overrides_of(args: str) -> list[str]:
    words = shlex.split(args)
    assert words[0::2] == ["--set"] * (len(words) // 2)
    return words[1::2]


def test_glen_point_overrides_build_the_sweep():
    cfg = yaml.safe_load((project_root() / "config" / "ci.yaml").read_text())["lattice"]
    jobs = Jobs(cfg, "ci")
    for kind in ("glen", "frozen"):
        key = "stresses" if kind == "glen" else "frozen_stresses"
        for k, tau in enumerate(cfg["glen"][key]):
            scene = glen_point_scene(jobs.glen_scene_file, cfg, kind, k)
            assert scene.get("loads.top_shear_stress") == tau
            assert scene.get("loads.top_normal_stress") == 0.1 * tau
            lam = glen.melt_rate_estimate(scene, tau)
            assert scene.get("outputs.t_end") == cfg["glen"]["relaxations"] / lam
            assert (scene.get("melting.frozen_rate") > 0) == (kind == "frozen")


def test_every_profile_builds_valid_run_scenes():
    for profile in ("config", "ci", "paper"):
        cfg = yaml.safe_load((project_root() / "config" / f"{profile}.yaml").read_text())
        jobs = Jobs(cfg["lattice"], profile)
        for scene in cfg["lattice"]["runs"]:
            args = jobs.run_set(type("W", (), {"scene": scene}))
            load_scene(f"lattice/{scene}", overrides_of(args) if args else [])
        assert "results/lattice/glen/glen.png" in jobs.targets()
