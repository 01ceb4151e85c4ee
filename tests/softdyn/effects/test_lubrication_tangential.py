"""Tangential lubrication (spec check 6): a loaded pair slides at T/zeta_t once q has relaxed."""


import numpy as np
import pytest

from craquelure.scene import load_scene
from craquelure.softdyn.engine import run
from craquelure.softdyn.initial_state import build


def test_steady_sliding_speed_is_t_over_zeta_t():
    """Check 6: a pair under a normal load and a tangential load slides, once q has relaxed
    (10 relaxation times), at the speed T/zeta_t with T the tangential load in the pair frame."""
    setup = build(load_scene("softdyn/two_sphere_approach", [
        "particles.h0=1.0e-2", "loads.reduced_force=1.0e-3",
        "loads.tangential_over_normal=0.1", "outputs.stop=none", "outputs.t_end=0.3"]))
    res = run(setup, sample_times_tau=np.array([0.3]))
    ev = setup.system.evaluate(res.t[-1], res.y[-1])
    n = ev["n"][0]
    vrel = ev["v"][0] - ev["v"][1]
    v_t = vrel - (vrel @ n) * n
    load = ev["load"][0]
    t_pair = load - (load @ n) * n
    assert np.linalg.norm(v_t) == pytest.approx(np.linalg.norm(t_pair) / ev["zeta_t"][0],
                                                rel=1e-2)
    assert np.linalg.norm(v_t) > 0.0
