"""Damaged and wrong inputs to the commands that read datasets (`fragments`, `campaign`,
`run --init`, `run --resume`): each gives one line on stderr naming the file and what is
wrong (not found, unreadable, truncated, damaged, another model or kind, a missing
variable); a damaged checkpoint or one of another run is refused with the reason; the
temporaries of a run killed while writing its checkpoint are removed by the next run of the
same output."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
import yaml

from craquelure import cli, runner
from craquelure.io import (
    DatasetError,
    diagnose_file,
    open_dataset,
    read_dataset,
    remove_stale_temporaries,
    write_dataset,
)

# A small drying scene (400 particles on a square lattice, equal masses, a few steps).
SCENE = {
    "model": "drying",
    "domain": {"box_length": 1.0},
    "particles": {"n": 400, "placement": "square_lattice"},
    "material": {"rho0": 1.0, "lame_lambda": 1.0, "lame_mu": 0.1, "eta": 1.0,
                 "thickness": 0.316, "yield_stress": 5.0e-3, "drying_rate": 2.2e-5},
    "numerics": {"h": 0.2, "integrator": "rk4", "dt": 0.004, "checkpoint_every": 5,
                 "mass_solve": {"method": "equal"}},
    "outputs": {"t_end": 0.04, "times": [0.04]},
    "effects": ["elasticity", "viscosity", "drying", "substrate", "fracture", "xsph",
                "continuity"],
}


def fail_line(argv, capsys) -> str:
    """Run the CLI in-process; it must exit 2 with exactly one line on stderr."""
    assert cli.main(argv) == 2
    err = capsys.readouterr().err
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    return lines[0]


def damage_inside_data(data: bytes, path: Path) -> Path:
    """``data`` with 64 bytes overwritten inside a data chunk, written to ``path``: the first
    offset from the middle on (64-byte steps) where the header still opens but reading the
    variables fails. (A fixed offset is not enough: where the chunks sit depends on how much
    metadata precedes them.)"""
    import netCDF4

    for start in range(len(data) // 2, len(data) - 64, 64):
        damaged = bytearray(data)
        damaged[start:start + 64] = bytes(range(64))
        path.write_bytes(bytes(damaged))
        try:
            nc = netCDF4.Dataset(path)
        except OSError:
            continue  # the header, not the data
        try:
            for var in nc.variables.values():
                var[:]
        except (OSError, RuntimeError):
            return path
        finally:
            nc.close()
    raise AssertionError("no offset damages a data chunk")


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    """A scene file, its initial state, a finished run and damaged variants of the state."""
    folder = tmp_path_factory.mktemp("damaged")
    scene = folder / "scene.yaml"
    scene.write_text(yaml.safe_dump(SCENE))
    init = folder / "init.nc"
    assert cli.main(["init", str(scene), "--seed", "2", "--out", str(init)]) == 0
    run = folder / "run.nc"
    assert cli.main(["run", str(scene), "--init", str(init), "--out", str(run)]) == 0
    data = init.read_bytes()
    paths = {"scene": scene, "init": init, "run": run}
    paths["truncated"] = folder / "truncated.nc"
    paths["truncated"].write_bytes(data[: len(data) // 2])
    paths["empty"] = folder / "empty.nc"
    paths["empty"].write_bytes(b"")
    paths["text"] = folder / "text.nc"
    paths["text"].write_text("not a dataset\n")
    # 64 bytes overwritten inside the (checksummed) data chunks
    paths["damaged"] = damage_inside_data(data, folder / "damaged.nc")
    impact = xr.Dataset({"x": ("particle", np.zeros(3)), "series_contact_force": ("time", [0.0]),
                         "snap_damage": (("snapshot_time", "particle"), np.zeros((1, 3)))},
                        attrs={"model": "impact"})
    paths["impact"] = write_dataset(impact, folder / "impact.nc")
    no_alive = open_dataset(run).drop_vars("alive")
    paths["no_alive"] = write_dataset(no_alive, folder / "no_alive.nc")
    return paths


@pytest.mark.parametrize("case, expected", [
    ("missing", "not found"),
    ("empty", "empty (0 bytes): truncated"),
    ("text", "not a netCDF file"),
    ("truncated", "truncated"),
    ("damaged", "damaged, cannot be read"),
    ("impact", "a dataset of model 'impact'"),
    ("init", "it is a drying initial state, not a drying run dataset: missing variable(s)"),
    ("no_alive", "not a usable drying run dataset: missing variable(s) alive"),
])
def test_fragments_names_the_file_and_the_damage(files, case, expected, capsys, tmp_path):
    path = files.get(case, tmp_path / "nowhere.nc")
    out = tmp_path / "frag.nc"
    line = fail_line(["fragments", str(path), "--out", str(out)], capsys)
    assert str(path) in line and expected in line, line
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("case, expected", [
    ("missing", "not found"),
    ("truncated", "truncated"),
    ("damaged", "damaged, cannot be read"),
    ("text", "not a netCDF file"),
    ("impact", "a dataset of model 'impact'"),
    ("run", "it is a drying run dataset, not a drying initial state: missing variable(s)"),
])
def test_run_init_names_the_file_and_the_damage(files, case, expected, capsys, tmp_path):
    path = files.get(case, tmp_path / "nowhere.nc")
    line = fail_line(["run", str(files["scene"]), "--init", str(path), "--out",
                      str(tmp_path / "run.nc")], capsys)
    assert str(path) in line and expected in line, line
    assert list(tmp_path.iterdir()) == []


def test_run_init_must_match_the_scene(files, capsys, tmp_path):
    """An initial state of 400 particles in a box of 1 cannot start a scene of 900 in 1.5."""
    line = fail_line(["run", str(files["scene"]), "--init", str(files["init"]), "--out",
                      str(tmp_path / "run.nc"), "--set", "particles.n=900", "--set",
                      "domain.box_length=1.5"], capsys)
    assert "--init does not match the scene" in line
    assert "holds 400 particles; the scene's particles.n is 900" in line
    assert "domain.box_length is 1.5" in line


@pytest.mark.parametrize("case, expected", [
    ("truncated", "truncated"),
    ("run", "it is a drying run dataset, not a fragment dataset"),
])
def test_campaign_names_the_file_and_the_damage(files, case, expected, capsys, tmp_path):
    line = fail_line(["campaign", str(files[case]), "--out", str(tmp_path / "c.nc")], capsys)
    assert str(files[case]) in line and expected in line, line


@pytest.mark.parametrize("damage, reason", [
    ("text", "damaged or truncated, cannot be read"),
    ("truncated", "damaged or truncated, cannot be read"),
    ("empty_npz", "not a checkpoint of this package: missing runner_fingerprint"),
])
def test_damaged_drying_checkpoint_is_refused_with_the_reason(files, damage, reason, capsys,
                                                              tmp_path):
    """`run --resume` next to a damaged checkpoint says why it is refused, starts from the
    beginning and gives the dataset of an uninterrupted run."""
    out = tmp_path / "run.nc"
    ck = runner.checkpoint_path(out)
    if damage == "empty_npz":
        with open(ck, "wb") as fh:
            np.savez(fh, something=np.zeros(3))
    elif damage == "truncated":
        from craquelure.drying.api import run
        from craquelure.scene import load_scene

        run(load_scene(files["scene"]), out, init=files["init"], stop_after_checkpoints=1)
        ck.write_bytes(ck.read_bytes()[:200])
    else:
        ck.write_bytes(files[damage].read_bytes())
    argv = ["run", str(files["scene"]), "--init", str(files["init"]), "--out", str(out),
            "--resume"]
    assert cli.main(argv) == 0
    err = capsys.readouterr().err
    assert f"refusing checkpoint {ck}" in err and reason in err, err
    assert "starting from the beginning" in err
    a, b = open_dataset(out), open_dataset(files["run"])
    np.testing.assert_array_equal(a.x.values, b.x.values)
    assert not ck.exists()


def test_checkpoint_of_another_run_is_refused_with_the_reason(files, capsys, tmp_path):
    out = tmp_path / "run.nc"
    from craquelure.drying.api import run
    from craquelure.scene import load_scene

    scene = load_scene(files["scene"])
    run(scene, out, init=files["init"], stop_after_checkpoints=1)
    assert runner.checkpoint_path(out).exists()
    other = scene.with_overrides(["material.drying_rate=1e-3"])
    run(other, out, init=files["init"], resume=True)
    err = capsys.readouterr().err
    assert "its fingerprint does not match this run" in err


def test_read_dataset_reports_missing_variables_and_kind(files):
    with pytest.raises(DatasetError, match="missing variable\\(s\\) nonexistent"):
        read_dataset(files["init"], "drying initial state", variables=("x", "nonexistent"))
    assert diagnose_file(files["init"]) is None
    assert "truncated" in diagnose_file(files["truncated"])


def test_stale_temporaries_of_dead_processes_are_removed(tmp_path):
    out = tmp_path / "out.nc"
    dead = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"],
                          capture_output=True, text=True).stdout.strip()
    stale = tmp_path / f".out.nc.tmp-{dead}"
    live = tmp_path / f".out.nc.tmp-{os.getppid()}"  # a running process: left alone
    stale.write_text("x")
    live.write_text("x")
    assert remove_stale_temporaries(out) == [stale]
    assert live.exists() and not stale.exists()


KILL_WHILE_CHECKPOINTING = r"""
import sys, time
from pathlib import Path
import numpy as np
original = np.savez
def slow(file, *args, **kwargs):
    result = original(file, *args, **kwargs)
    name = str(getattr(file, "name", file))
    if ".checkpoint.npz.tmp-" in name:
        file.flush()
        Path(sys.argv[2]).write_text(name)  # the temporary is written, not yet renamed
        time.sleep(600)
    return result
