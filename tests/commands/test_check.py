"""``craquelure check``: the derived numbers follow the step the run takes; a number that cannot be
computed is reported, not raised."""

from __future__ import annotations

import math

from craquelure.commands.check import derived_numbers
from craquelure.models import model_api
from craquelure.scene import load_scene


def test_check_uses_the_step_the_run_takes():
    """A huge viscosity makes the run halve dt many times; check's step count and wall-time
    estimate follow the run's step, not numerics.dt."""
    scene = load_scene("drying/ci", ["material.eta=1e6"])
    numbers = derived_numbers(model_api("drying"), scene)
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
