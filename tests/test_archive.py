"""Archive and ``craquelure verify``: a clean archive verifies; a flipped byte and a missing
file are each named, in the archive and in its unpacked folder."""

from __future__ import annotations

import hashlib
import subprocess
import tarfile
from pathlib import Path

import numpy as np
import pytest

from craquelure import cli
from craquelure.archive import MANIFEST, build_archive, parse_manifest, verify
from craquelure.errors import CraquelureError

FILES = {
    "results/drying/ci/run/seed1.nc": np.random.default_rng(1).bytes(20000),
    "results/drying/figures/drying_snapshots.png": b"\x89PNG\r\n\x1a\n" + bytes(range(256)) * 8,
    "results/validation.json": b'{"claims": []}\n',
    "config/ci.yaml": b"profile: ci\n",
}


@pytest.fixture
def project(tmp_path, monkeypatch) -> Path:
    monkeypatch.chdir(tmp_path)
    for name, data in FILES.items():
        Path(name).parent.mkdir(parents=True, exist_ok=True)
        Path(name).write_bytes(data)
    return tmp_path


def make(project) -> Path:
    return build_archive(project / "results/archive/craquelure-ci-2026-12-01.tar.gz",
                         list(FILES), {"resolved-config.yaml": "profile: ci\n"})


def unpack(archive: Path, dest: Path) -> Path:
    with tarfile.open(archive) as tar:
        tar.extractall(dest, filter="data")
    return dest / "craquelure-ci-2026-12-01"


def flip_byte(path: Path, offset: int) -> None:
    data = bytearray(path.read_bytes())
    data[offset] ^= 0x01
    path.write_bytes(bytes(data))


def test_archive_layout_and_manifest(project):
    archive = make(project)
    folder = unpack(archive, project / "unpacked")
    digests = parse_manifest((folder / MANIFEST).read_text())
    assert set(digests) == set(FILES) | {"resolved-config.yaml"}
    for name, data in FILES.items():
        assert digests[name] == hashlib.sha256(data).hexdigest()
        assert (folder / name).read_bytes() == data
    sidecar = archive.with_name(archive.name + ".sha256").read_text().split()
    assert sidecar == [hashlib.sha256(archive.read_bytes()).hexdigest(), archive.name]
    # The manifest is sha256sum's format: the standard tool agrees.
    check = subprocess.run(["sha256sum", "-c", "--quiet", MANIFEST], cwd=folder,
                           capture_output=True, text=True)
    assert check.returncode == 0, check.stdout + check.stderr
    assert not [p for p in (project / "results/archive").iterdir() if ".tmp" in p.name]


def test_clean_archive_and_folder_verify(project, capsys):
    archive = make(project)
    assert verify(archive) == ([], len(FILES) + 1)
    folder = unpack(archive, project / "unpacked")
    assert verify(folder) == ([], len(FILES) + 1)
    assert verify(folder.parent)[0] == []  # the folder the archive was unpacked into
    (folder / ".snakemake_timestamp").write_text("")  # a rule's directory output marker
    assert verify(folder) == ([], len(FILES) + 1)
    assert cli.main(["verify", str(archive)]) == 0
    assert "OK, 5 files match" in capsys.readouterr().out


def test_folder_names_a_flipped_byte_and_a_missing_file(project, capsys):
    folder = unpack(make(project), project / "unpacked")
    flip_byte(folder / "results/drying/ci/run/seed1.nc", 12345)
    (folder / "results/validation.json").unlink()
    (folder / "results/stray.txt").write_text("not archived")
    problems, _ = verify(folder)
    assert len(problems) == 3
    assert problems[0].startswith("changed: results/drying/ci/run/seed1.nc")
    assert problems[1] == "missing: results/validation.json"
    assert problems[2] == "not in manifest: results/stray.txt"
    assert cli.main(["verify", str(folder)]) == 1
    out = capsys.readouterr().out
    assert "seed1.nc" in out and "validation.json" in out and "3 mismatch(es)" in out


def test_archive_with_a_changed_and_a_missing_member(project):
    """An archive repacked with one member altered and one dropped (its sidecar digest then
    no longer matches either)."""
    archive = make(project)
    folder = unpack(archive, project / "unpacked")
    flip_byte(folder / "results/drying/figures/drying_snapshots.png", 100)
    (folder / "config/ci.yaml").unlink()
    with tarfile.open(archive, "w:gz") as tar:
        tar.add(folder, arcname=folder.name)
    problems, _ = verify(archive)
    assert problems[0].startswith(f"changed: {archive.name} (SHA-256")
    assert problems[1] == "missing: config/ci.yaml"
    assert problems[2].startswith("changed: results/drying/figures/drying_snapshots.png")
    assert len(problems) == 3


def test_flipped_byte_in_the_compressed_archive(project):
    archive = make(project)
    flip_byte(archive, archive.stat().st_size // 2)
    problems, _ = verify(archive)
    assert problems[0].startswith(f"changed: {archive.name}")
    # gzip's CRC or the tar structure catches it too; whichever, it is named, not a traceback.
    assert any(p.startswith(("unreadable:", "changed: results/")) for p in problems[1:])


def test_bad_paths(project):
    with pytest.raises(CraquelureError, match="not found"):
        verify(project / "nothing.tar.gz")
    with pytest.raises(CraquelureError, match=f"no {MANIFEST}"):
        verify(project / "results")
    with pytest.raises(CraquelureError, match="does not exist"):
        build_archive(project / "a.tar.gz", ["results/none.nc"])
    with pytest.raises(CraquelureError, match="relative path"):
        build_archive(project / "a.tar.gz", [str(project / "config/ci.yaml")])


def test_benchmark_cpu_seconds_reads_the_jobs_cpu_time(tmp_path):
    from craquelure.archive import benchmark_cpu_seconds

    path = tmp_path / "job.tsv"
    path.write_text("s\th:m:s\tmax_rss\tcpu_time\n12.5\t0:00:12\t100.0\t11.25\n")
    assert benchmark_cpu_seconds(path) == 11.25
    assert benchmark_cpu_seconds(tmp_path / "absent.tsv") is None
