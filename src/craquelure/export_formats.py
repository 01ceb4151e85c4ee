"""Export a run dataset for particle viewers: a ParaView time series (``.pvd`` of VTU point
clouds, written with pyevtk) and an extended-XYZ trajectory that OVITO (and ASE) read.

Works on the run dataset of any model by its layout, not by model name:

- positions: ``position`` (frame, particle, dim), ``snap_x``/``snap_y`` (frame, particle),
  ``x``/``y`` (frame, particle) or, for a single state, ``x``/``y`` (particle);
- frames: the first dimension of the positions; their times are its coordinate or a 1-D
  variable on that dimension whose name ends in ``time`` (e.g. the lattice's ``frame_time``);
- fields: every numeric variable on (frame, particle) (the ``snap_`` prefix dropped) and on
  (frame, particle, dim) (a 3-vector, zero-padded in 2D), plus every numeric per-particle
  variable without a frame dimension (mass, initial positions, labels), written unchanged into
  every frame. A per-particle variable that repeats a time-resolved field or the position under
  the same name is the last frame's state and is left out. Removed particles keep their index.

2D models get z = 0. Each field keeps its name; units and long names stay in the netCDF file.
"""

import os
import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import xarray as xr

from craquelure.errors import CraquelureError

FORMATS = ("vtu", "xyz")
PARTICLE = "particle"


@dataclass
class Frames:
    """Particle frames of a run: positions (T, N, 3) and fields (T, N) or (T, N, 3)."""

    times: np.ndarray
    positions: np.ndarray
    fields: dict[str, np.ndarray] = field(default_factory=dict)
    box: np.ndarray | None = None  # 3x3 cell (rows: vectors) when the run is periodic

    @property
    def n_frames(self) -> int:
        return self.positions.shape[0]


def _numeric(var: xr.DataArray) -> bool:
    return var.dtype.kind in "fiub"


def _pad3(vec: np.ndarray) -> np.ndarray:
    """(..., d) with d <= 3 -> (..., 3), zero-padded."""
    out = np.zeros((*vec.shape[:-1], 3))
    out[..., : vec.shape[-1]] = vec
    return out


def _frame_times(ds: xr.Dataset, dim: str, n: int) -> np.ndarray:
    if dim in ds.coords and _numeric(ds[dim]):
        return np.asarray(ds[dim].values, float)
    for name, var in ds.variables.items():
        if var.dims == (dim,) and str(name).endswith("time") and _numeric(var):
            return np.asarray(var.values, float)
    return np.arange(n, dtype=float)


def frames_from_dataset(ds: xr.Dataset) -> Frames:
    """The particle frames of a run dataset (see the module docstring for the layout)."""
    prefix = ""
    if "position" in ds and ds["position"].ndim == 3 and ds["position"].dims[1] == PARTICLE:
        pos = ds["position"]
        tdim = pos.dims[0]
        positions = _pad3(np.asarray(pos.values, float))
        used = {"position"}
    else:
        for prefix in ("snap_", ""):
            if f"{prefix}x" in ds and f"{prefix}y" in ds:
                break
        else:
            raise CraquelureError("no particle positions in the dataset: expected `position` "
                                  "(frame, particle, dim), `snap_x`/`snap_y` or `x`/`y`")
        x, y = ds[f"{prefix}x"], ds[f"{prefix}y"]
        if x.dims == (PARTICLE,):
            x, y = x.expand_dims("frame"), y.expand_dims("frame")
        if x.ndim != 2 or x.dims[1] != PARTICLE:
            raise CraquelureError(f"positions `{prefix}x` have dims {x.dims}; expected "
                                  "(frame, particle) or (particle,)")
        tdim = x.dims[0]
        comps = [x.values, y.values]
        used = {f"{prefix}x", f"{prefix}y"}
        if f"{prefix}z" in ds and ds[f"{prefix}z"].dims == x.dims:
            comps.append(ds[f"{prefix}z"].values)
            used.add(f"{prefix}z")
        positions = _pad3(np.stack(comps, axis=-1).astype(float))
    n_frames = positions.shape[0]
    frames = Frames(_frame_times(ds, tdim, n_frames), positions)

    static = {}
    for name, var in ds.data_vars.items():
        if name in used or not _numeric(var):
            continue
        key = name[len(prefix):] if prefix and name.startswith(prefix) else name
        if var.dims == (tdim, PARTICLE):
            frames.fields[key] = np.asarray(var.values)
        elif var.ndim == 3 and var.dims[:2] == (tdim, PARTICLE) and var.shape[2] <= 3:
            frames.fields[key] = _pad3(np.asarray(var.values, float))
        elif var.dims == (PARTICLE,):
            static[name] = np.asarray(var.values)
    frames.fields.update({name: np.broadcast_to(values, (n_frames, *values.shape))
                          for name, values in static.items() if name not in frames.fields
                          and name not in ("x", "y", "z", "position")})
    length = ds.attrs.get("box_length")
    if isinstance(length, int | float | np.number) and float(length) > 0:
        frames.box = np.diag([float(length), float(length), 0.0])
    return frames


