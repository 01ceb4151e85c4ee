"""CF-1.11 metadata for every dataset, applied in one place (:func:`craquelure.io.write_dataset`
calls :func:`apply`), so a model's writer only says what its variables are (docs/outputs.md).

A model in reduced units (drying, lattice, softdyn) writes its quantities as multiples of its
own scales: they get ``units = "1"`` and the scale in ``reduced_units``; wall times, angles and
true ratios keep their units. Impact is in SI per unit thickness (2D); a 3D impact dataset
(attribute ``dim`` = 3) takes the whole-body units (:func:`per_body`). A writer's own
``long_name``/``units`` win over the model's table (``<model>/metadata.py``).
"""

import shlex
import sys
from dataclasses import dataclass, field
from datetime import UTC, datetime
from pathlib import Path

import xarray as xr

import craquelure
from craquelure.models import MODELS, model_module

CONVENTIONS = "CF-1.11"
# Units kept as they are in reduced-unit models: they are physical (wall time, angles) or a
# true ratio.
PHYSICAL_UNITS = {"1", "s", "degree"}
UNIT_ALIASES = {"deg": "degree", "N/m": "N m-1"}


@dataclass(frozen=True)
class ModelMetadata:
    title: str
    references: str
    reduced_unit_system: str | None = None  # None: SI
    variables: dict[str, tuple[str, str | None]] = field(default_factory=dict)


# per unit thickness (2D) -> whole body (3D)
_BODY_UNITS = {"kg m-1": "kg", "J m-1": "J", "N m-1": "N", "kg s-1": "kg m s-1", "N s m-1": "N s"}


def per_body(variables: dict[str, tuple[str, str | None]]) -> dict[str, tuple[str, str | None]]:
    """A 2D per-thickness table as the 3D one: "per unit thickness" dropped from the long
    names, units multiplied by a length (kg m-1 -> kg, J m-1 -> J, N m-1 -> N, ...)."""
    return {name: (long_name.replace(" per unit thickness", ""),
                   _BODY_UNITS.get(units, units))
            for name, (long_name, units) in variables.items()}


def command_line(argv: list[str] | None = None) -> str:
    """The command that is writing, as a user would type it (``python -m craquelure ...``
    shows as ``craquelure ...``)."""
    argv = list(sys.argv if argv is None else argv)
    if not argv:
        return "python"
    first = Path(argv[0])
    if first.name == "__main__.py" and first.parent.name == "craquelure":
        argv[0] = "craquelure"
    return shlex.join(argv)


def history_line(argv: list[str] | None = None) -> str:
    stamp = datetime.now(UTC).isoformat(timespec="seconds").replace("+00:00", "Z")
    return f"{stamp} {command_line(argv)}"


def _units(model: ModelMetadata, units: str) -> tuple[str, str | None]:
    """(UDUNITS units, reduced scale or None) for a unit string as the model writes it."""
    units = UNIT_ALIASES.get(units, units)
    if model.reduced_unit_system is None or units in PHYSICAL_UNITS or units == "rad":
        return units, None
    return "1", units


def apply(ds: xr.Dataset, argv: list[str] | None = None) -> xr.Dataset:
    """Add the CF attributes to ``ds`` in place (see the module docstring) and return it.
    Datasets without a known ``model`` attribute get the global attributes only."""
    model = str(ds.attrs.get("model", ""))
    meta = model_module(model, "metadata").METADATA if model in MODELS else None
    attrs = ds.attrs
    attrs["Conventions"] = CONVENTIONS
    line = history_line(argv)
    attrs["history"] = f"{attrs['history']}\n{line}" if attrs.get("history") else line
    parts = [f"craquelure {craquelure.__version__}", f"{model} model" if meta else "",
             f"scene {attrs['scene_name']}" if attrs.get("scene_name") else ""]
    attrs["source"] = ", ".join(p for p in parts if p)
    if meta is None:
        attrs.setdefault("title", "craquelure dataset")
        return ds
    if not attrs.get("title"):
        what = f", scene {attrs['scene_name']}" if attrs.get("scene_name") else ""
        seed = f", seed {attrs['seed']}" if "seed" in attrs else ""
        attrs["title"] = f"{meta.title}{what}{seed}"
    attrs["references"] = meta.references
    if meta.reduced_unit_system:
        attrs["reduced_unit_system"] = meta.reduced_unit_system
    # 3D datasets of a per-thickness model: per_body names and units
    table = per_body(meta.variables) if attrs.get("dim") == 3 else meta.variables
    for name, var in ds.variables.items():
        long_name, units = table.get(str(name), (None, None))
        if long_name and not var.attrs.get("long_name"):
            var.attrs["long_name"] = long_name
        units = var.attrs.get("units", units)
        if var.dtype.kind not in "fiub" or units is None:
            continue  # labels: no units
        udunits, reduced = _units(meta, str(units))
        var.attrs["units"] = udunits
        if reduced is not None:
            var.attrs["reduced_units"] = reduced
    return ds
