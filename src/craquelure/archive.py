"""Archive of a finished workflow: the final datasets, figures, reports and resolved
configuration in one ``.tar.gz`` with a SHA-256 manifest, and the check of an archive or of its
unpacked folder against that manifest (docs/outputs.md, "Archive").

``craquelure-<profile>-<date>.tar.gz`` holds one top folder of the same name with
``MANIFEST.sha256`` (``sha256sum -c`` format) and the files under their project paths; beside
it, ``<archive>.sha256`` holds the digest of the archive file itself. ``protected()`` output
flags are only a permission bit: the manifest is what lets anyone check later that nothing
changed.
"""

import csv
import hashlib
import io
import os
import tarfile
import zlib
from collections.abc import Iterable, Mapping
from pathlib import Path

from craquelure.errors import CraquelureError

MANIFEST = "MANIFEST.sha256"
# Snakemake's marker in a directory() output written after the job (an archived folder made by
# a rule carries it): no part of the result, never in a manifest.
SNAKEMAKE_MARKER = ".snakemake_timestamp"


def benchmark_cpu_seconds(path: str | Path) -> float | None:
    """CPU seconds of the job a Snakemake benchmark file times (its ``cpu_time``), or None
    when the file does not exist (a job run outside Snakemake)."""
    if not Path(path).is_file():
        return None
    with open(path, newline="") as fh:
        return float(next(csv.DictReader(fh, delimiter="\t"))["cpu_time"])


def sha256_file(path: str | Path) -> str:
    with open(path, "rb") as fh:
        return hashlib.file_digest(fh, "sha256").hexdigest()


def manifest_text(digests: Mapping[str, str]) -> str:
    return "".join(f"{digests[name]}  {name}\n" for name in sorted(digests))


def parse_manifest(text: str) -> dict[str, str]:
    digests = {}
    for number, line in enumerate(text.splitlines(), 1):
        if not line.strip():
            continue
        digest, sep, name = line.partition("  ")
        if not sep or len(digest) != 64:
            raise CraquelureError(f"{MANIFEST} line {number} is not '<sha256>  <path>': {line!r}")
        digests[name] = digest
    return digests


def build_archive(out: str | Path, files: Iterable[str | Path],
                  texts: Mapping[str, str] | None = None) -> Path:
    """Pack ``files`` (paths relative to the working directory, kept as archive paths) and
    ``texts`` ({archive path: content}) into ``out`` (.tar.gz) with the manifest; write
    ``<out>.sha256``. Written to temporary names and renamed, so an archive that exists is
    whole."""
    out = Path(out)
    top = out.name.removesuffix(".tar.gz")
    members: dict[str, bytes | Path] = {}
    for f in files:
        path = Path(f)
        if path.is_absolute() or ".." in path.parts:
            raise CraquelureError(f"archive member {f} must be a relative path inside the project")
        if not path.is_file():
            raise CraquelureError(f"archive member {f} does not exist")
        members[path.as_posix()] = path
    members.update({name: text.encode() for name, text in (texts or {}).items()})
    if MANIFEST in members:
        raise CraquelureError(f"{MANIFEST} is written by the archive itself")
    digests = {name: (hashlib.sha256(src).hexdigest() if isinstance(src, bytes)
                      else sha256_file(src)) for name, src in members.items()}
    out.parent.mkdir(parents=True, exist_ok=True)
    tmp = out.with_name(f".{out.name}.tmp-{os.getpid()}")
    try:
        with tarfile.open(tmp, "w:gz") as tar:
            _add_bytes(tar, f"{top}/{MANIFEST}", manifest_text(digests).encode())
            for name in sorted(members):
                src = members[name]
                if isinstance(src, bytes):
                    _add_bytes(tar, f"{top}/{name}", src)
                else:
                    tar.add(src, arcname=f"{top}/{name}", recursive=False)
        sidecar = out.with_name(f"{out.name}.sha256")
        sidecar_tmp = sidecar.with_name(f".{sidecar.name}.tmp-{os.getpid()}")
        sidecar_tmp.write_text(f"{sha256_file(tmp)}  {out.name}\n")
        os.replace(tmp, out)
        os.replace(sidecar_tmp, sidecar)
    finally:
        for leftover in out.parent.glob(f".{out.name}*.tmp-{os.getpid()}"):
            leftover.unlink()
    return out


def _add_bytes(tar: tarfile.TarFile, name: str, data: bytes) -> None:
    info = tarfile.TarInfo(name)
    info.size = len(data)
    info.mode = 0o644
    tar.addfile(info, io.BytesIO(data))


# --- verification ---------------------------------------------------------------------------


def _archive_contents(path: Path) -> tuple[dict[str, str], str | None]:
    """{path under the top folder: sha256} of every regular file, and the manifest text."""
    digests: dict[str, str] = {}
    manifest = None
    with tarfile.open(path, "r:*") as tar:
        for member in tar:
            if not member.isfile():
                continue
            top, _, name = member.name.partition("/")
            stream = tar.extractfile(member)
            if name == MANIFEST:
                manifest = stream.read().decode()
            else:
                digests[name or top] = hashlib.file_digest(stream, "sha256").hexdigest()
    return digests, manifest


def _folder_root(path: Path) -> Path:
    if (path / MANIFEST).is_file():
        return path
    subdirs = [p for p in path.iterdir() if p.is_dir()]
    if len(subdirs) == 1 and (subdirs[0] / MANIFEST).is_file():
        return subdirs[0]
    raise CraquelureError(f"no {MANIFEST} in {path} (nor in a single folder inside it)")


def verify(path: str | Path) -> tuple[list[str], int]:
    """Check an archive (.tar.gz) or its unpacked folder against its manifest: (problems,
    number of files checked). Each problem names the file: ``changed``, ``missing``, ``not in
    manifest``, ``unreadable`` (a corrupted archive)."""
    path = Path(path)
    problems: list[str] = []
    if path.is_dir():
        root = _folder_root(path)
        manifest = (root / MANIFEST).read_text()
        actual = {p.relative_to(root).as_posix(): sha256_file(p)
                  for p in sorted(root.rglob("*")) if p.is_file() and p != root / MANIFEST
                  and p.name != SNAKEMAKE_MARKER}
    elif path.is_file():
        sidecar = path.with_name(f"{path.name}.sha256")
        if sidecar.is_file():
            want = sidecar.read_text().split()[0]
            got = sha256_file(path)
            if got != want:
                problems.append(f"changed: {path.name} (SHA-256 {got}, {sidecar.name} says "
                                f"{want})")
        try:
            actual, manifest = _archive_contents(path)
        except (tarfile.TarError, EOFError, zlib.error, OSError) as exc:
            problems.append(f"unreadable: {path.name} is not a whole archive ({exc})")
            return problems, 0
        if manifest is None:
            problems.append(f"missing: {MANIFEST} in {path.name}")
            return problems, 0
    else:
        raise CraquelureError(f"{path} not found (give an archive .tar.gz or its unpacked folder)")
    expected = parse_manifest(manifest)
    for name, digest in sorted(expected.items()):
        if name not in actual:
            problems.append(f"missing: {name}")
        elif actual[name] != digest:
            problems.append(f"changed: {name} (SHA-256 {actual[name]}, manifest says {digest})")
    problems += [f"not in manifest: {name}" for name in sorted(set(actual) - set(expected))]
    return problems, len(expected)
