"""Dataset writing: compressed netCDF4 with CF-1.11 metadata (:mod:`craquelure.cf`), written
to a temporary name and renamed, so a killed job never leaves a file that looks finished."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import xarray as xr

from craquelure import cf


def _encoding(ds: xr.Dataset) -> dict[str, dict]:
    enc = {}
    for name, var in ds.variables.items():
        if var.dtype.kind in "fiub" and var.ndim > 0:
            enc[name] = {"zlib": True, "complevel": 4}
        if var.dims == (name,) and var.dtype.kind == "f":
            # CF 2.5.1: a coordinate variable has no missing values, so no _FillValue.
            enc.setdefault(name, {})["_FillValue"] = None
    return enc


def _clean_attrs(attrs: dict) -> dict:
    """netCDF attributes hold numbers, strings and 1-D numeric arrays only."""
    out = {}
    for key, value in attrs.items():
        if isinstance(value, bool | np.bool_):
            value = int(value)
        elif isinstance(value, list | tuple) and all(isinstance(v, str) for v in value):
            value = ",".join(value)
        elif value is None:
            value = ""
        out[key] = value
    return out


def write_dataset(ds: xr.Dataset, path: str | Path) -> Path:
    """Write ``ds`` to ``path`` atomically (temporary file in the same folder, then rename)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    ds = cf.apply(ds.copy())
    ds.attrs = _clean_attrs(ds.attrs)
    for var in ds.variables.values():
        var.attrs = _clean_attrs(var.attrs)
    tmp = path.with_name(f".{path.name}.tmp-{os.getpid()}")
    try:
        ds.to_netcdf(tmp, engine="netcdf4", encoding=_encoding(ds))
        os.replace(tmp, path)
    finally:
        if tmp.exists():
            tmp.unlink()
    return path


def write_text_atomic(path: str | Path, text: str) -> Path:
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f".{path.name}.tmp-{os.getpid()}")
    tmp.write_text(text)
    os.replace(tmp, path)
    return path


def open_dataset(path: str | Path) -> xr.Dataset:
    """Open and load a dataset fully (so the file handle is released at once)."""
    with xr.open_dataset(path, engine="netcdf4") as ds:
        return ds.load()
