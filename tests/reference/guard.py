"""The CI profile's numbers and verdicts against the committed reference (tests/reference/ci/).

A CI-profile run (``config/ci.yaml``) is reduced to a *snapshot*: every ``summary.json`` under
``results/`` and the claims of ``results/validation.json``, with the quantities below left out.
The reference is the snapshot of an accepted run, one JSON file per source under
``tests/reference/ci/`` (``results/`` dropped from the path), plus ``REFERENCE.json`` (why it
was made, from which commit, and the digest of the files). :func:`differences` names every key
whose value moved.

Per quantity, the tolerance and why:

- numbers of ``summary.json`` (floats, integers, booleans), strings and list lengths: **exact**
  (a float equals its reference bit for bit: JSON writes floats as their shortest repr, which
  reads back to the same double). Every CI run is single-threaded with fixed seeds and the
  runs are deterministic (same scene, seed and threads give the same dataset), so any
  difference is a change in results. The reference holds for this machine's CPU and the
  pinned libraries (requirements.lock): numba compiles for the host CPU, and another CPU
  family may round differently; regenerate there.
- timings (a key naming wall or CPU time, seconds, elapsed time, a runtime or a rate per
  second): **left out**; they measure the machine and its load, not the model.
- provenance (``git_commit``, start times, host, library versions, command history):
  **left out**; they change with every commit by design.
- validation claims (per claim: source, criterion, measured, verdict, note), the tally per
  model and the claims judged by benchmarks instead: **exact**; the ``measured`` strings print
  the summaries' numbers, so they move with them. ``provenance`` of validation.json is left
  out (see above).

A NaN equals a NaN (JSON's ``NaN``: a quantity that could not be computed, stably so).
"""

from __future__ import annotations

import hashlib
import json
import math
import re
import tarfile
from collections.abc import Iterator, Mapping
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
REFERENCE = ROOT / "tests" / "reference" / "ci"
META = "REFERENCE.json"
CHANGELOG = ROOT / "CHANGELOG.md"
VALIDATION = "results/validation.json"

# Key names left out of the comparison, with the reason (the docstring's table).
TIMING = re.compile(r"(^|_)(wall|cpu|elapsed|seconds|runtime)(_|$)|_per_s$|_per_cpu_s$|"
                    r"^wall_time|_s_by_dim$")
PROVENANCE = re.compile(r"^(git_commit|campaign_git_commit|start_time|host|history|"
                        r"version_.*|provenance)$")


def left_out(key: str) -> str | None:
    """Why a key is not compared ("timing", "provenance"), or None when it is compared."""
    if PROVENANCE.search(key):
        return "provenance"
    if TIMING.search(key):
        return "timing"
    return None


def _strip(value):
    """``value`` without the left-out keys, at any depth."""
    if isinstance(value, dict):
        return {k: _strip(v) for k, v in value.items() if left_out(str(k)) is None}
    if isinstance(value, list):
        return [_strip(v) for v in value]
    return value


def _validation(doc: dict) -> dict:
    """What of validation.json the reference keeps: claims, tally, benchmarked claims."""
    return _strip({key: doc[key] for key in ("profile", "tally", "claims", "benchmarked")
                   if key in doc})


def _sources(folder: Path) -> Iterator[tuple[str, bytes]]:
    """(results-relative path, content) of the snapshot's sources: a workflow folder holding
    results/, or an archive of `snakemake archive` (the sources are packed in it)."""
    if folder.is_file() and folder.name.endswith(".tar.gz"):
        with tarfile.open(folder) as tar:
            for member in tar.getmembers():
                name = member.name.split("/", 1)[1] if "/" in member.name else member.name
                if member.isfile() and _wanted(name):
                    yield name, tar.extractfile(member).read()
        return
    results = folder / "results"
    if not results.is_dir():
        raise FileNotFoundError(f"{folder}: neither a workflow folder with results/ nor a "
                                f".tar.gz archive of one")
    for path in sorted(results.rglob("*.json")):
        name = path.relative_to(folder).as_posix()
        if _wanted(name):
            yield name, path.read_bytes()


def _wanted(name: str) -> bool:
    return name == VALIDATION or (name.startswith("results/") and
                                  name.endswith("/summary.json") and
                                  not name.startswith("results/archive/"))


def snapshot(folder: str | Path) -> dict[str, object]:
    """{results-relative path: compared content} of a CI-profile run (folder or archive)."""
    out: dict[str, object] = {}
    for name, data in _sources(Path(folder)):
        doc = json.loads(data)
        out[name] = _validation(doc) if name == VALIDATION else _strip(doc)
    if VALIDATION not in out:
        raise FileNotFoundError(f"{folder}: no {VALIDATION} (not a finished CI-profile run)")
    return dict(sorted(out.items()))


def _text(content: object) -> str:
    return json.dumps(content, indent=1, sort_keys=True, allow_nan=True) + "\n"


def reference_files(snap: Mapping[str, object]) -> dict[str, str]:
    """{file under tests/reference/ci/: text} of a snapshot."""
    return {name.removeprefix("results/"): _text(content) for name, content in snap.items()}


def digest(files: Mapping[str, str]) -> str:
    """SHA-256 over the reference files (names and texts), the first 12 hex digits."""
    h = hashlib.sha256()
    for name in sorted(files):
        h.update(name.encode() + b"\0" + files[name].encode() + b"\0")
    return h.hexdigest()[:12]


