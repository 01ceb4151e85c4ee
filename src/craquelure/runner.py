"""One run loop for every model (in the spirit of HOOMD-blue's ``Simulation.run``).

A model's adapter (:class:`EngineRun`) says how to ``advance()`` to the next safe point, what
to ``sample()``, its ``divergence()`` and its checkpoint ``state()`` / ``restore()`` (a run
resumed from ``state()`` is bit-identical to the uninterrupted run). The runner does the rest:
checkpoints with a fingerprint of scene, seed and code (:func:`usable_checkpoint`), the one
:class:`~craquelure.errors.SimulationDiverged` message, progress lines, the end-of-run
:class:`Summary` and the stop on SIGTERM/SIGINT: the current advance reaches its next safe
point (a long one calls :func:`heartbeat` between sub-steps), a checkpoint is written and
:class:`~craquelure.errors.RunInterrupted` names it (docs/reliability.md). A second signal
acts as it would without the runner.
"""

import hashlib
import signal
import sys
import tempfile
import threading
import time
from dataclasses import dataclass
from functools import cache
from pathlib import Path

import numpy as np

from craquelure.errors import RunInterrupted, SimulationDiverged
from craquelure.progress import Progress
from craquelure.provenance import WallClock, provenance_attrs

# wall-time checkpoint interval when a scene gives none (minutes)
DEFAULT_CHECKPOINT_MINUTES = 10.0
# the signals that make a run checkpoint and stop
STOP_SIGNALS = (signal.SIGTERM, signal.SIGINT)


@dataclass(frozen=True)
class Divergence:
    """A failed health check: its name, what failed and the worst particle (if one)."""

    check: str
    what: str
    particle: int | None = None


def diverged(desc: str, bad: Divergence, step: int, time: float,
             time_unit: str = "") -> SimulationDiverged:
    """The one message of a failed guard: which check, the step, the time, the worst particle."""
    where = f" (worst particle {bad.particle})" if bad.particle is not None else ""
    unit = f" {time_unit}" if time_unit else ""
    return SimulationDiverged(f"{desc}: {bad.check} check failed at step {step}, "
                              f"t = {time:.6g}{unit}: {bad.what}{where}")


class EngineRun:
    """Base of the models' adapters, which define ``advance()``, ``done()`` and
    ``n_particles``: ``time`` and ``steps`` read from ``self.engine`` (its attributes named by
    ``TIME`` and ``STEPS``); nothing to record at the ``start()`` (not on resume) or the
    ``finish()``, no guard and no sample unless overridden; the checkpoint ``state()`` /
    ``restore()`` is every attribute of the objects ``parts()`` names (``{prefix: object}``)
    unless overridden."""

    TIME, STEPS = "t", "step_count"
    engine: object

    @property
    def time(self) -> float:
        return float(getattr(self.engine, self.TIME))

    @property
    def steps(self) -> int:
        return int(getattr(self.engine, self.STEPS))

    def start(self) -> None:
        pass

    def divergence(self) -> Divergence | None:
        return None

    def sample(self) -> None:
        pass

    def finish(self) -> None:
        pass

    def state(self) -> dict[str, np.ndarray]:
        return {key: value for prefix, part in self.parts().items()
                for key, value in attributes(part, prefix).items()}

    def restore(self, state: dict[str, np.ndarray]) -> None:
        for prefix, part in self.parts().items():
            set_attributes(part, state, prefix)


def non_finite(fields: dict[str, np.ndarray]) -> Divergence | None:
    """The first field with a NaN/inf, naming the particle (the last axis is the particle)."""
    for name, values in fields.items():
        bad = ~np.isfinite(np.asarray(values))
        if bad.any():
            particle = int(np.flatnonzero(bad.reshape(-1, bad.shape[-1]).any(axis=0))[0]) \
                if bad.ndim else None
            return Divergence("finite", f"{name} is not finite", particle)
    return None


def runaway(energy: float, limit: float, what: str,
            per_particle: np.ndarray | None = None) -> Divergence | None:
    """Energy above its limit (or not finite); the worst particle is the most energetic one."""
    if np.isfinite(energy) and energy <= limit:
        return None
    worst = int(np.argmax(per_particle)) if per_particle is not None and per_particle.size else None
    return Divergence("runaway", f"{what} = {energy:.6g} exceeds {limit:.6g}", worst)


