"""The throughput model behind `craquelure check`'s wall-time prediction."""

from pathlib import Path

import numpy as np
import pytest

from craquelure.impact.api import listed_neighbours
from craquelure.models import MODELS, model_api
from craquelure.scene import load_scene
from craquelure.throughput import (
    CostModel,
    cost_model,
    predicted_parts,
    predicted_wall_time,
)

SCENES = sorted(f"{p.parent.name}/{p.stem}"
                for p in (Path(__file__).parents[1] / "config" / "scenes").glob("*/*.yaml"))


def test_cost_model_terms_and_thread_speedup():
    m = CostModel(unit="steps", overhead_s=2.0, per_unit_s=1e-4, per_particle_s=1e-7,
                  per_pair_s=1e-8, speedup_2=1.8)
    assert m.seconds(0, 1000, 20) == 2.0
    one = m.compute_seconds(100, 1000, 20)
    assert one == pytest.approx(100 * (1e-4 + 1000 * (1e-7 + 20 * 1e-8)))
    assert m.compute_seconds(100, 1000, 20, threads=2) == pytest.approx(one / 1.8)
    # Amdahl beyond 2 threads with the parallel fraction of S(2): f = 2(1 - 1/1.8)
    f = 2 * (1 - 1 / 1.8)
    assert m.speedup(4) == pytest.approx(1 / ((1 - f) + f / 4))
    # an effect's extra per-particle cost counts only when the scene lists the effect
    e = CostModel(unit="steps", overhead_s=2.0, per_unit_s=0.0, per_particle_s=1e-7,
                  per_pair_s=0.0, speedup_2=1.0, per_particle_effect_s={"melting": 2e-8})
    assert e.compute_seconds(100, 1000, 6, effects=("beams",)) == pytest.approx(100 * 1e-4)
    assert e.compute_seconds(100, 1000, 6, effects=("beams", "melting")) == \
        pytest.approx(100 * 1000 * 1.2e-7)


def test_every_engine_has_a_measured_model():
    for engine in MODELS:
        m = cost_model(engine)
        assert m.overhead_s > 0 and m.speedup_2 >= 1.0
        assert m.per_unit_s + m.per_particle_s + m.per_pair_s > 0


@pytest.mark.parametrize("ref", SCENES)
def test_every_built_in_scene_gets_a_prediction(ref):
    scene = load_scene(ref)
    work = model_api(scene.model).workload(scene)
    assert work["units"] > 0 and work["particles"] > 0 and work["neighbours"] >= 0
    one, two = (predicted_wall_time(scene.model, work, t) for t in (1, 2))
    assert 0 < two <= one < 1e7


def test_serial_workload_gains_nothing_from_threads():
    work = {"units": 1000, "particles": 5000, "neighbours": 6.0}
    assert predicted_wall_time("lattice", {**work, "serial": True}, 2) == \
        predicted_wall_time("lattice", work, 1)


def test_prediction_is_fixed_cost_plus_compute_part():
    work = {"units": 1000, "particles": 5000, "neighbours": 20.0}
    fixed, compute = predicted_parts("impact", work, 2)
    assert fixed == cost_model("impact").overhead_s and compute > 0
    assert fixed + compute == pytest.approx(predicted_wall_time("impact", work, 2))


@pytest.mark.parametrize("dim", [2, 3])
def test_impact_neighbour_count_matches_the_grid_in_2d_and_3d(dim):
    """The impact workload's neighbours (ball area or volume in cells, minus the particle)
    against the grid points within the radius (square grid in 2D, cubic in 3D), averaged over
    the radii a scene uses (2 h + skin = 2.5-3.6 cells; at one radius the count jumps by
    shells): within 5 %, so a 3D scene is not charged 2D's neighbour count (3-4x fewer)."""
    axis = np.arange(-4, 5)
    r2 = np.sum(np.stack(np.meshgrid(*[axis] * dim), -1).reshape(-1, dim) ** 2, axis=1)
    radii = np.linspace(2.5, 3.6, 45)
    exact = np.mean([np.count_nonzero(r2 < r * r) - 1 for r in radii])
    model = np.mean([listed_neighbours(r, dim) for r in radii])
    assert model == pytest.approx(exact, rel=0.05)


def test_long_run_warning_states_figure_and_model():
    """Above an hour: the predicted figure (equal to predicted_wall_time), the workload and
    the throughput model it came from; none below an hour."""
    from craquelure.throughput import LONG_RUN_S, long_run_warning

    work = {"units": 1e8, "particles": 1000, "neighbours": 6.0}
    seconds = predicted_wall_time("lattice", work)
    assert seconds > LONG_RUN_S
    message = long_run_warning("lattice", work)
    assert message.startswith(f"warning: predicted wall time {seconds / 3600:.3g} h "
                              f"({seconds:.3g} s) with 1 thread(s) exceeds an hour")
    assert "1e+08 steps x 1000 particles x 6 neighbours" in message
    assert "throughput.yaml (measured " in message and "\n" not in message
    assert long_run_warning("lattice", {**work, "units": 10}) is None


def test_check_and_run_warn_of_a_run_longer_than_an_hour(capsys, tmp_path, monkeypatch):
    """One of the accepted-but-slow scenes of the fuzzing (a lattice step 1e-5 of the stable
    one: ~1e8 steps): `check` warns on stderr; a CI scene does not. `run` warns before it
    starts (the threshold lowered so that a seconds-long run is "long")."""
    from craquelure import cli, throughput

    assert cli.main(["check", "lattice/calving", "--set", "numerics.dt_factor=1e-5"]) == 0
    err = capsys.readouterr().err
    assert err.startswith("warning: predicted wall time ") and "exceeds an hour" in err
    assert cli.main(["check", "softdyn/t1_single_ci"]) == 0
    assert "warning" not in capsys.readouterr().err
    monkeypatch.setattr(throughput, "LONG_RUN_S", 0.01)
    assert cli.main(["run", "softdyn/t1_single_ci", "--out", str(tmp_path / "r.nc")]) == 0
    err = capsys.readouterr().err
    assert err.splitlines()[0].startswith("warning: predicted wall time ")
