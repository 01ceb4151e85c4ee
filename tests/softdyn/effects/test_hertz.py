"""The hertz effect's deflection rules: the literal rule (spec 9.3) breaks the gap law by
n-dot . q."""


import numpy as np

from ..test_engine import random_t1_state, t1_setup


def test_literal_rule_breaks_the_gap_law_by_ndot_q():
    """The literal lab-frame rule adds ndot.q to dh/dt (spec 9.3): that is what jams the T1."""
    rng = np.random.default_rng(6)
    setup = t1_setup("numerics.deflection_rule=literal")
    sysm = setup.system
    y = random_t1_state(setup, rng)
    ev = sysm.evaluate(0.05 * setup.tau, y)
    v = ev["v"]
    sdot = ev["ydot"][sysm.n * sysm.d: sysm.n * sysm.d + sysm.n_pairs]
    extra = []
    for k, (i, j) in enumerate(sysm.pairs):
        vij = v[i] - v[j]
        ndot = (vij - (ev["n"][k] @ vij) * ev["n"][k]) / ev["r"][k]
        hdot = ev["n"][k] @ vij + sdot[k]
        expected = -ev["f_n"][k] / ev["zeta_n"][k] + ndot @ ev["q"][k]
        assert abs(hdot - expected) <= 1e-12 * np.abs(v).max()
        extra.append(abs(ndot @ ev["q"][k]))
    assert max(extra) > 1e-6 * np.abs(v).max()  # the difference is really there
