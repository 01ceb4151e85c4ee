"""The fracture effect: spec section 13 check 11 (the first removal on a perfect lattice) and
effects on demand (no removal without ``fracture``)."""

from __future__ import annotations

import numpy as np


def test_onset_on_perfect_lattice(make_scene, make_lattice_engine, monkeypatch):
    """Check 11 (time in units of t* = sigma_Y/v_r so the test is short): on a perfect lattice
    with sigma_0 ~ U(-0.01, 0.01) sigma_Y the first removal comes at t/t* in
    [223/227.3, 230/227.3]; no particle is removed while its mean stress <= sigma_Y."""
    v_r, sigma_y = 1e-3, 5e-3
    t_star = sigma_y / v_r
    scene = make_scene(material={"drying_rate": v_r},
                       numerics={"integrator": "abm4"},
                       outputs={"t_end": 1.2 * t_star, "times": [1.2 * t_star]})
    rng = np.random.default_rng(2)
    eng = make_lattice_engine(scene, sigma_e=rng.uniform(-0.01, 0.01, (3, 400)) * sigma_y)
    removed_stress = []
    original = type(eng).remove_overstressed

    def spy(self):
        doomed = self.alive & (self.mean_stress > self.yield_stress)
        removed_stress.extend(self.mean_stress[doomed])
        return original(self)

    monkeypatch.setattr(type(eng), "remove_overstressed", spy)
    first = None
    while eng.t < 1.2 * t_star and first is None:
        if eng.step():
            first = eng.t
    assert first is not None
    assert 223 / 227.3 <= first / t_star <= 230 / 227.3
    assert min(removed_stress) > sigma_y


def test_without_fracture_nothing_is_removed(make_scene, make_lattice_engine):
    """Effects on demand: past the yield stress, no particle is removed without `fracture`."""
    scene = make_scene(effects=["elasticity", "viscosity", "drying", "substrate", "xsph",
                                "continuity"], material={"drying_rate": 0.05})
    eng = make_lattice_engine(scene)
    for _ in range(50):
        eng.step()
    assert eng.mean_stress.max() > scene.get("material.yield_stress")
    assert eng.alive.all() and eng.n_removed == 0
