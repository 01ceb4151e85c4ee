"""``craquelure export``: the .pvd/VTU series and the extended-XYZ trajectory hold every
per-particle field of every frame. Read back with independent readers (meshio for VTU, ASE's
extended-XYZ parser, the format OVITO reads) on datasets laid out like each model's run."""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

import ase.io
import meshio
import numpy as np
import pytest
import xarray as xr

from craquelure import cli
from craquelure.export_formats import export, frames_from_dataset

RNG = np.random.default_rng(17)
T, N = 3, 11


def drying_like() -> xr.Dataset:
    """(time, particle) fields, an int8 flag, a periodic box (drying run)."""
    return xr.Dataset(
        {name: (("time", "particle"), RNG.random((T, N))) for name in
         ("x", "y", "vx", "vy", "mass", "rho", "mean_stress")}
        | {"alive": (("time", "particle"), RNG.integers(0, 2, (T, N)).astype(np.int8)),
           "kinetic_energy": (("step_time",), RNG.random(7))},
        coords={"time": [0.5, 1.0, 1.5], "step_time": np.arange(7.0)},
        attrs={"box_length": 2.0},
    )


def impact_like() -> xr.Dataset:
    """snap_ fields on snapshot_time, initial and final per-particle state (impact run)."""
    ds = xr.Dataset(
        {f"snap_{k}": (("snapshot_time", "particle"), RNG.random((T, N)))
         for k in ("x", "y", "damage")}
        | {k: (("particle",), RNG.random(N)) for k in ("x0", "y0", "mass", "x", "y", "damage",
                                                       "vx")}
        | {"precrack": (("particle",), RNG.integers(0, 2, N).astype(np.int8)),
           "series_kinetic": (("time",), RNG.random(5))},
        coords={"snapshot_time": [1e-4, 2e-4, 3e-4], "time": np.arange(5.0)},
    )
    return ds


def lattice_like() -> xr.Dataset:
    """x, y, theta on frame without a coordinate; times in frame_time (lattice run)."""
    return xr.Dataset(
        {k: (("frame", "particle"), RNG.random((T, N))) for k in ("x", "y", "theta")}
        | {"body": (("particle",), np.arange(N)), "frame_time": (("frame",), [0.0, 5.0, 9.0]),
           "bond_i": (("bond",), np.arange(4))},
    )


def softdyn_like() -> xr.Dataset:
    """position and velocity (time, particle, dim) with string labels (Soft Dynamics run)."""
    return xr.Dataset(
        {"position": (("time", "particle", "dim"), RNG.random((T, N, 3))),
         "velocity": (("time", "particle", "dim"), RNG.random((T, N, 3))),
         "gap": (("time", "pair"), RNG.random((T, 2)))},
        coords={"time": [0.0, 0.1, 0.2], "particle": [f"P{i}" for i in range(N)],
                "dim": ["x", "y", "z"]},
    )


# expected time-resolved fields and static ones (written into every frame)
LAYOUTS = {
    "drying": (drying_like, ("x", "y", None), ["vx", "vy", "mass", "rho", "mean_stress",
                                                "alive"], []),
    "impact": (impact_like, ("snap_x", "snap_y", None), ["damage"],
               ["x0", "y0", "mass", "vx", "precrack"]),
    "lattice": (lattice_like, ("x", "y", None), ["theta"], ["body"]),
    "softdyn": (softdyn_like, ("position",), ["velocity"], []),
}


def expected_positions(ds, names) -> np.ndarray:
    if names == ("position",):
        return ds["position"].values
    x, y = ds[names[0]].values, ds[names[1]].values
    return np.stack([x, y, np.zeros_like(x)], axis=-1)


@pytest.mark.parametrize("model", list(LAYOUTS))
def test_frames_take_every_per_particle_field(model):
    make, _, resolved, static = LAYOUTS[model]
    frames = frames_from_dataset(make())
    assert sorted(frames.fields) == sorted(resolved + static)
    assert frames.positions.shape == (T, N, 3)


@pytest.mark.parametrize("model", list(LAYOUTS))
def test_vtu_series_and_xyz_read_back_equal(tmp_path, model):
    make, pos_names, resolved, static = LAYOUTS[model]
    ds = make()
    run = tmp_path / "run.nc"
    ds.to_netcdf(run)
    pvd, xyz = export(run, "vtu")
    assert pvd == tmp_path / "run.pvd" and xyz == tmp_path / "run.xyz"
    frames = frames_from_dataset(ds)
    positions = expected_positions(ds, pos_names)

    # ParaView collection: one DataSet per frame, in time order, paths relative to the .pvd.
    entries = ET.parse(pvd).getroot().find("Collection").findall("DataSet")
    assert [float(e.get("timestep")) for e in entries] == pytest.approx(frames.times)
    assert len(entries) == T
    for k, entry in enumerate(entries):
        mesh = meshio.read(pvd.parent / entry.get("file"))
        np.testing.assert_array_equal(mesh.points, positions[k])
        assert sorted(mesh.point_data) == sorted(resolved + static)
        for name in resolved:
            source = ds[f"snap_{name}" if model == "impact" else name].values[k]
            got = mesh.point_data[name]  # meshio reads scalars as (N, 1)
            np.testing.assert_array_equal(got.reshape(source.shape), source, err_msg=name)
        for name in static:
            got = mesh.point_data[name].reshape(N)
            np.testing.assert_array_equal(got, ds[name].values, err_msg=name)

    # Extended XYZ, read by ASE's parser: same frames, positions and fields, exact round trip.
    atoms = ase.io.read(xyz, index=":", format="extxyz")
    assert len(atoms) == T
    for k, frame in enumerate(atoms):
        assert frame.info["Time"] == pytest.approx(frames.times[k], rel=1e-15)
        np.testing.assert_array_equal(frame.positions, positions[k])
        for name in resolved + static:
            got = frame.arrays[name]
            want = frames.fields[name][k]
            np.testing.assert_array_equal(got, want, err_msg=name)
        if model == "drying":  # periodic box from box_length
            np.testing.assert_array_equal(frame.cell.array[:2, :2], 2.0 * np.eye(2))


def test_cli_export_xyz_only_and_bad_format(tmp_path, capsys):
    run = tmp_path / "run.nc"
    lattice_like().to_netcdf(run)
    assert cli.main(["export", str(run), "--to", "xyz", "--out", str(tmp_path / "o" / "b")]) == 0
    assert (tmp_path / "o" / "b.xyz").is_file() and not (tmp_path / "o" / "b.pvd").exists()
    with pytest.raises(SystemExit):
        cli.main(["export", str(run), "--to", "vtk"])
    assert "invalid choice: 'vtk'" in capsys.readouterr().err
    assert cli.main(["export", str(tmp_path / "missing.nc")]) == 2
    assert "not found" in capsys.readouterr().err


def test_dataset_without_positions_is_rejected(tmp_path):
    run = tmp_path / "run.nc"
    xr.Dataset({"energy": (("time",), np.ones(3))}).to_netcdf(run)
    with pytest.raises(Exception, match="no particle positions"):
        export(run)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["run.nc"]


def test_export_leaves_no_temporary_files(tmp_path):
    run = tmp_path / "run.nc"
    drying_like().to_netcdf(run)
    export(run)
    names = [p.name for p in Path(tmp_path).rglob("*")]
    assert not [n for n in names if ".tmp" in n]
