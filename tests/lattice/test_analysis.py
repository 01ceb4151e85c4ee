"""The lattice analysis helpers: the Glen sweep's point scenes carry the configured stress,
normal load, run length (relaxations over the melt rate) and frozen control."""

import shlex

import yaml

from craquelure.lattice import glen
from craquelure.lattice.analysis import glen_point_scene
from craquelure.lattice.workflow import Jobs
from craquelure.scene import project_root


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
