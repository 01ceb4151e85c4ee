"""Dataset writing: compressed netCDF4, atomic (temporary name + rename), attributes cleaned;
and the dataset written by ``craquelure init`` on the drying CI scene; damaged and wrong inputs
to the commands that read datasets, and writes that fail (their own sections below)."""

from __future__ import annotations

import errno
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import netCDF4
import numpy as np
import pytest
import xarray as xr
import yaml

from craquelure import cli, runner
from craquelure import io as cio
from craquelure.drying.mass_consistency import kernel_matrix
from craquelure.errors import WriteError
from craquelure.io import (
    DatasetError,
    diagnose_file,
    open_dataset,
    read_dataset,
    remove_stale_temporaries,
    write_dataset,
    write_text_atomic,
)
from craquelure.runner import read_checkpoint, write_checkpoint
from craquelure.scene import load_scene


def sample_dataset(n: int = 20000) -> xr.Dataset:
    return xr.Dataset(
        {"x": (("particle",), np.zeros(n), {"units": "m", "long_name": "position"}),
         "k": (("particle",), np.arange(n) % 7, {"units": "1", "flag": True})},
        attrs={"seed": 3, "effects": ("a", "b"), "nothing": None, "flag": np.bool_(True)},
    )


def test_write_dataset_round_trip_and_attribute_cleaning(tmp_path):
    path = write_dataset(sample_dataset(), tmp_path / "sub" / "out.nc")
    assert path == tmp_path / "sub" / "out.nc" and path.is_file()
    ds = open_dataset(path)
    np.testing.assert_array_equal(ds["k"].values, np.arange(20000) % 7)
    assert ds.attrs["seed"] == 3
    assert ds.attrs["effects"] == "a,b"
    assert ds.attrs["nothing"] == ""
    assert ds.attrs["flag"] == 1
    assert ds["k"].attrs["flag"] == 1
    assert ds["x"].attrs == {"units": "m", "long_name": "position"}
    # open_dataset loads and closes: the file can be replaced right away.
    write_dataset(sample_dataset(10), path)
    assert open_dataset(path).sizes["particle"] == 10


def test_write_dataset_is_compressed_netcdf4(tmp_path):
    path = write_dataset(sample_dataset(), tmp_path / "out.nc")
    with netCDF4.Dataset(path) as nc:
        assert nc.data_model == "NETCDF4"
        for name in ("x", "k"):
            filters = nc.variables[name].filters()
            assert filters["zlib"] and filters["complevel"] == 4
    # 20000 float64 zeros + int64 = 320 kB raw; compressed far below that.
    assert path.stat().st_size < 50_000


def test_temporary_file_never_has_the_final_name(tmp_path, monkeypatch):
    final = tmp_path / "out.nc"
    seen = {}
    real_to_netcdf = xr.Dataset.to_netcdf
    real_replace = os.replace

    def spy_to_netcdf(self, path, *args, **kwargs):
        seen["tmp"] = Path(path)
        assert not final.exists()
        return real_to_netcdf(self, path, *args, **kwargs)

    def spy_replace(src, dst):
        seen["replace"] = (Path(src), Path(dst))
        assert Path(src).is_file() and not final.exists()
        real_replace(src, dst)

    monkeypatch.setattr(xr.Dataset, "to_netcdf", spy_to_netcdf)
    monkeypatch.setattr(cio.os, "replace", spy_replace)
    write_dataset(sample_dataset(100), final)
    tmp = seen["tmp"]
    assert tmp != final and tmp.parent == final.parent  # same file system: rename is atomic
    assert not tmp.name.endswith(".nc")  # a glob for *.nc never picks it up
    assert seen["replace"] == (tmp, final)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.nc"]


