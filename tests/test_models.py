"""Model dispatch: every model provides a run stage; unknown models are named."""

from __future__ import annotations

import pytest

from craquelure import models


@pytest.mark.parametrize("model", models.MODELS)
def test_every_model_runs_through_a_run_stage(model):
    assert callable(models.stage(model, "run"))


def test_unknown_model_lists_the_allowed_ones():
    with pytest.raises(models.CraquelureError, match="allowed values"):
        models.model_api("fluid")
