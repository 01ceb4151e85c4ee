"""The one run loop: checkpoints that change nothing, bit-identical resume, one guard message,
the fingerprint, the end-of-run summary (a toy engine: a chaotic map, so any perturbation of
the trajectory would show in the last bits)."""

from __future__ import annotations

import numpy as np
import pytest

from craquelure import runner
from craquelure.errors import SimulationDiverged
from craquelure.scene import load_scene


class ToyEngine:
    """x <- 3.9 x (1 - x) per particle; samples the mean every 3 steps."""

    def __init__(self, n: int = 5, seed: int = 0, n_steps: int = 40, nan_at: int | None = None):
        self.x = np.random.default_rng(seed).uniform(0.1, 0.9, n)
        self.steps, self.n_particles, self.n_steps, self.nan_at = 0, n, n_steps, nan_at
        self.samples: list[float] = []

    @property
    def time(self) -> float:
        return 0.5 * self.steps

    def start(self):
        self.samples.append(float(self.x.mean()))

    def advance(self):
        self.x = 3.9 * self.x * (1.0 - self.x)
        self.steps += 1
        if self.steps == self.nan_at:
            self.x[3] = np.nan

    def divergence(self):
        return runner.non_finite({"x": self.x})

    def sample(self):
        if self.steps % 3 == 0:
            self.samples.append(float(self.x.mean()))

    def done(self):
        return self.steps >= self.n_steps

    def state(self):
        return {"x": self.x.copy(), "steps": self.steps, "samples": np.array(self.samples)}

    def restore(self, state):
        self.x, self.steps = state["x"].copy(), int(state["steps"])
        self.samples = state["samples"].tolist()


@pytest.fixture(scope="module")
def scene():
    return load_scene("lattice/glen")


def _run(scene, out=None, seed=0, **kw):
    engine = ToyEngine(seed=seed)
    summary = runner.run(engine, scene, seed, t_end=20.0, desc="toy", out=out, progress=False,
                         minutes=0, **kw)
    return engine, summary


def test_resume_after_a_stop_is_bit_identical(scene, tmp_path):
    full, _ = _run(scene)
    out = tmp_path / "run.nc"
    with pytest.raises(runner.Stopped):
        _run(scene, out, every=7, stop_after_checkpoints=2)
    assert runner.checkpoint_path(out).exists()
    resumed, summary = _run(scene, out, every=7, resume=True)
    assert summary.resumed_at_step == 14 and summary.steps == 40
    np.testing.assert_array_equal(resumed.x, full.x)
    assert resumed.samples == full.samples


def test_wall_time_checkpoints_change_nothing(scene, tmp_path):
    """A checkpoint after every step (minutes ~ 0) leaves the trajectory as it was."""
    full, _ = _run(scene)
    engine = ToyEngine()
    runner.run(engine, scene, 0, t_end=20.0, desc="toy", out=tmp_path / "run.nc",
               progress=False, minutes=1e-12)
    np.testing.assert_array_equal(engine.x, full.x)


def test_checkpoint_of_another_seed_is_ignored(scene, tmp_path, capsys):
    out = tmp_path / "run.nc"
    with pytest.raises(runner.Stopped):
        _run(scene, out, seed=1, every=5, stop_after_checkpoints=1)
    engine, summary = _run(scene, out, seed=2, every=5, resume=True)
    assert "refusing checkpoint" in capsys.readouterr().err
    assert summary.resumed_at_step == 0
    np.testing.assert_array_equal(engine.x, _run(scene, seed=2)[0].x)


def test_fingerprint_covers_scene_seed_and_code(scene):
    other = scene.with_overrides(["outputs.t_end=1.0"])
    assert runner.fingerprint(scene, 1) == runner.fingerprint(scene, 1)
    assert runner.fingerprint(scene, 1) != runner.fingerprint(scene, 2)
    assert runner.fingerprint(scene, 1) != runner.fingerprint(other, 1)
    assert len(runner.code_fingerprint()) == 64


def test_guard_names_check_step_time_and_particle(scene):
    engine = ToyEngine(nan_at=9)
    with pytest.raises(SimulationDiverged,
                       match=r"^toy: finite check failed at step 9, t = 4.5 s: x is not finite "
                             r"\(worst particle 3\)$"):
        runner.run(engine, scene, 0, t_end=20.0, desc="toy", time_unit="s", progress=False)


def test_runaway_names_the_most_energetic_particle():
    bad = runner.runaway(10.0, 5.0, "energy", np.array([1.0, 7.0, 2.0]))
    assert bad.check == "runaway" and bad.particle == 1 and "10 exceeds 5" in bad.what
    assert runner.runaway(4.0, 5.0, "energy") is None
    assert runner.runaway(float("nan"), 5.0, "energy") is not None


def test_summary_and_progress_lines(scene, capsys):
    _, summary = _run(scene)
    err = capsys.readouterr().err
    assert "[toy] done: 40 steps, simulated time 20" in err and "particle-steps/s" in err
    assert summary.steps == 40 and summary.simulated_time == 20.0
    assert summary.particle_steps_per_s > 0
    assert set(summary.attrs()) == {"run_steps", "run_simulated_time",
                                    "run_particle_steps_per_s", "run_resumed_at_step"}


def test_dataset_pieces_round_trip_exactly():
    import xarray as xr

    ds = xr.Dataset({"a": ("p", [1.0 / 3.0, np.pi]), "n": ("p", np.array([1, 2], np.int64)),
                     "regime": ("p", ["hertz", "poiseuille"])}, attrs={"k": 1.5})
    assert runner.dataset_from_bytes(runner.dataset_bytes(ds)).identical(ds)
