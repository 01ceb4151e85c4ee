"""``craquelure check``: the derived numbers follow the step the run takes; a number that cannot be
computed is reported, not raised."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from craquelure import cli
from craquelure.api import check
from craquelure.scene import (
    load_scene,
)
from tests.test_scene import INVALID, ci_text


def test_check_uses_the_step_the_run_takes():
    """A huge viscosity makes the run halve dt many times; check's step count and wall-time
    estimate follow the run's step, not numerics.dt."""
    scene = load_scene("drying/ci", ["material.eta=1e6"])
    numbers = check(scene)
    dt_run = numbers["time step of the run (halved below 0.6 of the viscous limit)"]
    assert dt_run < 1e-8 < scene.get("numerics.dt")
    assert numbers["steps"] == math.ceil(scene.get("outputs.t_end") / dt_run)
    assert numbers["predicted wall time [s], 1 / 2 threads"][0] > 1e5


def test_check_reports_uncomputable_numbers_instead_of_raising(capsys):
    from craquelure import cli

    assert cli.main(["check", "softdyn/two_sphere_approach", "--set", "particles.h0=1e300"]) == 0
    assert "cannot be computed" in capsys.readouterr().out


def test_check_reports_a_derived_number_whose_quadrature_fails(capsys):
    """softdyn/t1_phase with an overflowing F~ in study.reduced_force: the T1 duration behind
    the cost estimate cannot be solved (the deflection's root search does not converge); check
    prints that, naming the force, and exits 0 instead of raising."""
    from craquelure import cli

    assert cli.main(["check", "softdyn/t1_phase", "--set",
                     "study.reduced_force=[1e300, 1e-3]"]) == 0
    out = capsys.readouterr().out
    line = next(line for line in out.splitlines() if "cannot be computed" in line)
    assert "T_sep quadrature" in line and "F~ = 1e+300" in line
    # the same scene with representable forces still gets every number
    assert cli.main(["check", "softdyn/t1_phase"]) == 0
    assert "cannot be computed" not in capsys.readouterr().out


# --- scene validation through the CLI -------------------------------------------------------------


def write_scene(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "scene.yaml"
    path.write_text(text)
    return path


@pytest.mark.parametrize("case", INVALID, ids=[c[0] for c in INVALID])
def test_cli_check_rejects_invalid_scenes(case, tmp_path, capsys):
    _, edit, overrides, fragments = case
    path = write_scene(tmp_path, ci_text(edit))
    argv = ["check", str(path)]
    for item in overrides or ():
        argv += ["--set", item]
    assert cli.main(argv) == 2
    out, err = capsys.readouterr()
    assert err.startswith("craquelure check: error: ")
    for fragment in fragments:
        assert fragment in err, (fragment, err)
    assert "valid" not in out


def test_cli_check_valid_scene_prints_resolved_scene_effects_and_numbers(capsys):
    assert cli.main(["check", "drying/ci", "--set", "numerics.dt=2e-3"]) == 0
    out, _ = capsys.readouterr()
    assert "# scene ci (model drying): valid" in out
    assert "dt: 0.002" in out
    assert "xsph_epsilon: 0.5" in out  # defaults are shown
    for name in load_scene("drying/ci").effects:
        assert f"  {name} " in out
    assert "neighbours per particle: 49.2" in out  # N pi h^2 / L^2 - 1 = 1600 pi 0.04 / 4 - 1
    assert "steps: 4000" in out  # t_end / dt = 8 / 0.002
