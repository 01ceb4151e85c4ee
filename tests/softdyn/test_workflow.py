"""Workflow helpers of the softdyn rules: the config's overrides, the scene file and one batch
dataset per ``sweep_batches`` (required by the config schema), named without reading the scene."""

import yaml

from craquelure.scene import project_root
from craquelure.softdyn.workflow import Jobs


def test_batches_and_scene_paths():
    w = type("W", (), {"scene": "t1_sweep_ci"})
    jobs = Jobs({"sweep_batches": 3, "set": ["numerics.rtol=1e-6"]})
    files = jobs.sweep_batch_files(w)
    assert files == [f"results/softdyn/t1_sweep_ci/batches/b{b}.nc" for b in range(3)]
    # the config schema requires the count (the workflow keeps no default of its own)
    schema = yaml.safe_load((project_root() / "workflow/schemas/config.schema.yaml").read_text())
    assert "sweep_batches" in schema["properties"]["softdyn"]["required"]
    assert jobs.overrides() == ["numerics.rtol=1e-6"]
    jobs.overrides().append("x=1")  # a copy: the config section is not edited
    assert jobs.overrides() == ["numerics.rtol=1e-6"]
    assert (project_root() / Jobs.scene_path(w)).is_file()


def test_every_profile_has_a_batch_count_the_rules_can_use():
    for profile in ("config", "ci", "paper"):
        cfg = yaml.safe_load((project_root() / "config" / f"{profile}.yaml").read_text())
        assert Jobs(cfg["softdyn"]).n_batches() >= 1
