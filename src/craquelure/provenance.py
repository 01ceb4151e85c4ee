"""Provenance attributes carried by every dataset: scene text, seed, effects, versions,
git commit, wall time and start time."""

import platform
import subprocess
import time
from datetime import UTC, datetime
from functools import cache
from pathlib import Path

import craquelure


@cache
def git_commit() -> str:
    """HEAD of the checkout the package lives in, with ``-dirty`` if files are modified."""
    root = Path(craquelure.__file__).resolve().parents[2]
    try:
        head = subprocess.run(["git", "rev-parse", "HEAD"], cwd=root, capture_output=True,
                              text=True, timeout=10, check=True).stdout.strip()
        dirty = subprocess.run(["git", "status", "--porcelain", "--untracked-files=no"],
                               cwd=root, capture_output=True, text=True, timeout=10).stdout
        return head + ("-dirty" if dirty.strip() else "")
    except (OSError, subprocess.SubprocessError):
        return "unknown"


def library_versions() -> dict[str, str]:
    import numba
    import numpy
    import scipy
    import xarray

    return {"version_craquelure": craquelure.__version__,
            **{f"version_{m.__name__}": m.__version__ for m in (numpy, numba, scipy, xarray)},
            "version_python": platform.python_version()}


class WallClock:
    """Start time (ISO, UTC), elapsed wall time and code (the commit at the start: a job that
    outlives a commit ran the code it started with) of a job."""

    def __init__(self) -> None:
        self.start_iso = datetime.now(UTC).isoformat(timespec="seconds")
        self.git_commit = git_commit()
        self._t0 = time.perf_counter()

    @property
    def elapsed(self) -> float:
        return time.perf_counter() - self._t0


def provenance_attrs(scene, seed: int | None, clock: WallClock, effects=None,
                     extra_wall_time: float = 0.0) -> dict[str, object]:
    """Global attributes for a dataset produced from ``scene`` (a :class:`Scene`);
    ``extra_wall_time`` adds time spent in earlier (checkpointed) parts of a resumed run."""
    attrs: dict[str, object] = {
        "model": scene.model, "scene_name": scene.name, "scene": scene.text,
        "scene_source": scene.source_text, "scene_overrides": " ".join(scene.overrides),
        "effects": ",".join(scene.effects if effects is None else effects),
        "git_commit": clock.git_commit, "start_time": clock.start_iso,
        "wall_time_s": float(clock.elapsed + extra_wall_time), "host": platform.node()}
    if seed is not None:
        attrs["seed"] = int(seed)
    attrs.update(library_versions())
    return attrs