_VALUE = (np.ndarray, np.number, float, int, bool)


def attributes(obj, prefix: str = "") -> dict[str, np.ndarray]:
    """The array, number and list attributes of ``obj`` and the lists in its dict attributes
    (an engine's evolving state, generically: a field added later is checkpointed without
    further code; a list of numbers or of equal-shaped arrays becomes one array), with keys
    ``<prefix><name>`` and ``<prefix><name>.<key>``."""
    out = {}
    for name, value in vars(obj).items():
        if isinstance(value, dict):
            out.update({f"{prefix}{name}.{k}": np.asarray(v) for k, v in value.items()
                        if isinstance(v, list)})
        elif isinstance(value, (*_VALUE, list)):
            out[prefix + name] = np.asarray(value) if isinstance(value, list) else value
    return out


def _restored(value: np.ndarray, like: object):
    if isinstance(like, list):
        return list(value.copy()) if value.ndim > 1 else value.tolist()
    return value.copy() if value.ndim else value.item()


def set_attributes(obj, state: dict[str, np.ndarray], prefix: str = "") -> None:
    """Inverse of :func:`attributes` (numbers come back as Python numbers, lists as lists)."""
    for key, value in state.items():
        if key.startswith(prefix):
            name, _, item = key[len(prefix):].partition(".")
            if item:
                getattr(obj, name)[item] = _restored(value, [])
            else:
                setattr(obj, name, _restored(value, getattr(obj, name, None)))


def dataset_bytes(ds) -> np.ndarray:
    """An xarray dataset as the bytes of its netCDF file (checkpointing finished pieces)."""
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "piece.nc"
        ds.to_netcdf(path, engine="netcdf4")
        return np.frombuffer(path.read_bytes(), np.uint8)


def dataset_from_bytes(data: np.ndarray):
    """Inverse of :func:`dataset_bytes`."""
    import xarray as xr

    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "piece.nc"
        path.write_bytes(np.asarray(data, np.uint8).tobytes())
        return xr.load_dataset(path, engine="netcdf4")


@cache
def code_fingerprint() -> str:
    """Hash of the package's Python sources: a checkpoint is only resumed by the same code."""
    root = Path(__file__).resolve().parent
    digest = hashlib.sha256()
    for path in sorted(root.rglob("*.py")):
        digest.update(str(path.relative_to(root)).encode())
        digest.update(path.read_bytes())
    return digest.hexdigest()


def fingerprint(scene, seed: int, extra: bytes = b"") -> str:
    """Resolved scene + seed + code (+ e.g. the initial state's bytes)."""
    digest = hashlib.sha256(f"{scene.text}\nseed={int(seed)}\n{code_fingerprint()}".encode())
    digest.update(extra)
    return digest.hexdigest()


def checkpoint_path(out: Path) -> Path:
    out = Path(out)
    return out.with_name(out.name + ".checkpoint.npz")


def write_checkpoint(path: Path, state: dict[str, np.ndarray]) -> None:
    from craquelure.io import atomic_write

    with atomic_write(path, "checkpoint") as tmp, open(tmp, "wb") as fh:
        np.savez(fh, **{k: np.asarray(v) for k, v in state.items()})


def read_checkpoint(path: Path) -> dict[str, np.ndarray]:
    with np.load(path, allow_pickle=False) as data:
        return {k: data[k] for k in data.files}


RUNNER_KEYS = ("runner_fingerprint", "runner_wall_time", "runner_advances")


def usable_checkpoint(path: Path, fp: str) -> dict[str, np.ndarray] | None:
    """The checkpoint's state if it can be resumed from, else None after saying why on stderr
    (damaged, not a checkpoint, or of another scene, seed, initial state or code)."""
    try:
        state = read_checkpoint(path)
    except Exception as exc:  # noqa: BLE001 - zip/npy errors of a damaged file vary
        reason = f"damaged or truncated, cannot be read ({type(exc).__name__}: {exc})"
    else:
        missing = [key for key in RUNNER_KEYS if key not in state]
        if missing:
            reason = f"not a checkpoint of this package: missing {', '.join(missing)}"
        elif str(state["runner_fingerprint"]) != fp:
            reason = ("its fingerprint does not match this run (made by another scene, seed, "
                      "initial state or code)")
        else:
            return state
    print(f"refusing checkpoint {path}: {reason}; starting from the beginning", file=sys.stderr)
    return None


