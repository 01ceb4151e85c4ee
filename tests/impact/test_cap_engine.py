"""The CSCM-like concrete in the SPH engine (effects cap_plasticity, compressive_damage,
rate_effects; scene impact/cscm): a hard impact stays stable with a closed energy balance and
every particle ends inside its surface; wiring and scene errors."""

import math
import shlex

import numpy as np
import pytest
import yaml

from craquelure.errors import SceneError
from craquelure.impact import workflow
from craquelure.impact.api import simulate
from craquelure.impact.effects.cap_plasticity import cap_position, willam_warnke
from craquelure.impact.effects.compressive_damage import DC_MAX
from craquelure.impact.material import standard_concrete
from craquelure.scene import load_scene, project_root

SMALL = ["particles.diameter_cells=20", "outputs.t_end=1.5e-4", "outputs.snapshot_times=[]"]


def inside(sig, epsv, epsp, mat, eps_fc):
    """Surface value sqrt(J2) - (1 - D_c) R F_f(I1') sqrt(F_c) (<= 0 inside; CSCM's coupled
    cap, the cap at X of the particle's compaction) and I1' - X per particle."""
    c = mat.cap
    i1 = -(sig[:, 0] + sig[:, 1] + sig[:, 3])
    m = -i1 / 3.0
    d = sig[:, [0, 1, 3]] - m[:, None]
    j2 = 0.5 * (d**2).sum(axis=1) + sig[:, 2] ** 2
    j3 = d[:, 2] * (d[:, 0] * d[:, 1] - sig[:, 2] ** 2)
    c3 = np.clip(1.5 * math.sqrt(3) * j3 / np.maximum(j2, 1e-30) ** 1.5, -1, 1)
    ratio = np.array([willam_warnke(math.cos(math.acos(v) / 3), c.e) for v in c3])
    x = np.array([cap_position(v, c.X0, c.W, c.D1, c.D2) for v in epsv])
    cap = np.array([float(c.F_c(v, xv)) for v, xv in zip(i1, x, strict=True)])
    limit = (1 - np.minimum(DC_MAX, epsp / eps_fc)) * ratio * c.F_f(i1) * np.sqrt(cap)
    return np.sqrt(j2) - limit, i1 - x, i1


@pytest.mark.slow
@pytest.mark.parametrize("plane", ["strain", "stress"])
def test_cap_model_disc_impact_is_stable_and_inside_its_surface(plane):
    scene = load_scene("impact/cscm", [*SMALL, f"domain.plane={plane}"])
    _, eng, series, _ = simulate(scene, 0, progress=False)
    mat = eng.s.material
    f, over_cap, i1 = inside(eng.state.sig, eng.state.epsv, eng.state.epsp, mat, mat.eps_fc)
    # 1e-3 f_c: the return uses D_c of the step's start (explicit), the check D_c of its end
    assert f[i1 > 0].max() <= 1e-3 * mat.f_c
    assert over_cap.max() <= 1e-6 * mat.f_c
    assert eng.state.epsp.max() > 0.0035  # crushing happened: the return was active
    assert np.abs(series["balance_error"]).max() < 0.02
    if plane == "stress":
        assert np.abs(eng.state.sig[:, 3]).max() == 0.0


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


@pytest.mark.parametrize("effect", ["compressive_damage", "rate_effects"])
def test_cap_effects_need_cap_plasticity(effect):
    with pytest.raises(SceneError, match=f"effects: {effect} .* needs cap_plasticity"):
        load_scene("impact/default", [f"effects=[elasticity, plasticity, damage, {effect}]"])


def test_cap_and_cone_conflict():
    with pytest.raises(SceneError, match="plasticity"):
        load_scene("impact/default", ["effects=[elasticity, plasticity, cap_plasticity]"])


def test_cscm_scene_is_the_default_scene_with_the_cap_model():
    default = load_scene("impact/default").data
    cscm = load_scene("impact/cscm").data
    assert "plasticity" in default["effects"] and "cap_plasticity" in cscm["effects"]
    assert "rate_effects" not in cscm["effects"]  # off in the source-faithful scenes
    for data in (default, cscm):
        data.pop("description")
        data["effects"] = [e for e in data["effects"] if e not in (
            "plasticity", "cap_plasticity", "compressive_damage")]
    assert cscm == default


def test_regime_runs_and_their_overrides_are_valid_scenes():
    section = yaml.safe_load((project_root() / "config" / "config.yaml").read_text())["impact"]
    runs = workflow.regime_runs(section)
    assert len(runs) == len(set(runs)) == 24
    name = runs[-1].rsplit("/", 1)[1][:-3]  # ft9.648_aauto_v15
    ft, a, v = name[2:].split("_")

    class W:
        pass

    w = W()
    w.scene, w.ft, w.a, w.v = section["scene"], ft, a[1:], v[1:]
    args = shlex.split(workflow.regime_overrides(section)(w))
    scene = load_scene("impact/default", args[1::2])
    assert scene.get("material.f_t") == pytest.approx(9.648e6)
    assert scene.get("numerics.contact_a") == "auto"
    assert scene.get("particles.impact_velocity") == 15
    assert scene.get("outputs.t_end") == pytest.approx(5e-4)
    assert standard_concrete().f_t == pytest.approx(3.216e6, rel=1e-3)