def test_failed_write_leaves_no_file(tmp_path, monkeypatch):
    final = tmp_path / "out.nc"
    # 1. netCDF cannot store a nested mapping as an attribute.
    bad = sample_dataset(100)
    bad.attrs["nested"] = {"a": 1}
    with pytest.raises((TypeError, ValueError)):
        write_dataset(bad, final)
    assert list(tmp_path.iterdir()) == []

    # 2. A job dying half way through the write (after bytes hit the disk).
    real_to_netcdf = xr.Dataset.to_netcdf

    def dies(self, path, *args, **kwargs):
        real_to_netcdf(self, path, *args, **kwargs)
        assert Path(path).stat().st_size > 0
        raise KeyboardInterrupt

    monkeypatch.setattr(xr.Dataset, "to_netcdf", dies)
    with pytest.raises(KeyboardInterrupt):
        write_dataset(sample_dataset(100), final)
    assert list(tmp_path.iterdir()) == []

    # 3. An existing finished file is kept untouched when the rewrite fails.
    monkeypatch.setattr(xr.Dataset, "to_netcdf", real_to_netcdf)
    write_dataset(sample_dataset(7), final)
    monkeypatch.setattr(xr.Dataset, "to_netcdf", dies)
    with pytest.raises(KeyboardInterrupt):
        write_dataset(sample_dataset(100), final)
    assert [p.name for p in tmp_path.iterdir()] == ["out.nc"]
    assert open_dataset(final).sizes["particle"] == 7


def test_write_text_atomic(tmp_path):
    path = write_text_atomic(tmp_path / "a" / "b.txt", "hello\n")
    assert path.read_text() == "hello\n"
    assert [p.name for p in path.parent.iterdir()] == ["b.txt"]


# --- craquelure init on the drying CI scene ----------------------------------------------


@pytest.fixture(scope="module")
def init_datasets(tmp_path_factory):
    """Two runs with seed 1 and one with seed 2 (in-process CLI: exit code, files)."""
    folder = tmp_path_factory.mktemp("init")
    paths = {}
    for label, seed in (("a", 1), ("b", 1), ("c", 2)):
        out = folder / f"{label}.nc"
        assert cli.main(["init", "drying/ci", "--seed", str(seed), "--out", str(out)]) == 0
        paths[label] = out
    return paths


def test_init_dataset_variables_and_attributes(init_datasets):
    with xr.open_dataset(init_datasets["a"]) as ds:
        scene = load_scene("drying/ci")
        n = scene.get("particles.n")
        for name in ("x", "y", "mass"):
            var = ds[name]
            assert var.dims == ("particle",) and var.size == n
            assert var.attrs["units"] and var.attrs["long_name"]
            assert np.all(np.isfinite(var.values))
        for var in ds.data_vars.values():
            assert "units" in var.attrs and "long_name" in var.attrs, var.name
        length = ds.attrs["box_length"]
        assert length == scene.get("domain.box_length")
        assert ds.attrs["h"] == scene.get("numerics.h")
        assert ds.attrs["rho0"] == scene.get("material.rho0")
        assert ds["x"].min() >= 0 and ds["x"].max() < length
        assert 1 <= ds.attrs["cg_iterations"] <= 30
        assert 0 < ds.attrs["cg_residual"] <= 3e-3
        assert ds.attrs["seed"] == 1
        assert ds.attrs["scene"] == scene.text
        assert ds.attrs["effects"] == ",".join(scene.effects)
        for key in ("version_craquelure", "version_numpy", "version_numba", "version_scipy",
                    "git_commit", "start_time"):
            assert isinstance(ds.attrs[key], str) and ds.attrs[key], key
        assert ds.attrs["wall_time_s"] > 0


def test_init_masses_pass_the_residual_check(init_datasets):
    ds = open_dataset(init_datasets["a"])
    x, y, mass = ds["x"].values, ds["y"].values, ds["mass"].values
    length, h, rho0 = ds.attrs["box_length"], ds.attrs["h"], ds.attrs["rho0"]
    density = kernel_matrix(x, y, length, h) @ mass
    residual = np.linalg.norm(density - rho0) / (rho0 * np.sqrt(x.size))
    assert residual <= 3e-3
    assert residual == pytest.approx(ds.attrs["cg_residual"], rel=1e-9)
    m_bar = rho0 * length**2 / x.size
    assert mass.min() > 0.1 * m_bar
    assert np.abs(density - rho0).max() <= 0.05 * rho0
    assert mass.sum() == pytest.approx(rho0 * length**2, rel=0.01)
    # Initial stress components within +-0.01 sigma_Y (drying spec section 7).
    amp = 0.01 * 5e-3
    for c in ("sigma_e_xx", "sigma_e_yy", "sigma_e_xy"):
        v = ds[c].values
        assert np.abs(v).max() <= amp and v.std() > 0.5 * amp / np.sqrt(3)


