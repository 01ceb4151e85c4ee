"""Dataset writing (compressed netCDF4 with CF-1.11 metadata, written to a temporary name and
renamed: :func:`atomic_write`, so a killed job never leaves a file that looks finished) and
reading (:func:`open_dataset`, :func:`read_dataset`: errors name the file and what is wrong).
"""

import errno
import os
import struct
from collections.abc import Iterable, Iterator
from contextlib import contextmanager
from pathlib import Path

import numpy as np
import xarray as xr

from craquelure import cf
from craquelure.errors import CraquelureError, WriteError

HDF5_SIGNATURE = b"\x89HDF\r\n\x1a\n"
CLASSIC_SIGNATURES = (b"CDF\x01", b"CDF\x02", b"CDF\x05")

# Variables that tell the datasets of this package apart (for "a <kind>, not a <kind>").
KIND_SIGNATURES = {
    "drying initial state": ("sigma_e_xx", "sigma_e_yy", "sigma_e_xy", "mass", "rho"),
    "drying run dataset": ("alive", "mean_stress", "n_removed", "mass"),
    "fragment dataset": ("fragment_area", "n_fragments", "paste_fraction"),
    "lattice run dataset": ("bond_state", "theta", "bond_i"),
    "impact run dataset": ("series_contact_force", "snap_damage"),
}


class DatasetError(CraquelureError):
    """A dataset given to a command cannot be used; the message names the file and why."""


def _encoding(ds: xr.Dataset) -> dict[str, dict]:
    enc = {}
    for name, var in ds.variables.items():
        if var.dtype.kind in "fiub" and var.ndim > 0:
            # fletcher32: a checksum per chunk, so a damaged file fails to read instead of
            # returning altered numbers
            enc[name] = {"zlib": True, "complevel": 4, "fletcher32": True}
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
    ds = cf.apply(ds.copy())
    ds.attrs = _clean_attrs(ds.attrs)
    for var in ds.variables.values():
        var.attrs = _clean_attrs(var.attrs)
    with atomic_write(path, "dataset") as tmp:
        ds.to_netcdf(tmp, engine="netcdf4", encoding=_encoding(ds))
    return path


def write_cause(exc: BaseException, folder: Path) -> str:
    """Why a write into ``folder`` failed, in the OS's words: the netCDF library reports a
    full disk as "HDF error" and a read-only file system as "Permission denied", so the
    folder's file system is asked when the error carries no reason."""
    try:
        fs = os.statvfs(folder)
    except OSError:
        fs = None
    if fs is not None and fs.f_flag & os.ST_RDONLY:  # netCDF says "Permission denied"
        return os.strerror(errno.EROFS)
    code = getattr(exc, "errno", None)
    if isinstance(code, int) and code > 0:
        return os.strerror(code)
    if fs is not None and fs.f_bavail * fs.f_frsize < 1 << 20:
        return os.strerror(errno.ENOSPC)
    if not os.access(folder, os.W_OK):
        return os.strerror(errno.EACCES)
    return f"{type(exc).__name__}: {exc}"


@contextmanager
def atomic_write(path: str | Path, what: str = "file") -> Iterator[Path]:
    """Yield a temporary path next to ``path`` to write to; rename it to ``path`` when the
    block ends. If anything fails the temporary is removed and ``path`` keeps its old content;
    a failure of the file system (OSError; the netCDF library's RuntimeError) becomes a
    :class:`WriteError` "cannot write <what> <path>: <cause>"."""
    path = Path(path)
    tmp = path.with_name(f".{path.name}.tmp-{os.getpid()}")
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        remove_stale_temporaries(path)
        yield tmp
        os.replace(tmp, path)
    except (OSError, RuntimeError) as exc:
        _discard(tmp)
        raise WriteError(f"cannot write {what} {path}: "
                         f"{write_cause(exc, _existing_folder(path))}") from exc
    except BaseException:
        _discard(tmp)
        raise


def _discard(tmp: Path) -> None:
    try:
        tmp.unlink(missing_ok=True)
    except OSError:  # nothing was written there (read-only folder)
        pass


def _existing_folder(path: Path) -> Path:
    folder = path.parent
    while not folder.exists() and folder != folder.parent:
        folder = folder.parent
    return folder


def _pid_alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True  # another user's live process
    return True


