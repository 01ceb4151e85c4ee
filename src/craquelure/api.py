"""The Python API: the command line's verbs as functions, for scripts and notebooks (example
in :mod:`craquelure`). Each function does what the command of the same name does (the commands
in :mod:`craquelure.commands` parse their arguments, call it and print), for every model;
errors are the commands' one-line :class:`~craquelure.errors.CraquelureError` messages.
"""

import sys
import tempfile
from collections.abc import Iterable, Mapping
from contextlib import ExitStack
from pathlib import Path

import numpy as np
import xarray as xr
import yaml

from craquelure import scene as _scenes
from craquelure.errors import CraquelureError
from craquelure.io import open_dataset, write_dataset
from craquelure.models import model_api, model_module, stage
from craquelure.provenance import WallClock, provenance_attrs
from craquelure.scene import Scene
from craquelure.throughput import long_run_warning

Overrides = Mapping[str, object] | Iterable[str] | None
RunInput = xr.Dataset | str | Path


def scenes() -> dict[str, str]:
    """The built-in scenes, ``{name: one-line description}`` (``craquelure scenes``).

    Example:

        >>> "drying/ci" in craquelure.scenes()
        True
    """
    return dict(_scenes.list_scenes())


def override_strings(overrides: Overrides) -> list[str]:
    """``--set`` strings (``KEY.PATH=VALUE``, the value in YAML) of a dict of dotted keys or
    of a list of such strings.

    Example:

        >>> override_strings({"numerics.dt": 0.002, "numerics.integrator": "rk4"})
        ['numerics.dt=0.002', 'numerics.integrator=rk4']
    """
    if overrides is None:
        return []
    if isinstance(overrides, str):
        raise CraquelureError(f"overrides: {overrides!r} is not allowed; give a dict "
                              "{'key.path': value} or a list of 'key.path=value' strings")
    if not isinstance(overrides, Mapping):
        return [str(item) for item in overrides]
    return [f"{key}={yaml.safe_dump(value, default_flow_style=True, width=1 << 30)}"
            .removesuffix("\n").removesuffix("\n...") for key, value in overrides.items()]


def load_scene(name_or_path: str | Path | Scene, overrides: Overrides = None) -> Scene:
    """The validated scene of a built-in name (``drying/ci``) or a YAML file, with
    ``overrides`` applied: the dotted keys of ``--set``, as a dict or as ``KEY.PATH=VALUE``
    strings (``craquelure check``'s scene). Unknown keys and bad values raise the one-line
    :class:`~craquelure.errors.SceneError` naming the key and what is allowed.

    Example:

        >>> scene = craquelure.load_scene("drying/ci", overrides={"numerics.dt": 0.002})
        >>> scene.get("numerics.dt"), scene.model
        (0.002, 'drying')
    """
    if isinstance(name_or_path, Scene):
        return name_or_path.with_overrides(override_strings(overrides)) if overrides \
            else name_or_path
    return _scenes.load_scene(name_or_path, override_strings(overrides))


class Uncomputable(str):
    """A derived number that cannot be computed, with the reason."""


def check(scene: Scene | str) -> dict[str, object]:
    """The model's derived numbers of a scene (``craquelure check``: neighbours, stable step,
    step count, predicted wall time, ...). Never raises for a valid scene: a number that
    cannot be computed (overflow, division by zero, too large to build) is an
    :class:`Uncomputable` saying why.

    Example:

        >>> numbers = craquelure.check("drying/ci")
        >>> numbers["steps"] > 0
        True
    """
    scene = load_scene(scene)
    api = model_api(scene.model)
    if not hasattr(api, "derived_numbers"):
        return {}
    try:
        with np.errstate(all="ignore"):
            return dict(api.derived_numbers(scene))
    except (ArithmeticError, ValueError, MemoryError) as exc:
        return {"(all)": Uncomputable(f"{type(exc).__name__}: {exc}")}


def warn_if_long(scene: Scene, threads: int) -> None:
    """Print :func:`~craquelure.throughput.long_run_warning` on stderr when the scene's
    predicted wall time exceeds an hour (nothing when it cannot be predicted: the derived
    numbers say why)."""
    api = model_api(scene.model)
    if not hasattr(api, "workload"):
        return
    try:
        with np.errstate(all="ignore"):
            message = long_run_warning(scene.model, api.workload(scene), threads)
    except Exception:  # noqa: BLE001 - advisory only; derived_numbers reports the failure
        return
    if message:
        print(message, file=sys.stderr)


def initial_state(scene: Scene | str, seed: int) -> xr.Dataset:
    """The initial state of a scene and seed with its provenance (``craquelure init``; drying:
    positions, mass-consistency masses and initial stress).

    Example:

        >>> state = craquelure.initial_state("drying/ci", seed=1)
        >>> state.sizes["particle"]
        1600
    """
    clock = WallClock()
    scene = load_scene(scene)
    ds = stage(scene.model, "build_initial_state")(scene, seed)
    ds.attrs.update(provenance_attrs(scene, seed, clock))
    return ds