@dataclass
class Summary:
    """End-of-run numbers; ``attrs()`` for the run dataset."""

    steps: int
    simulated_time: float
    wall_time_s: float
    particle_steps_per_s: float
    resumed_at_step: int
    time_unit: str
    earlier_wall_time_s: float = 0.0  # of the checkpointed parts before a resume

    def line(self) -> str:
        return (f"{self.steps} steps, simulated time {self.simulated_time:.6g} {self.time_unit}, "
                f"wall time {self.wall_time_s:.1f} s, "
                f"{self.particle_steps_per_s:.3g} particle-steps/s"
                + (f" (resumed at step {self.resumed_at_step})" if self.resumed_at_step else ""))

    def attrs(self) -> dict[str, float | int]:
        return {"run_steps": self.steps, "run_simulated_time": self.simulated_time,
                "run_particle_steps_per_s": self.particle_steps_per_s,
                "run_resumed_at_step": self.resumed_at_step}


class Stopped(Exception):
    """Raised by :func:`run` after ``stop_after_checkpoints`` checkpoints (resume tests)."""


class Interrupted(Exception):
    """Raised by :func:`heartbeat` inside an advance once a stop signal came."""


class _Monitor:
    """The run in progress as :func:`heartbeat` sees it: the stop signal received (if any)
    and the progress bar with its rate."""

    def __init__(self, engine, bar: Progress | None, t_end: float, time_scale: float) -> None:
        self.engine, self.bar, self.t_end, self.time_scale = engine, bar, t_end, time_scale
        self.signal: int | None = None
        self.steps0, self.t0 = engine.steps, time.perf_counter()
        self._previous: dict[int, object] = {}

    def install(self) -> None:
        if threading.current_thread() is not threading.main_thread():
            return  # signal handlers can only be set in the main thread
        for sig in STOP_SIGNALS:
            self._previous[sig] = signal.signal(sig, self._received)

    def uninstall(self) -> None:
        for sig, handler in self._previous.items():
            signal.signal(sig, handler)
        self._previous = {}

    def _received(self, signum, frame) -> None:
        self.signal = signum
        self.uninstall()  # a second signal acts as without the runner

    def progress(self) -> None:
        if self.bar is None:
            return
        engine = self.engine
        rate = (engine.steps - self.steps0) * engine.n_particles / max(
            time.perf_counter() - self.t0, 1e-9)
        self.bar.update_to(min(engine.time, self.t_end) * self.time_scale,
                           f"{rate:.3g} particle-steps/s")

    def beat(self) -> None:
        self.progress()
        if self.signal is not None:
            raise Interrupted


_ACTIVE: list[_Monitor] = []


def heartbeat() -> None:
    """For long advances, between safe sub-steps: print the run's progress line when due and
    raise :class:`Interrupted` when a stop signal came (no-op outside :func:`run`)."""
    if _ACTIVE:
        _ACTIVE[-1].beat()


def stop_requested() -> bool:
    """True once a stop signal came to the run in progress (for loops that stop by
    themselves)."""
    return bool(_ACTIVE) and _ACTIVE[-1].signal is not None


