"""The ``gradient_correction`` effect: a linear velocity field gives the exact velocity gradient
at a free edge."""

from __future__ import annotations

import numpy as np

from craquelure.drying.engine import X


def test_gradient_correction_makes_the_velocity_gradient_exact_at_a_free_edge(make_scene):
    """Effect ``gradient_correction``: a linear velocity field v = (a x, 0) on a strip with free
    edges gives the viscous stress eta a at every particle, edges included (raw kernel
    gradient: about eta a / 2 on the last row); in the bulk both agree to check 2's 2e-3."""
    from craquelure.drying.api import engine_from_initial
    from craquelure.drying.initial_state import build_initial_state

    length, width, a = 2.0, 1.2, 1e-3
    rows = {}
    for extra in ([], ["gradient_correction"]):
        scene = make_scene(
            effects=["viscosity", *extra], domain={"box_length": length},
            particles={"n": 1600, "placement": "square_lattice",
                       "excluded_bands": [{"axis": "x", "lo": width, "hi": length}]},
            numerics={"mass_solve": {"method": "equal"}})
        init = build_initial_state(scene, seed=0)
        eng = engine_from_initial(scene, init)
        eng.state[2] = a * (eng.state[X] - 0.5 * width)
        eng.evaluate(eng.state, 0.0)
        rows[bool(extra)] = eng.stress[0] / a  # eta = 1
    x = np.mod(eng.state[X], length)
    edge = (x < 0.05) | (x > width - 0.05)
    bulk = np.abs(x - 0.5 * width) < 0.5 * width - 0.25
    assert np.abs(rows[True] - 1.0).max() < 1e-9
    assert rows[False][edge].max() < 0.6
    assert np.abs(rows[False][bulk] - 1.0).max() < 2e-3
