"""The Python API (craquelure.api): each function is its command, so a run through the API
equals `craquelure init` + `craquelure run` of the same scene, overrides and seed in every
variable and attribute (timing and the file's own names aside), for every model; bad input
raises the command's one-line error."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest
import xarray as xr

import craquelure as cq
from craquelure import cli
from craquelure.api import override_strings
from craquelure.errors import CraquelureError, SceneError
from craquelure.io import open_dataset, write_dataset

# the smallest scene of each model, cut short (seconds each); scene, overrides, init?
CASES = {
    "drying": ("drying/ci", {"outputs.t_end": 0.4, "outputs.times": [0.2, 0.4]}, True),
    "impact": ("impact/ci", {"outputs.t_end": 2.0e-6, "outputs.snapshot_times": []}, False),
    "lattice": ("lattice/gravity_block", {"domain.nx": 16, "domain.ny": 6,
                                          "outputs.t_end": 20.0}, False),
    "softdyn": ("softdyn/t1_single_ci", {"outputs.t_end": 0.05}, False),
}


def timing(key: str) -> bool:
    """Attributes that say when, where and how fast a run went (history: when it was
    written), not what it computed."""
    return key in ("start_time", "host", "history", "run_particle_steps_per_s") \
        or key.endswith("wall_time_s")


def same(a: xr.Dataset, b: xr.Dataset) -> None:
    xr.testing.assert_identical(a.drop_attrs(), b.drop_attrs())
    differ = {k for k in a.attrs.keys() | b.attrs.keys()
              if not timing(k) and not _equal(a.attrs.get(k), b.attrs.get(k))}
    assert differ == set(), differ


def _equal(x, y) -> bool:
    x, y = np.asarray(x), np.asarray(y)
    nan = x.dtype.kind == "f" and y.dtype.kind == "f"
    return x.shape == y.shape and bool(np.array_equal(x, y, equal_nan=nan))


@pytest.mark.parametrize("model", list(CASES))
def test_api_run_equals_cli_init_and_run(model, tmp_path):
    name, overrides, with_init = CASES[model]
    sets = [arg for item in override_strings(overrides) for arg in ("--set", item)]
    run_args = ["run", name, *sets, "--seed", "3", "--out", str(tmp_path / "cli.nc")]
    if with_init:
        assert cli.main(["init", name, *sets, "--seed", "3",
                         "--out", str(tmp_path / "init.nc")]) == 0
        run_args += ["--init", str(tmp_path / "init.nc")]
    assert cli.main(run_args) == 0
    with open_dataset(tmp_path / "cli.nc") as ds:
        expected = ds.load()

    scene = cq.load_scene(name, overrides=overrides)
    init = cq.initial_state(scene, 3) if with_init else None
    got = cq.run(scene, seed=3, init=init)
    assert isinstance(got, xr.Dataset) and got.sizes
    same(got, expected)
    if with_init:  # the API's initial state is the command's, written the same way
        write_dataset(init, tmp_path / "api_init.nc")
        with open_dataset(tmp_path / "init.nc") as a, open_dataset(tmp_path / "api_init.nc") as b:
            same(a.load(), b.load())
    # written to `out` as well, with the same content
    cq.run(scene, seed=3, init=init, out=tmp_path / "api.nc")
    with open_dataset(tmp_path / "api.nc") as ds:
        same(ds.load(), expected)


def test_overrides_as_dict_and_as_strings_are_the_same_scene():
    a = cq.load_scene("drying/ci", overrides={"numerics.dt": 0.002, "outputs.times": [1, 2]})
    b = cq.load_scene("drying/ci", overrides=["numerics.dt=0.002", "outputs.times=[1, 2]"])
    assert a == b and a.get("numerics.dt") == 0.002 and a.overrides == b.overrides
    assert cq.load_scene(a, {"numerics.dt": 0.001}).get("numerics.dt") == 0.001


def test_scenes_and_check_are_the_commands(capsys):
    names = cq.scenes()
    assert {"drying/ci", "impact/ci", "lattice/glen", "softdyn/t1_single_ci"} <= set(names)
    assert cli.main(["scenes"]) == 0
    assert capsys.readouterr().out.count("\n") == len(names)
    numbers = cq.check("drying/ci")
    assert numbers["steps"] > 0 and numbers["stable time step"] > 0


@pytest.mark.parametrize("call, command, message", [
    (lambda: cq.load_scene("drying/ci", {"numerics.h": -0.2}),
     ["check", "drying/ci", "--set", "numerics.h=-0.2"],
     "numerics.h: -0.2 is not allowed; must be > 0"),
    (lambda: cq.load_scene("drying/nowhere"), ["check", "drying/nowhere"], "drying/nowhere"),
    (lambda: cq.export("nowhere.nc", to="xyz"), ["export", "nowhere.nc", "--to", "xyz"],
     "nowhere.nc"),
])
def test_errors_are_the_commands_one_line_errors(call, command, message, capsys):
    with pytest.raises(CraquelureError) as err:
        call()
    assert message in str(err.value)
    assert cli.main(command) == 2
    printed = capsys.readouterr().err
    cli._fail(command[0], str(err.value))  # the command prints the API's error on one line
    assert printed == capsys.readouterr().err and printed.count("\n") == 1


def test_fragments_of_a_model_without_fragments_is_a_named_error(tmp_path):
    run = xr.Dataset(attrs={"model": "softdyn"})
    with pytest.raises(CraquelureError, match="model 'softdyn', which has no fragments"):
        cq.fragments(run)
    with pytest.raises(CraquelureError, match="overrides"):
        cq.load_scene("drying/ci", "numerics.dt=0.002")
    with pytest.raises(SceneError, match="numerics: unknown key 'nope'"):
        cq.load_scene("drying/ci", {"numerics.nope": 1})


def test_acceptance_snippet_in_a_fresh_process(tmp_path):
    """The issue's snippet: a run of drying/ci through the API in a new process equals the
    command's run; its fragments are a Dataset; export writes the files."""
    code = (
        "import craquelure as cq, xarray as xr\n"
        "short = {'outputs.t_end': 0.4, 'outputs.times': [0.2, 0.4]}\n"
        "ds = cq.run(cq.load_scene('drying/ci', overrides=short), seed=1)\n"
        "frag = cq.fragments(ds)\n"
        "assert isinstance(ds, xr.Dataset) and isinstance(frag, xr.Dataset)\n"
        "assert frag.sizes['time'] == ds.sizes['time']\n"
        f"ds.to_netcdf({str(tmp_path / 'api.nc')!r})\n"
        f"print(*cq.export(ds, to='xyz', out={str(tmp_path / 'api')!r}))\n")
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          timeout=600)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.strip() == str(tmp_path / "api.xyz")
    assert cli.main(["run", "drying/ci", "--set", "outputs.t_end=0.4",
                     "--set", "outputs.times=[0.2, 0.4]", "--seed", "1",
                     "--out", str(tmp_path / "cli.nc")]) == 0
    with open_dataset(tmp_path / "cli.nc") as cli_ds, xr.open_dataset(tmp_path / "api.nc") as api:
        same(api.load(), cli_ds.load())


def test_docstring_examples_run(tmp_path, monkeypatch):
    """Every function's example, in the order a user would meet them (run_to_file writes the
    run.nc that fragments and export read), in an empty folder."""
    import doctest

    from craquelure import api

    monkeypatch.chdir(tmp_path)
    names = ["scenes", "override_strings", "load_scene", "check", "initial_state",
             "run_to_file", "run", "fragments", "export"]
    globs = {"craquelure": cq, "override_strings": override_strings}
    runner = doctest.DocTestRunner(optionflags=doctest.NORMALIZE_WHITESPACE)
    for name in names:
        (test,) = doctest.DocTestFinder().find(getattr(api, name), name, globs=globs)
        assert test.examples, name
        runner.run(test)
    assert runner.summarize(verbose=False).failed == 0