def run(engine: EngineRun, scene, seed: int, *, t_end: float, desc: str, out: Path | None = None,
        resume: bool = False, every: int = 0, minutes: float = DEFAULT_CHECKPOINT_MINUTES,
        time_unit: str = "", time_scale: float = 1.0, extra_fingerprint: bytes = b"",
        progress: bool = True, stop_after_checkpoints: int | None = None,
        clock: WallClock | None = None) -> Summary:
    """Advance ``engine`` until it is done. ``every`` (advances) and ``minutes`` (wall time) set
    the checkpoint schedule (0: off; checkpoints need ``out``); ``time_scale`` converts engine
    time to the progress unit."""
    clock = clock or WallClock()
    ck_path = checkpoint_path(out) if out is not None else None
    fp = fingerprint(scene, seed, extra_fingerprint)
    wall_before, advances, resumed_at = 0.0, 0, 0
    state = usable_checkpoint(ck_path, fp) if resume and ck_path is not None \
        and ck_path.exists() else None
    if state is not None:
        state.pop("runner_fingerprint")
        wall_before = float(state.pop("runner_wall_time"))
        advances = int(state.pop("runner_advances"))
        engine.restore(state)
        resumed_at = engine.steps
        print(f"resumed from {ck_path} at t = {engine.time * time_scale:.6g} {time_unit} "
              f"(step {engine.steps})", file=sys.stderr)
    if not resumed_at:
        engine.start()
    bar = Progress(t_end * time_scale, desc, unit=time_unit or "t",
                   initial=engine.time * time_scale) if progress else None
    monitor = _Monitor(engine, bar, t_end, time_scale)
    steps0, t0 = engine.steps, monitor.t0
    last_ck, written = t0, 0

    def save() -> None:
        write_checkpoint(ck_path, {**engine.state(), "runner_fingerprint": fp,
                                   "runner_wall_time": wall_before + clock.elapsed,
                                   "runner_advances": advances})

    _ACTIVE.append(monitor)
    monitor.install()
    try:
        while not engine.done():
            try:
                engine.advance()
            except Interrupted:
                pass  # the adapter's state is that of the last safe sub-step
            else:
                bad = engine.divergence()
                if bad is not None:
                    raise diverged(desc, bad, engine.steps, engine.time * time_scale, time_unit)
                engine.sample()
                advances += 1
                monitor.progress()
            now = time.perf_counter()
            if monitor.signal is not None and not engine.done():
                where = f"{signal.Signals(monitor.signal).name} at t = " \
                    f"{engine.time * time_scale:.6g}{' ' + time_unit if time_unit else ''} " \
                    f"(step {engine.steps})"
                if ck_path is None:
                    raise RunInterrupted(f"{where}; no output file, so no checkpoint")
                save()
                raise RunInterrupted(f"{where}: checkpoint written to {ck_path}; run again "
                                     f"with --resume to continue")
            due = (every and advances % every == 0) or (minutes and now - last_ck >= 60 * minutes)
            if ck_path is not None and due and not engine.done():
                save()
                last_ck, written = now, written + 1
                if stop_after_checkpoints is not None and written >= stop_after_checkpoints:
                    raise Stopped(str(ck_path))
    finally:
        monitor.uninstall()
        _ACTIVE.remove(monitor)
        if bar is not None:
            bar.close("done" if engine.done() else "stopped")
    wall = time.perf_counter() - t0
    summary = Summary(engine.steps, engine.time * time_scale, wall_before + clock.elapsed,
                      (engine.steps - steps0) * engine.n_particles / max(wall, 1e-9),
                      resumed_at, time_unit, wall_before)
    print(f"[{desc}] done: {summary.line()}", file=sys.stderr)
    return summary


def write_run(ds, out: Path, scene, seed: int | None, summary: Summary, clock: WallClock) -> Path:
    """Write the finished run dataset with its provenance (wall time of all parts of a resumed
    run) and the run summary (``run_*`` attributes), atomically; then drop the checkpoint."""
    from craquelure.io import write_dataset

    ds.attrs.update(provenance_attrs(scene, seed, clock,
                                     extra_wall_time=summary.earlier_wall_time_s))
    ds.attrs.update(summary.attrs())
    path = write_dataset(ds, out)
    checkpoint_path(out).unlink(missing_ok=True)
    return path


def run_to_file(engine: EngineRun, scene, seed: int | None, out: Path, dataset,
                clock: WallClock, *, checkpoint_every: int | None = None,
                checkpoint_minutes: float | None = None, default_every: int = 0,
                **options) -> Path:
    """A model's run with the checkpoint options of ``craquelure run`` (None: the model's
    ``default_every``, :data:`DEFAULT_CHECKPOINT_MINUTES`): :func:`run`, ``engine.finish()`` and
    :func:`write_run` of ``dataset()``; the checkpoint's path instead when
    ``stop_after_checkpoints`` ended the run early."""
    out = Path(out)
    minutes = DEFAULT_CHECKPOINT_MINUTES if checkpoint_minutes is None else checkpoint_minutes
    try:
        summary = run(engine, scene, seed or 0, out=out, clock=clock, minutes=float(minutes),
                      every=checkpoint_every or default_every, **options)
    except Stopped:
        return checkpoint_path(out)
    engine.finish()
    return write_run(dataset(), out, scene, seed, summary, clock)
