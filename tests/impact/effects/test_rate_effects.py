"""The opt-in rate effects in the SPH engine (scene impact/cscm): the dynamic strength is higher,
the same impact cracks less and still closes its energy balance."""


import numpy as np
import pytest

from craquelure.impact.api import simulate
from craquelure.scene import load_scene

from .test_cap_plasticity import SMALL


@pytest.mark.slow
def test_rate_effects_raise_the_strength_in_the_disc():
    """Opt-in rate effects: the same impact with them cracks less (the dynamic tensile
    strength is higher) and still closes its energy balance."""
    effects = load_scene("impact/cscm").effects
    with_rate = load_scene("impact/cscm", [*SMALL, f"effects=[{', '.join(effects)}, "
                                                   "rate_effects]"])
    _, eng, series, _ = simulate(with_rate, 0, progress=False)
    _, plain, _, _ = simulate(load_scene("impact/cscm", SMALL), 0, progress=False)
    assert np.abs(series["balance_error"]).max() < 0.02
    assert eng.state.dmg.mean() < plain.state.dmg.mean()
