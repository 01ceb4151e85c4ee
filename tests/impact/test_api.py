"""Run datasets (provenance, determinism, divergence) and the workflow helpers."""

import copy
from pathlib import Path

import numba
import numpy as np
import pytest
import yaml

from craquelure.errors import SceneError, SimulationDiverged
from craquelure.impact import workflow
from craquelure.impact.api import (
    concrete,
    derived_numbers,
    run,
    settings,
    softening,
)
from craquelure.impact.initial_state import build_specimen
from craquelure.io import open_dataset
from craquelure.registry import kernel_parameters
from craquelure.scene import load_scene, load_scene_text, project_root
from tests.impact.runs import simulate

from ..killed_run import check_message, kill_and_resume, same_dataset, stop_and_resume

CI = ["outputs.t_end=1.0e-4", "outputs.snapshot_times=[5.0e-5]"]


def test_run_dataset_is_complete_and_deterministic(tmp_path):
    scene = load_scene("impact/ci", [*CI, "particles.masses.distribution=uniform"])
    a = open_dataset(run(scene, tmp_path / "a.nc", seed=3))
    b = open_dataset(run(scene, tmp_path / "b.nc", seed=3))
    for key in ("x", "y", "damage", "plastic_strain", "mass", "series_contact_force",
                "snap_softening"):
        assert np.array_equal(a[key].values, b[key].values), key
    assert a.attrs["seed"] == 3 and a.attrs["model"] == "impact"
    assert "elasticity" in a.attrs["effects"] and "numerics:" in a.attrs["scene"]
    assert a.sizes["snapshot_time"] == 2  # 50 us and the end
    sp = build_specimen(scene, 3)  # reference positions are the untouched grid
    assert np.array_equal(a["x0"].values, sp.x) and np.array_equal(a["y0"].values, sp.y)
    assert not np.array_equal(a["y"].values, sp.y)
    assert a["mass"].sum() == pytest.approx(a.sizes["particle"] * 2400.0 * 0.01**2, rel=1e-12)
    assert np.abs(a["series_balance_error"].values).max() < 0.02
    assert a.attrs["as_epsilon"] == pytest.approx(0.15)  # as_epsilon: auto at kappa = 1
    assert a.attrs["contact_a"] == pytest.approx(6.27, abs=0.01)  # contact_a: auto
    assert not [k for k in a.attrs if k.startswith("metric_")]  # a run computes no analysis
    c = open_dataset(run(scene, tmp_path / "c.nc", seed=4))
    assert not np.array_equal(a["mass"].values, c["mass"].values)
    # the strength-to-load ratio: peak contact force over pi D t f_t / 2, 2D per metre (t = 1)
    load = np.pi * 2.0 * a.attrs["radius"] * scene.get("material.f_t") / 2.0
    assert float(a["static_splitting_load"]) == pytest.approx(load, rel=1e-12)
    assert a["static_splitting_load"].attrs["units"] in ("N/m", "N m-1")
    assert float(a["strength_to_load"]) == pytest.approx(
        a["series_contact_force"].values.max() / load, rel=1e-12)
    assert a["strength_to_load"].attrs["long_name"].startswith("peak contact force over")


@pytest.mark.parametrize("overrides,expected", [
    (["numerics.kappa=0.7"], 0.2), (["numerics.kappa=1.0"], 0.15), (["numerics.kappa=1.5"], 0.0),
    (["numerics.kappa=1.25"], 0.075), (["numerics.kappa=3.0"], 0.0),
    (["numerics.kappa=1.5", "numerics.as_epsilon=0.3"], 0.3)])
def test_artificial_stress_epsilon_auto(overrides, expected):
    """``as_epsilon: auto`` (the schema's default) follows h(0)/Delta = 1.2 kappa through
    the measured minimisers 0.2 / 0.15 / 0 at 0.84 / 1.2 / 1.8, linear in between, constant
    outside; a number is taken as given."""
    scene = load_scene("impact/ci", overrides)
    assert settings(scene).as_epsilon == pytest.approx(expected, abs=1e-12)


@pytest.mark.parametrize("value", ["automatic", "-0.1"])
def test_artificial_stress_epsilon_rejects_bad_values(value):
    with pytest.raises(SceneError, match=r"numerics\.as_epsilon: .* not allowed; allowed: a "
                                         r"number >= 0, or auto"):
        load_scene("impact/ci", [f"numerics.as_epsilon={value}"])


@pytest.mark.parametrize("overrides,expected", [
    ([], 2 * 2**0.5 * (14.15 + 4 * 12.92 / 3) / 14.15),             # bulk, plane strain: 6.27
    (["domain.plane=stress"], 2 * 2**0.5 * 30.41 / 14.15),         # E/(1-nu^2) = 30.41 GPa
    (["effects=[elasticity, contact_mass]"], 0.1),                  # the spec's SOFSCL
    (["numerics.contact_a=0.1"], 0.1)])
