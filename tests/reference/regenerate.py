"""Regenerate the CI reference (tests/reference/ci/) from a CI-profile run, and add the
CHANGELOG.md line that names it. ``make reference REASON='...'`` calls this.

    python -m tests.reference.regenerate --reason "why the numbers moved"
        [--from WORKFLOW_FOLDER | --from results/archive/craquelure-ci-<date>.tar.gz]

Without ``--from`` it runs ``snakemake --configfile config/ci.yaml`` (the same run the test
suite does) in a temporary copy of Snakefile, workflow/, config/ and profiles/, then reads it.
With ``--from`` it reads a finished CI-profile run: its workflow folder, or the archive
``snakemake archive`` packed of it (the end-to-end test copies one to results/archive/).
Prints what moved against the old reference. What is compared, and how exactly:
tests/reference/guard.py.
"""

from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
import tempfile
from datetime import UTC, datetime
from pathlib import Path

from tests.reference import guard


def ci_run(dest: Path, cores: int) -> Path:
    """The CI profile run in a fresh copy of the workflow under ``dest``."""
    shutil.copy2(guard.ROOT / "Snakefile", dest / "Snakefile")
    for folder in ("workflow", "config", "profiles"):
        shutil.copytree(guard.ROOT / folder, dest / folder,
                        ignore=shutil.ignore_patterns("__pycache__", "*.pyc"))
    env = dict(os.environ)
    env["PATH"] = f"{Path(sys.executable).parent}{os.pathsep}{env.get('PATH', '')}"
    print(f"running the CI profile in {dest} ...", flush=True)
    proc = subprocess.run([sys.executable, "-m", "snakemake", "--cores", str(cores),
                           "--configfile", "config/ci.yaml"], cwd=dest, env=env,
                          capture_output=True, text=True)
    if proc.returncode != 0:
        sys.exit(f"the CI-profile run failed (exit {proc.returncode}); its log:\n"
                 f"{proc.stderr[-4000:]}")
    return dest


def commit() -> str:
    try:
        return subprocess.run(["git", "rev-parse", "HEAD"], cwd=guard.ROOT, check=True,
                              capture_output=True, text=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "unknown"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--reason", required=True,
                        help="why the numbers moved (goes into CHANGELOG.md)")
    parser.add_argument("--from", dest="source", type=Path, default=None,
                        help="a finished CI-profile run: workflow folder or its archive")
    parser.add_argument("--cores", type=int, default=2)
    args = parser.parse_args(argv)
    if not args.reason.strip():
        parser.error("--reason: say why the numbers moved (it goes into CHANGELOG.md)")
    with tempfile.TemporaryDirectory(prefix="craquelure-reference-") as tmp:
        source = args.source or ci_run(Path(tmp), args.cores)
        snap = guard.snapshot(source)
    old = guard.load_reference()[0] if (guard.REFERENCE / guard.META).is_file() else {}
    diffs = guard.differences(old, snap)
    files_digest = guard.write_reference(snap, args.reason.strip(), commit())
    line = guard.changelog_line(files_digest, args.reason.strip())
    if not guard.changelog_has(files_digest):
        guard.add_changelog_line(line, datetime.now(UTC).strftime("%Y-%m-%d"))
    print(f"wrote {guard.REFERENCE}/ ({len(snap)} sources, digest "
          f"{files_digest}); {len(diffs)} value(s) moved:")
    for d in diffs:
        print(f"  {d}")
    print(f"CHANGELOG.md: {line}\nCommit tests/reference/ci/ and CHANGELOG.md with the change.")
    return 0


if __name__ == "__main__":
    sys.exit(main())
