"""Writes that fail: a full disk (a size-limited tmpfs), a read-only folder (a tmpfs remounted
read-only) and a forbidden one (EACCES). The previous dataset or checkpoint stays intact, no
temporary is left behind, and the error is one line naming the file and the cause (exit 2 from
the command line).

Mounting needs root (and a kernel that lets the process mount): where it cannot be done the
real-filesystem tests are skipped, saying so. As root, a folder's permissions do not stop a
write, so EACCES is tested by making the rename fail (and for real when not root)."""

from __future__ import annotations

import errno
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from craquelure import io as cio
from craquelure.errors import WriteError
from craquelure.io import open_dataset, write_dataset, write_text_atomic
from craquelure.runner import read_checkpoint, write_checkpoint


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
