"""Model dispatch: which models checkpoint, and the CLI's word on --resume for those that don't."""

from __future__ import annotations

import pytest

from craquelure import cli, models


def test_checkpointing_models():
    assert models.checkpoints("drying") and models.checkpoints("lattice")
    assert not models.checkpoints("impact") and not models.checkpoints("softdyn")


def test_resume_on_a_model_without_checkpoints_says_so(tmp_path, capsys):
    out = tmp_path / "pair.nc"
    assert cli.main(["run", "softdyn/two_sphere_separation", "--out", str(out), "--resume"]) == 0
    assert "softdyn runs are short and write no checkpoints" in capsys.readouterr().err
    assert out.is_file()


def test_unknown_model_lists_the_allowed_ones():
    with pytest.raises(models.CraquelureError, match="allowed values"):
        models.checkpoints("fluid")
