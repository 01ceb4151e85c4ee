"""Dataset writing: compressed netCDF4, atomic (temporary name + rename), attributes cleaned;
and the dataset written by ``craquelure init`` on the drying CI scene."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import netCDF4
import numpy as np
import pytest
import xarray as xr

from craquelure import cli
from craquelure import io as cio
from craquelure.drying.mass_consistency import kernel_matrix
from craquelure.io import open_dataset, write_dataset, write_text_atomic
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