def test_init_same_seed_same_arrays(init_datasets):
    a, b, c = (open_dataset(init_datasets[k]) for k in "abc")
    assert set(a.data_vars) == set(b.data_vars)
    for name in a.data_vars:
        np.testing.assert_array_equal(a[name].values, b[name].values)
    assert not np.array_equal(a["x"].values, c["x"].values)
    # Particles are sorted by cell for locality: the neighbour list rows are local.
    order_cells = np.floor(a["y"].values / 0.2).astype(int) * 10 + np.floor(
        a["x"].values / 0.2).astype(int)
    assert np.all(np.diff(order_cells) >= 0)


def test_init_console_script_in_a_new_process_gives_the_same_dataset(init_datasets, tmp_path):
    # The installed `craquelure` entry point, another process and another thread count:
    # same scene + seed -> same arrays.
    script = Path(sys.executable).parent / "craquelure"
    out = tmp_path / "sub.nc"
    proc = subprocess.run([str(script), "init", "drying/ci", "--seed", "1", "--out", str(out),
                           "--threads", "2"], capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr
    assert "wrote" in proc.stdout and "1600 particles" in proc.stdout
    a, b = open_dataset(init_datasets["a"]), open_dataset(out)
    for name in a.data_vars:
        np.testing.assert_array_equal(a[name].values, b[name].values)
    for key in ("cg_iterations", "cg_residual", "scene", "seed", "effects"):
        assert a.attrs[key] == b.attrs[key]


def test_init_errors_exit_nonzero(tmp_path, capsys):
    out = tmp_path / "bad.nc"
    assert cli.main(["init", "drying/ci", "--seed", "1", "--out", str(out),
                     "--set", "particles.rsa_min_separation=0.3"]) == 2
    err = capsys.readouterr().err
    assert "craquelure init: error:" in err and "drying spec 13.3" in err
    assert not out.exists()

# A small drying scene (400 particles on a square lattice, equal masses, a few steps).

# -- damaged and wrong inputs ------------------------------------------------------------------
# Damaged and wrong inputs to the commands that read datasets (`fragments`, `campaign`,
# `run --init`, `run --resume`): each gives one line on stderr naming the file and what is
# wrong (not found, unreadable, truncated, damaged, another model or kind, a missing
# variable); a damaged checkpoint or one of another run is refused with the reason; the
# temporaries of a run killed while writing its checkpoint are removed by the next run of the
# same output.

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



# -- writes that fail --------------------------------------------------------------------------
# Writes that fail: a full disk (a size-limited tmpfs), a read-only folder (a tmpfs remounted
# read-only) and a forbidden one (EACCES). The previous dataset or checkpoint stays intact, no
# temporary is left behind, and the error is one line naming the file and the cause (exit 2 from
# the command line).
#
# Mounting needs root (and a kernel that lets the process mount): where it cannot be done the
# real-filesystem tests are skipped, saying so. As root, a folder's permissions do not stop a
# write, so EACCES is tested by making the rename fail (and for real when not root).

def dataset(n: int, value: float = 0.0) -> xr.Dataset:
    # random numbers do not compress: the file holds about 8 n bytes
    rng = np.random.default_rng(n)
    return xr.Dataset({"x": ("particle", rng.random(n) + value,
                             {"units": "m", "long_name": "position"})})


def mount_tmpfs(folder: Path, size: str) -> None:
    folder.mkdir(parents=True, exist_ok=True)
    proc = subprocess.run(["mount", "-t", "tmpfs", "-o", f"size={size}", "tmpfs", str(folder)],
                          capture_output=True, text=True)
    if proc.returncode != 0:
        pytest.skip(f"cannot mount a tmpfs here (needs root): {proc.stderr.strip()}")


@pytest.fixture
def small_fs(tmp_path):
    """A 512 KiB tmpfs."""
    folder = tmp_path / "fs"
    mount_tmpfs(folder, "512k")
    yield folder
    subprocess.run(["umount", "-l", str(folder)], check=False)


def fill(folder: Path, leave: int) -> None:
    """Fill ``folder``'s file system up to ``leave`` bytes."""
    fs = os.statvfs(folder)
    free = fs.f_bavail * fs.f_frsize
    (folder / "filler").write_bytes(b"\0" * max(0, free - leave))


def temporaries(folder: Path) -> list[Path]:
    return list(folder.glob(".*.tmp-*"))


def test_full_disk_keeps_the_previous_dataset(small_fs):
    path = small_fs / "run.nc"
    write_dataset(dataset(100, 1.0), path)
    before = path.read_bytes()
    with pytest.raises(WriteError) as info:
        write_dataset(dataset(200_000), path)  # 1.6 MB into 512 KiB
    assert str(info.value) == f"cannot write dataset {path}: No space left on device"
    assert path.read_bytes() == before
    np.testing.assert_array_equal(open_dataset(path)["x"].values, dataset(100, 1.0)["x"].values)
    assert temporaries(small_fs) == []


def test_full_disk_keeps_the_previous_checkpoint(small_fs):
    path = small_fs / "run.nc.checkpoint.npz"
    write_checkpoint(path, {"q": np.arange(10.0)})
    with pytest.raises(WriteError) as info:
        write_checkpoint(path, {"q": np.random.default_rng(0).random(200_000)})
    assert str(info.value) == f"cannot write checkpoint {path}: No space left on device"
    np.testing.assert_array_equal(read_checkpoint(path)["q"], np.arange(10.0))
    assert temporaries(small_fs) == []


def test_read_only_folder_keeps_the_previous_files(small_fs):
    path, text = small_fs / "run.nc", small_fs / "notes.txt"
    write_dataset(dataset(100, 1.0), path)
    write_text_atomic(text, "old")
    before = path.read_bytes()
    subprocess.run(["mount", "-o", "remount,ro", str(small_fs)], check=True)
    for write, target, what in ((lambda: write_dataset(dataset(100), path), path, "dataset"),
                                (lambda: write_text_atomic(text, "new"), text, "file"),
                                (lambda: write_dataset(dataset(100), small_fs / "a" / "b.nc"),
                                 small_fs / "a" / "b.nc", "dataset")):
        with pytest.raises(WriteError) as info:
            write()
        assert str(info.value) == f"cannot write {what} {target}: Read-only file system"
    assert path.read_bytes() == before and text.read_text() == "old"
    assert temporaries(small_fs) == []


def test_permission_denied_keeps_the_previous_dataset(tmp_path, monkeypatch):
    """EACCES at the rename (as root no folder permission makes one): the temporary goes, the
    old dataset stays."""
    path = write_dataset(dataset(100, 1.0), tmp_path / "run.nc")
    before = path.read_bytes()

    def refuse(src, dst):
        raise PermissionError(errno.EACCES, os.strerror(errno.EACCES), str(dst))

    monkeypatch.setattr(cio.os, "replace", refuse)
    with pytest.raises(WriteError) as info:
        write_dataset(dataset(100), path)
    assert str(info.value) == f"cannot write dataset {path}: Permission denied"
    assert path.read_bytes() == before and temporaries(tmp_path) == []


@pytest.mark.skipif(os.geteuid() == 0, reason="as root a folder's permissions do not stop a "
                    "write (EACCES tested above by a refused rename)")
def test_forbidden_folder_for_real(tmp_path):
    path = write_dataset(dataset(100, 1.0), tmp_path / "ro" / "run.nc")
    before = path.read_bytes()
    path.parent.chmod(0o500)
    try:
        with pytest.raises(WriteError, match="Permission denied"):
            write_dataset(dataset(100), path)
    finally:
        path.parent.chmod(0o700)
    assert path.read_bytes() == before and temporaries(path.parent) == []


def test_cli_run_on_a_full_disk_exits_2_naming_the_file(small_fs):
    """``craquelure run`` whose dataset does not fit: exit 2, one line naming the file and the
    cause, the dataset already there untouched, no temporary, no traceback."""
    out = small_fs / "run.nc"
    write_dataset(dataset(100, 1.0), out)
    before = out.read_bytes()
    fill(small_fs, 16 * 1024)
    proc = subprocess.run([sys.executable, "-m", "craquelure", "run", "impact/ci", "--seed",
                           "1", "--set", "outputs.t_end=2.0e-5", "--set",
                           "outputs.snapshot_times=[]", "--out", str(out)],
                          capture_output=True, text=True, env={**os.environ,
                                                               "NUMBA_NUM_THREADS": "1"})
    assert proc.returncode == 2, proc.stderr[-2000:]
    last = proc.stderr.strip().splitlines()[-1]
    assert last == (f"craquelure run: error: cannot write dataset {out}: No space left on "
                    f"device"), proc.stderr[-2000:]
    assert "Traceback" not in proc.stderr
    assert out.read_bytes() == before and temporaries(small_fs) == []
