"""The ``impact/rings`` scene: PySPH's colliding rings in the impact engine."""

import numpy as np
import pytest

from craquelure.impact.api import initial_state, settings
from craquelure.impact.engine import Engine
from craquelure.impact.initial_state import build_specimen, rings
from craquelure.scene import load_scene


@pytest.mark.parametrize(("spacing", "count"), [(5e-4, 17592), (2.5e-4, 70320)])
def test_the_grid_has_pysphs_particle_counts(spacing, count):
    x, y, side = rings(0.03, 0.04, 0.041, spacing)
    assert x.size == count
    r = np.hypot(x - 0.041 * side, y)
    assert r.min() >= 0.03 - 1e-12 and r.max() < 0.04 + 1e-12


def test_scene_is_elastic_with_av_and_as_and_rings_approach():
    scene = load_scene("impact/rings")
    assert set(scene.effects) == {"elasticity", "artificial_viscosity", "artificial_stress"}
    st = settings(scene)
    assert (st.av_alpha, st.av_beta, st.as_epsilon) == (1.0, 1.0, 0.3)
    young = 9 * st.material.bulk * st.material.shear / (3 * st.material.bulk
                                                         + st.material.shear)
    assert young == pytest.approx(1e7, rel=1e-9)
    sp = build_specimen(scene, 0)
    assert sp.n == 17592
    # 0.059 c0 with PySPH's c0 = sqrt(K / rho0)
    assert scene.get("particles.rings.speed") == pytest.approx(
        0.059 * np.sqrt(st.material.bulk / st.rho0), rel=1e-5)
    left = sp.x < sp.x.mean()
    assert (sp.vx[left] > 0).all() and (sp.vx[~left] < 0).all()


def test_rings_collide_symmetrically_and_conserve_momentum():
    """Coarse rings (Delta = 2 mm) through first contact: total momentum stays zero and the
    two centres of mass mirror each other."""
    scene = load_scene("impact/rings", ["particles.spacing=0.002"])
    sp = build_specimen(scene, 0)
    eng = Engine(settings(scene), initial_state(scene, sp))
    left = sp.vx > 0
    m = eng.state.m
    centre = 0.5 * (sp.x[left].mean() + sp.x[~left].mean())
    scale = float(np.sum(m * np.abs(eng.state.vx)))
    while eng.t < 1.2e-5:  # contact at ~4 us
        eng.step()
    st = eng.state
    assert abs(float(np.sum(m * st.vx))) < 1e-9 * scale
    xl = np.sum(m[left] * st.x[left]) / m[left].sum()
    xr = np.sum(m[~left] * st.x[~left]) / m[~left].sum()
    assert xl - centre == pytest.approx(-(xr - centre), rel=1e-9)
    # they have met: the left ring has slowed down
    ul = np.sum(m[left] * st.vx[left]) / m[left].sum()
    assert ul < 0.99 * scene.get("particles.rings.speed")
    assert abs(eng.balance_error()) < 0.05