def test_contact_scale_auto(overrides, expected):
    """``contact_a: auto``: the half-cell stiffness a = 2 sqrt(2) M/K with the bulk formula,
    0.1 with the mass-based one; a number is taken as given."""
    scene = load_scene("impact/ci", overrides)
    assert settings(scene).contact_a == pytest.approx(expected, rel=1e-3)


@pytest.mark.parametrize("effects, off", [
    ("[elasticity, artificial_viscosity, contact_bulk]", ["f_c", "f_t", "G_F"]),
    ("[elasticity, plasticity, contact_bulk]", ["f_t", "G_F"]),
    ("[elasticity, damage, contact_bulk]", ["f_c"]),
])
def test_an_off_effects_strengths_are_the_neutral_ones(effects, off):
    """The kernel's parameter vector and the concrete do not depend on a strength or fracture
    energy whose effects are all off (they hold their declared neutral values), whether or not
    the scene gives it: no fallback reads it; the effects that are on read the scene's."""
    given = load_scene("impact/ci", [f"effects={effects}"])
    data = copy.deepcopy(given.data)
    for name in off:
        del data["material"][name]
    st, st_absent = settings(given), settings(load_scene_text(yaml.safe_dump(data), "absent"))
    assert st.material == st_absent.material
    assert np.array_equal(st.params(), st_absent.params())
    for name in ("f_c", "f_t", "G_F"):
        expected = (kernel_parameters("impact")[name][0].neutral if name in off
                    else given.get(f"material.{name}"))
        assert getattr(st.material, name) == expected, name


def test_softening_is_zero_without_a_softening_law():
    """Damage off: no point softens, whatever its strain (the neutral strengths once made every
    point of an elastic run read fully softened, s = 1). Damage on: s runs linearly from 0 at
    eps_0 to 1 at eps_f."""
    strain = np.array([0.0, 1e-4, 1e-2, 1.0])
    elastic = concrete(load_scene("impact/ci", ["effects=[elasticity, contact_bulk]"]))
    assert np.array_equal(softening(strain, elastic), np.zeros(4))
    cracking = concrete(load_scene("impact/ci", ["effects=[elasticity, damage, contact_bulk]"]))
    e0, ef = cracking.eps_0, cracking.eps_f
    assert softening(np.array([0.5 * e0, e0, 0.5 * (e0 + ef), ef, 2 * ef]), cracking) == \
        pytest.approx([0.0, 0.0, 0.5, 1.0, 1.0])


def test_without_contact_the_penalty_scale_is_not_read():
    """No contact effect: a enters nothing, and a run records the spec's 0.1 whatever the
    scene's numerics.contact_a."""
    for a in ("auto", "5.0"):
        scene = load_scene("impact/ci", ["effects=[elasticity]", f"numerics.contact_a={a}"])
        assert settings(scene).contact_a == 0.1


@pytest.mark.parametrize("value", ["stiff", "0", "-1"])
def test_contact_scale_rejects_bad_values(value):
    with pytest.raises(SceneError, match=r"numerics\.contact_a: .* not allowed; allowed: a "
                                         r"number > 0, or auto"):
        load_scene("impact/ci", [f"numerics.contact_a={value}"])


@pytest.mark.slow
def test_divergence_stops_without_output(tmp_path):
    # mass-based penalty with a = 10: sqrt(a) > 2, the contact oscillator is unstable
    scene = load_scene("impact/ci", [*CI, "numerics.contact_a=10.0", "particles.gap=0.0",
                                     "effects=[elasticity, contact_mass]"])
    out = tmp_path / "run.nc"
    with pytest.raises(SimulationDiverged, match=r"runaway check failed at step \d+, t = .* us: "
                                                 r"total energy .*\(worst particle \d+\)"):
        run(scene, out, seed=1)
    assert not out.exists()
    assert not list(tmp_path.iterdir())


@pytest.mark.parametrize("profile,expected", [("config.yaml", 21), ("ci.yaml", 18),
                                              ("paper.yaml", 132)])
def test_campaign_sizes(profile, expected):
    section = yaml.safe_load(Path(project_root() / "config" / profile).read_text())["impact"]
    runs = workflow.campaign_runs(section)
    assert len(runs) == len(set(runs)) == expected
    figs = workflow.figure_runs(section)
    assert set(p for v in figs.values() for p in ([v] if isinstance(v, str) else v)) <= set(runs)


def test_fixed_across_kappa_sets_eps_as_and_l_c_on_every_run():
    """``impact.fixed_across_kappa`` adds the same --set of eps_AS and l_c to every variant;
    absent, the variant's arguments are the masses, pre-crack and kappa only."""
    wc = type("W", (), {"masses": "uniform", "precrack": "none", "kappa": "0.7"})()
    plain = workflow.variant_overrides({})(wc)
    assert plain == ("--set particles.masses.distribution=uniform --set particles.precrack=none "
                     "--set numerics.kappa=0.7")
    held = workflow.variant_overrides(
        {"fixed_across_kappa": {"as_epsilon": 0.15, "crack_band_width": 0.008}})(wc)
    assert held == (plain + " --set numerics.as_epsilon=0.15"
                    " --set material.crack_band_width=0.008")
    scene = load_scene("impact/ci", ["numerics.kappa=0.7", "numerics.as_epsilon=0.15",
                                     "material.crack_band_width=0.008"])
    st = settings(scene)
    assert st.as_epsilon == 0.15 and st.material.band == 0.008