def load_reference(folder: Path | None = None) -> tuple[dict[str, object], dict]:
    """(snapshot, REFERENCE.json) of the committed reference."""
    folder = folder or REFERENCE
    meta = json.loads((folder / META).read_text())
    snap = {f"results/{p.relative_to(folder).as_posix()}": json.loads(p.read_text())
            for p in sorted(folder.rglob("*.json")) if p.name != META}
    return snap, meta


def reference_digest(folder: Path | None = None) -> str:
    snap, _ = load_reference(folder)
    return digest(reference_files(snap))


def changelog_line(files_digest: str, reason: str) -> str:
    return f"- CI reference `tests/reference/ci/` (digest {files_digest}) regenerated: {reason}"


def changelog_has(files_digest: str, changelog: Path | None = None) -> bool:
    """Does CHANGELOG.md carry the line of the reference with this digest?"""
    changelog = changelog or CHANGELOG
    return changelog.is_file() and f"(digest {files_digest})" in changelog.read_text()


def _flat(value, prefix: str) -> Iterator[tuple[str, object]]:
    if isinstance(value, dict):
        for k, v in value.items():
            yield from _flat(v, f"{prefix}.{k}")
    elif isinstance(value, list):
        yield f"{prefix}[len]", len(value)
        for i, v in enumerate(value):
            yield from _flat(v, f"{prefix}[{i}]")
    else:
        yield prefix, value


def _claims_keyed(doc: dict) -> dict:
    """validation claims keyed by "<model>: <claim>" (so a moved verdict is named by its claim,
    not by its position)."""
    doc = dict(doc)
    keyed: dict[str, dict] = {}
    for c in doc.pop("claims", []):
        key, n = f"{c['model']}: {c['claim']}", 2
        while key in keyed:
            key, n = f"{c['model']}: {c['claim']} #{n}", n + 1
        keyed[key] = {k: v for k, v in c.items() if k not in ("model", "claim")}
    doc["claims"] = keyed
    return doc


def _same(a, b) -> bool:
    if isinstance(a, float) and isinstance(b, float) and math.isnan(a) and math.isnan(b):
        return True
    return type(a) is type(b) and a == b


def differences(reference: Mapping[str, object], now: Mapping[str, object]) -> list[str]:
    """One line per key whose value differs: "<file>: <key>: <reference> -> <now>" (missing
    and new keys and files included)."""
    out = []
    for name in sorted(set(reference) | set(now)):
        if name not in now:
            out.append(f"{name}: missing from this run (in the reference)")
            continue
        if name not in reference:
            out.append(f"{name}: new in this run (not in the reference)")
            continue
        ref, cur = reference[name], now[name]
        if name == VALIDATION:
            ref, cur = _claims_keyed(ref), _claims_keyed(cur)
        a, b = dict(_flat(ref, "")), dict(_flat(cur, ""))
        for key in sorted(set(a) | set(b)):
            where = key.lstrip(".")
            if key not in b:
                out.append(f"{name}: {where}: {a[key]!r} -> (missing)")
            elif key not in a:
                out.append(f"{name}: {where}: (new) -> {b[key]!r}")
            elif not _same(a[key], b[key]):
                out.append(f"{name}: {where}: {a[key]!r} -> {b[key]!r}")
    return out


HOW_TO_REGENERATE = (
    "If the change is intended, regenerate the reference and commit it with the change: "
    "`make reference REASON='<why the numbers moved>'` (runs the CI profile in a temporary "
    "copy, several minutes) or, from the archive this test run packed, `make reference "
    "REASON='...' RESULTS=results/archive/craquelure-ci-<date>.tar.gz`; it writes "
    "tests/reference/ci/ and the CHANGELOG.md line that names the new digest.")


def report(diffs: list[str], limit: int = 60) -> str:
    shown = "\n  ".join(diffs[:limit])
    more = f"\n  ... and {len(diffs) - limit} more" if len(diffs) > limit else ""
    return (f"{len(diffs)} value(s) of the CI run differ from tests/reference/ci/ "
            f"(file: key: reference -> this run):\n  {shown}{more}\n{HOW_TO_REGENERATE}")


def write_reference(snap: Mapping[str, object], reason: str, commit: str,
                    folder: Path | None = None) -> str:
    """Replace the reference by ``snap``; returns the digest of its files."""
    folder = folder or REFERENCE
    files = reference_files(snap)
    if folder.exists():
        for old in folder.rglob("*.json"):
            old.unlink()
    for name, text in files.items():
        path = folder / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)
    files_digest = digest(files)
    meta = {"reason": reason, "made_from_commit": commit, "digest": files_digest,
            "compared": "see tests/reference/guard.py and docs/reliability.md"}
    (folder / META).write_text(json.dumps(meta, indent=1) + "\n")
    return files_digest


def add_changelog_line(line: str, date: str, changelog: Path | None = None) -> None:
    """Insert ``line`` under the ``## <date>`` heading (created below the intro if missing)."""
    changelog = changelog or CHANGELOG
    text = changelog.read_text() if changelog.is_file() else (
        "# Changelog\n\nNewest on top. Every entry says what was compared and whether results "
        "changed.\n")
    heading = f"## {date}"
    lines = text.splitlines()
    if heading in lines:
        at = lines.index(heading) + 1
        while at < len(lines) and not lines[at].strip():
            at += 1
        lines[at:at] = [line]
    else:
        first = next((i for i, x in enumerate(lines) if x.startswith("## ")), len(lines))
        lines[first:first] = ["", heading, "", line, ""] if first == len(lines) else \
            [heading, "", line, ""]
    changelog.write_text("\n".join(lines).rstrip("\n") + "\n")