def remove_stale_temporaries(path: str | Path) -> list[Path]:
    """Remove the temporaries ``.<name>.tmp-<pid>`` of ``path`` left by processes that are no
    longer running (a killed run); a live writer's temporary is left alone."""
    path = Path(path)
    removed = []
    for tmp in path.parent.glob(f".{path.name}.tmp-*"):
        pid = tmp.name.rsplit("-", 1)[-1]
        if pid.isdigit() and int(pid) != os.getpid() and not _pid_alive(int(pid)):
            tmp.unlink(missing_ok=True)
            removed.append(tmp)
    return removed


def write_text_atomic(path: str | Path, text: str) -> Path:
    path = Path(path)
    with atomic_write(path) as tmp:
        tmp.write_text(text)
    return path


def _hdf5_end_of_file(head: bytes) -> int | None:
    """End-of-file address stored in an HDF5 superblock (versions 0-3), or None."""
    if not head.startswith(HDF5_SIGNATURE) or len(head) < 16:
        return None
    version = head[8]
    if version in (0, 1):
        size_offsets = head[13]
        start = 24 + (4 if version == 1 else 0) + 2 * size_offsets
    elif version in (2, 3):
        size_offsets = head[9]
        start = 12 + 2 * size_offsets
    else:
        return None
    fmt = {4: "<I", 8: "<Q"}.get(size_offsets)
    if fmt is None or len(head) < start + size_offsets:
        return None
    return struct.unpack(fmt, head[start:start + size_offsets])[0]


def diagnose_file(path: str | Path) -> str | None:
    """Why ``path`` cannot be a readable netCDF dataset, judged from its header and size
    (None if it looks whole): missing, empty, not netCDF/HDF5, truncated."""
    path = Path(path)
    if not path.exists():
        return "not found"
    if path.is_dir():
        return "a directory, not a dataset file"
    size = path.stat().st_size
    if size == 0:
        return "empty (0 bytes): truncated"
    with open(path, "rb") as fh:
        head = fh.read(512)
    if head.startswith(CLASSIC_SIGNATURES):
        return None
    if not head.startswith(HDF5_SIGNATURE):
        return "not a netCDF file (no netCDF/HDF5 signature): unreadable"
    end = _hdf5_end_of_file(head)
    return f"truncated: {size} of {end} bytes" if end is not None and end > size else None


def open_dataset(path: str | Path) -> xr.Dataset:
    """Open and load a dataset fully (so the file handle is released at once). A file that
    cannot be read raises :class:`DatasetError` naming it and saying why."""
    reason = diagnose_file(path)
    if reason is not None:
        raise DatasetError(f"{path}: {reason}")
    try:
        with xr.open_dataset(path, engine="netcdf4") as ds:
            return ds.load()
    except (OSError, RuntimeError, ValueError, KeyError, IndexError, TypeError) as exc:
        # the netCDF/HDF5 libraries report damage as OSError or RuntimeError ("NetCDF: HDF
        # error") when the header or a chunk does not decode
        raise DatasetError(f"{path}: damaged, cannot be read ({type(exc).__name__}: "
                           f"{exc})") from exc


def dataset_kind(ds: xr.Dataset) -> str | None:
    """The kind of a dataset of this package from its variables (:data:`KIND_SIGNATURES`)."""
    for kind, names in KIND_SIGNATURES.items():
        if all(name in ds.variables for name in names):
            return kind
    return None


def read_dataset(path: str | Path, kind: str, model: str | None = None,
                 variables: Iterable[str] = ()) -> xr.Dataset:
    """:func:`open_dataset`, then check the model (provenance attribute ``model``) and that
    the variables a command needs are there; errors name the file, the expected ``kind`` and
    what the file is instead."""
    ds = open_dataset(path)
    found = ds.attrs.get("model")
    if model is not None and found is not None and found != model:
        raise DatasetError(f"{path}: a dataset of model {found!r}; expected a {kind} of model "
                           f"{model!r}")
    missing = [name for name in variables if name not in ds.variables]
    if missing:
        other = dataset_kind(ds)
        what = f"it is a {other}, not a {kind}" if other and other != kind else \
            f"not a usable {kind}"
        raise DatasetError(f"{path}: {what}: missing variable(s) {', '.join(missing)}")
    return ds