def states_by_threads(scene, seed, threads=(1, 2)) -> list:
    """The final engine state of ``scene`` and ``seed`` run with each thread count."""
    out = []
    for n in threads:
        old = numba.get_num_threads()
        numba.set_num_threads(n)
        try:
            out.append(simulate(scene, seed, progress=False)[1].state)
        finally:
            numba.set_num_threads(old)
    return out


@pytest.mark.skipif(numba.config.NUMBA_NUM_THREADS < 2, reason="needs 2 numba threads")
def test_run_is_independent_of_the_thread_count():
    """Same scene and seed, 1 and 2 threads: bit-identical fields. Every pair sum is a gather
    over the particle's own neighbour row in a fixed order, and the material pass reads the
    step-start rho and h of its neighbours (it used to read them while other threads were
    overwriting them, so 2-thread runs differed from run to run)."""
    scene = load_scene("impact/ci", [*CI, "particles.masses.distribution=uniform"])
    out = states_by_threads(scene, 3)
    for key in ("x", "y", "vx", "vy", "rho", "h", "sig", "dmg"):
        assert np.array_equal(getattr(out[0], key), getattr(out[1], key)), key


def test_derived_numbers_show_the_resolved_penalty():
    """``craquelure check impact/default`` prints the penalty the run will use: a = 6.27,
    k = a K/sqrt(2) = 6.28e10 N/m, and the kinematic fallback's mass bound 4 k dt^2 / m_bar."""
    numbers = derived_numbers(load_scene("impact/default"))
    a, k = numbers["penalty scale a, k [N/m]"]
    assert a == pytest.approx(6.2718, rel=1e-4)
    assert k == pytest.approx(a * 14.15e9 / 2**0.5, rel=1e-12)
    dt = numbers["initial time step [s]"]
    assert numbers["kinematic below m / m_bar"] == pytest.approx(
        4 * k * dt**2 / (2400.0 * 0.004**2), rel=1e-12)


def test_dt_min_is_the_stability_step():
    """``run_dt_min`` is the smallest CFL step, not the last step shortened to end at t_end
    (which gave 1e-9 s): within the CFL range of this run (AV term included: ~0.18 us)."""
    scene = load_scene("impact/ci", ["outputs.t_end=1.0e-5", "outputs.snapshot_times=[]"])
    _, eng, _, _ = simulate(scene, 0, progress=False)
    h0, c = 1.2 * scene.get("particles.spacing"), eng.s.wave_speed
    assert 0.5 * 0.3 * h0 / (2.2 * c) < eng.dt_min_seen <= 0.3 * h0 / (2.2 * c) * 1.001


# -- checkpoint and resume -----------------------------------------------------------------
# Impact runs checkpoint through the runner: a killed run resumes bit-identically.

@pytest.mark.slow
def test_killed_cli_run_resumes_bit_identically(tmp_path):
    full, resumed, err = kill_and_resume(tmp_path, [
        "impact/ci", "--seed", "1", "--set", "outputs.t_end=1.0e-4",
        "--set", "outputs.snapshot_times=[5.0e-5]", "--checkpoint-every", "40"])
    assert "resumed from" in err
    assert resumed.attrs["run_resumed_at_step"] > 0
    same_dataset(full, resumed)


@pytest.mark.slow
def test_killed_3d_run_resumes_bit_identically(tmp_path):
    """The 3D state (z, v_z, six stress components, the k-d tree's neighbour list) goes
    through the same checkpoint: the tiny 3D CI disc (336 particles)."""
    full, resumed, err = kill_and_resume(tmp_path, [
        "impact/ci3d", "--seed", "1", "--set", "particles.masses.distribution=uniform",
        "--checkpoint-every", "40"])
    assert "resumed from" in err
    assert resumed.attrs["run_resumed_at_step"] > 0 and resumed.attrs["dim"] == 3
    same_dataset(full, resumed)


@pytest.mark.slow
def test_sigterm_run_checkpoints_and_resumes_bit_identically(tmp_path):
    """SIGTERM (a scheduler's time limit): a checkpoint at the next step, exit 3 with one
    line naming it; --resume gives the uninterrupted dataset (shared with the test above)."""
    stopped = stop_and_resume(tmp_path, [
        "impact/ci", "--seed", "1", "--set", "outputs.t_end=1.0e-4",
        "--set", "outputs.snapshot_times=[5.0e-5]", "--checkpoint-every", "40"])
    step = check_message(stopped, tmp_path)
    assert step > 0 and int(stopped.checkpoint["engine_step_count"]) == step
    assert stopped.resumed.attrs["run_resumed_at_step"] == step
    same_dataset(stopped.full, stopped.resumed)