# --- ParaView: .pvd time series of VTU point clouds ---------------------------------------


def write_vtu_series(frames: Frames, out: Path) -> Path:
    """``out`` (.pvd) plus ``<stem>/frame_<k>.vtu``, one point cloud per frame."""
    from pyevtk.hl import pointsToVTK
    from pyevtk.vtk import VtkGroup

    out = Path(out)
    folder = out.with_name(out.name.removesuffix(".pvd"))
    folder.mkdir(parents=True, exist_ok=True)
    width = max(4, len(str(frames.n_frames - 1)))
    # The .pvd is written under a temporary name (pyevtk appends ".pvd") and renamed last, so
    # a series that exists is complete.
    tmp_stem = out.with_name(f".{out.stem}.tmp-{os.getpid()}")
    group = VtkGroup(str(tmp_stem))
    for k in range(frames.n_frames):
        pos = frames.positions[k]
        data = {}
        for name, values in frames.fields.items():
            v = values[k]
            if v.ndim == 2:  # vector
                data[name] = tuple(np.ascontiguousarray(v[:, c], dtype=float) for c in range(3))
            else:
                # VTK readers handle int32 and float64 everywhere; int8/uint8 become int32
                data[name] = np.ascontiguousarray(v, np.int32 if v.dtype.kind in "iub"
                                                  else np.float64)
        stem = folder / f"frame_{k:0{width}d}"
        path = pointsToVTK(str(stem), *(np.ascontiguousarray(pos[:, c]) for c in range(3)),
                           data=data)
        group.addFile(filepath=path, sim_time=float(frames.times[k]))  # stored relative
    group.save()
    os.replace(f"{tmp_stem}.pvd", out)
    return out


# --- OVITO: extended XYZ ------------------------------------------------------------------


def write_extxyz(frames: Frames, out: Path) -> Path:
    """One extended-XYZ file with every frame (``species`` X, ``pos`` and every field)."""
    out = Path(out)
    props, fmt = ["species:S:1", "pos:R:3"], ["%s"] + ["%.17g"] * 3
    for name, values in frames.fields.items():
        kind = "I" if values.dtype.kind in "iub" else "R"
        ncol = 3 if values.ndim == 3 else 1
        # property names in the comment line: no spaces, colons or quotes
        props.append(f"{re.sub(r'[^A-Za-z0-9_]', '_', name)}:{kind}:{ncol}")
        fmt += ["%d" if kind == "I" else "%.17g"] * ncol
    header = "Properties=" + ":".join(props)
    cell = "" if frames.box is None else " ".join(f"{v:.17g}" for v in frames.box.ravel())
    lattice = f'Lattice="{cell}" pbc="T T F" ' if frames.box is not None else ""
    tmp = out.with_name(f".{out.name}.tmp-{os.getpid()}")
    n = frames.positions.shape[1]
    with open(tmp, "w") as fh:
        for k in range(frames.n_frames):
            fh.write(f"{n}\n{lattice}{header} Time={frames.times[k]:.17g}\n")
            cols = [np.full(n, "X", dtype=object), *frames.positions[k].T]
            for values in frames.fields.values():
                cols.extend(values[k].T if values[k].ndim == 2 else [values[k]])
            table = np.column_stack([np.asarray(col, dtype=object) for col in cols])
            np.savetxt(fh, table, fmt=fmt, delimiter=" ")
    os.replace(tmp, out)
    return out


def export(run: str | Path, to: str = "vtu", out: str | Path | None = None) -> list[Path]:
    """Export ``run`` (.nc). ``to="vtu"`` writes the .pvd series and, beside it, the
    extended-XYZ trajectory (OVITO); ``to="xyz"`` only the latter. Returns the files written."""
    if to not in FORMATS:
        raise CraquelureError(f"--to {to!r}: allowed values are {', '.join(FORMATS)}")
    run = Path(run)
    if not run.is_file():
        raise CraquelureError(f"run dataset {str(run)!r} not found")
    with xr.open_dataset(run) as ds:
        frames = frames_from_dataset(ds.load())
    base = Path(out) if out is not None else run.with_suffix("")
    if base.suffix in (".pvd", ".xyz"):
        base = base.with_suffix("")
    base.parent.mkdir(parents=True, exist_ok=True)
    written = []
    if to == "vtu":
        written.append(write_vtu_series(frames, base.with_name(f"{base.name}.pvd")))
    written.append(write_extxyz(frames, base.with_name(f"{base.name}.xyz")))
    return written