def run_to_file(scene: Scene | str, out: str | Path, seed: int = 0,
                init: RunInput | None = None, **checkpoints) -> Path:
    """Simulate ``scene`` and write the run dataset to ``out`` (``craquelure run``), with
    checkpoints next to it (``resume=True`` continues from the last one;
    ``checkpoint_every``, ``checkpoint_minutes``: the options of
    :func:`craquelure.runner.run_to_file`). ``init`` is an initial state (a file or a
    dataset of :func:`initial_state`); without it the run builds its own from ``seed``.

    Example:

        >>> short = {"outputs.t_end": 0.4, "outputs.times": [0.2, 0.4]}
        >>> craquelure.run_to_file(craquelure.load_scene("drying/ci", short), "run.nc", seed=1)
        PosixPath('run.nc')
    """
    import numba

    scene = load_scene(scene)
    warn_if_long(scene, numba.get_num_threads())
    with ExitStack() as stack:
        if isinstance(init, xr.Dataset):
            init = write_dataset(init, _temporary(stack, "init.nc"))
        return stage(scene.model, "run")(scene, Path(out), seed=seed,
                                         init=Path(init) if init is not None else None,
                                         **checkpoints)


def run(scene: Scene | str, seed: int = 0, init: RunInput | None = None,
        out: str | Path | None = None, **checkpoints) -> xr.Dataset:
    """Simulate ``scene`` and return the run dataset, the one ``craquelure run`` writes
    (every variable with its units and long name, the provenance in the attributes). With
    ``out`` the dataset is written there, with checkpoints and ``resume`` as
    :func:`run_to_file`; without it the run goes through a temporary folder.

    Example:

        >>> short = {"outputs.t_end": 0.4, "outputs.times": [0.2, 0.4]}
        >>> ds = craquelure.run(craquelure.load_scene("drying/ci", short), seed=1)
        >>> sorted(ds.data_vars)[:3]
        ['alive', 'elastic_energy', 'kappa_criterion_max']
    """
    with ExitStack() as stack:
        out = _temporary(stack, "run.nc") if out is None else out
        return open_dataset(run_to_file(scene, out, seed, init, **checkpoints))


def _temporary(stack: ExitStack, name: str) -> Path:
    return Path(stack.enter_context(tempfile.TemporaryDirectory())) / name


def _run_path(run: RunInput, stack: ExitStack) -> Path:
    """A run dataset's file: the path given, or the dataset written to a temporary folder."""
    return write_dataset(run, _temporary(stack, "run.nc")) if isinstance(run, xr.Dataset) \
        else Path(run)


def fragments(run: RunInput, out: str | Path | None = None, phi0: float | None = None,
              spacing: float | None = None) -> xr.Dataset:
    """The fragments of a run (``craquelure fragments``). Drying: every snapshot binarised
    (paste where the Shepard field exceeds ``phi0``, on a mesh of ``spacing`` h; default the
    scene's ``outputs.binarisation_*``) and its fragment areas; lattice: the fragment label of
    every body particle at the last frame. Other models have no fragments: a
    :class:`~craquelure.errors.CraquelureError` says so. With ``out`` the dataset is also
    written there.

    Example:

        >>> frag = craquelure.fragments("run.nc")   # the run of run_to_file's example
        >>> frag["n_fragments"].dims, int(frag["n_fragments"][-1])
        (('time',), 1)
    """
    ds = run if isinstance(run, xr.Dataset) else open_dataset(run)
    model = str(ds.attrs.get("model", "drying"))  # drying's datasets before the attribute
    if model == "lattice":
        labels = model_module("lattice", "analysis").fragment_labels(ds)
        frag = xr.Dataset({"fragment_label": ("particle", labels, {
            "long_name": "fragment of the body particle at the last frame (0: not in one)",
            "units": "1"})}, attrs={"model": "lattice", "source_run": ds.attrs.get("scene_name",
                                                                                  "")})
        if out is not None:
            write_dataset(frag, out)
        return frag
    if model != "drying":
        where = "the run" if isinstance(run, xr.Dataset) else str(run)
        raise CraquelureError(f"{where}: a dataset of model {model!r}, which has "
                              "no fragments; allowed models: drying, lattice")
    with ExitStack() as stack:
        path = _run_path(run, stack)
        target = Path(out) if out is not None else _temporary(stack, "fragments.nc")
        analysis = model_module("drying", "analysis")
        return open_dataset(analysis.fragments_from_run_file(path, target, phi0, spacing))


def export(run: RunInput, to: str = "vtu", out: str | Path | None = None) -> list[Path]:
    """Write a run for ParaView and OVITO (``craquelure export``): ``to="vtu"`` a ``.pvd``
    series of VTU point clouds and an extended-XYZ trajectory, ``to="xyz"`` the latter only.
    ``out`` is the base path (default: the run's file without ``.nc``; needed for a dataset).
    Returns the files written.

    Example:

        >>> craquelure.export("run.nc", to="xyz")   # the run of run_to_file's example
        [PosixPath('run.xyz')]
    """
    from craquelure.export_formats import FORMATS
    from craquelure.export_formats import export as write

    if to not in FORMATS:
        raise CraquelureError(f"--to {to!r}: allowed values are {', '.join(FORMATS)}")
    if isinstance(run, xr.Dataset) and out is None:
        raise CraquelureError("export: out is required for a dataset (the base path of the "
                              "files to write)")
    with ExitStack() as stack:
        return write(_run_path(run, stack), to, out)