np.savez = slow
from craquelure import cli
cli.main(["run", "lattice/glen", "--out", sys.argv[1], "--set", "domain.nx=8",
          "--set", "domain.ny=6", "--set", "outputs.t_end=60.0", "--set", "outputs.frames=6",
          "--set", "numerics.checkpoint_every=2"])
"""


def test_temporaries_of_a_run_killed_while_checkpointing_are_removed(tmp_path):
    """SIGKILL a lattice run while it writes `.<out>.checkpoint.npz.tmp-<pid>`; the next run
    of the same output removes it and finishes."""
    out = tmp_path / "run.nc"
    marker = tmp_path / "marker"
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path))
    proc = subprocess.Popen([sys.executable, "-c", KILL_WHILE_CHECKPOINTING, str(out),
                             str(marker)], env=env, stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL)
    try:
        deadline = time.monotonic() + 300
        while not marker.exists() and proc.poll() is None and time.monotonic() < deadline:
            time.sleep(0.2)
        assert marker.exists(), "the run never wrote a checkpoint"
        os.kill(proc.pid, signal.SIGKILL)
        proc.wait(timeout=30)
    finally:
        if proc.poll() is None:
            proc.kill()
    tmp = Path(marker.read_text())
    assert tmp.exists() and tmp.name == f".run.nc.checkpoint.npz.tmp-{proc.pid}"
    assert cli.main(["run", "lattice/glen", "--out", str(out), "--set", "domain.nx=8",
                     "--set", "domain.ny=6", "--set", "outputs.t_end=60.0", "--set",
                     "outputs.frames=6", "--set", "numerics.checkpoint_every=2"]) == 0
    assert sorted(p.name for p in tmp_path.iterdir()) == ["marker", "run.nc"]
