r"""The archived result of a drying ensemble (``results/published/<name>/``): compact tables that
hold everything the campaign, the summary, the figures and the validation rows are made from,
so they are rebuilt from the repository without re-running a simulation.

Tables (CSV, floats written with 17 significant digits, so reading them back gives the same
doubles) under ``tables/``:

- ``seed<N>_fragments.csv``: ``time, labelling, area``, one row per fragment of each snapshot of
  sample N, for the periodic labelling (on the torus) and the open image (no wrap-around);
- ``seed<N>_snapshots.csv``: one row per snapshot with the fragment counts of both labellings
  and the crack measures (:data:`SNAPSHOT_COLUMNS`);
- ``seeds.csv``: one row per sample with its onset numbers and the provenance of its run
  (:data:`SEED_COLUMNS`);
- ``common.json``: what every sample shares (the resolved scene, the binarisation); a sample
  that differs is refused.

:func:`read_tables` turns the tables back into fragment datasets of
:func:`craquelure.drying.analysis.analyse_run`'s layout (the variables the campaign reads)."""

from __future__ import annotations

import csv
import io
import json
import shutil
from collections.abc import Sequence
from pathlib import Path

import numpy as np
import xarray as xr

from craquelure.archive import MANIFEST, SNAKEMAKE_MARKER, manifest_text, sha256_file
from craquelure.errors import CraquelureError
from craquelure.io import write_text_atomic

LABELLING_VARIABLES = {"periodic": ("fragment_area", "fragment_time_index"),
                       "open": ("fragment_area_open", "fragment_time_index_open")}
SNAPSHOT_COLUMNS = ("n_fragments", "n_fragments_open", "mean_area", "paste_fraction", "n_alive",
                    "damage", "crack_length_per_area", "largest_fragment_fraction")
INTEGER_COLUMNS = {"n_fragments", "n_fragments_open", "n_alive", "seed"}
SEED_COLUMNS = ("seed", "first_removal_time", "kappa_max", "kappa_criterion", "kappa_records",
                "predicted_first_removal_time", "run_git_commit", "run_wall_time_s",
                "wall_time_s")
COMMON_ATTRS = ("h", "box_length", "n_particles", "phi0", "mesh_spacing_h", "mesh_spacing",
                "mesh_points_per_side", "edge_depth", "connectivity", "fracture_stress_measure",
                "scene", "scene_name", "effects")


def _number(value) -> str:
    """A table cell: a string as it is, a number with 17 significant digits (or nan)."""
    if isinstance(value, str):
        return value
    value = float(value)
    return "nan" if not np.isfinite(value) else format(value, ".17g")


def _csv(header: Sequence[str], rows) -> str:
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(header)
    writer.writerows(rows)
    return out.getvalue()


def write_tables(fragments: Sequence[xr.Dataset], folder: str | Path) -> list[Path]:
    """The tables of the fragment datasets ``fragments`` (one per sample) in
    ``folder/tables/``; returns the files written."""
    tables = Path(folder) / "tables"
    tables.mkdir(parents=True, exist_ok=True)
    if not fragments:
        raise CraquelureError("published tables: no fragment datasets given")
    common = {key: fragments[0].attrs.get(key) for key in COMMON_ATTRS}
    written, seed_rows = [], []
    for ds in sorted(fragments, key=lambda d: int(d.attrs["seed"])):
        seed = int(ds.attrs["seed"])
        for key, value in common.items():
            if ds.attrs.get(key) != value:
                raise CraquelureError(f"published tables: seed {seed} differs in `{key}` from "
                                      "the first sample; publish one scene at a time")
        times = ds["time"].values
        rows = [(_number(times[k]), labelling, _number(a))
                for labelling, (area, index) in LABELLING_VARIABLES.items()
                for a, k in zip(ds[area].values, ds[index].values, strict=True)]
        written.append(write_text_atomic(tables / f"seed{seed}_fragments.csv",
                                         _csv(("time", "labelling", "area"), rows)))
        rows = [(_number(t), *(_number(ds[c].values[k]) for c in SNAPSHOT_COLUMNS))
                for k, t in enumerate(times)]
        written.append(write_text_atomic(tables / f"seed{seed}_snapshots.csv",
                                         _csv(("time", *SNAPSHOT_COLUMNS), rows)))
        seed_rows.append([_number(ds.attrs.get(c, "")) for c in SEED_COLUMNS])
    written.append(write_text_atomic(tables / "seeds.csv", _csv(SEED_COLUMNS, seed_rows)))
    common = {k: (v.item() if isinstance(v, np.generic) else v) for k, v in common.items()}
    written.append(write_text_atomic(tables / "common.json",
                                     json.dumps(common, indent=1, sort_keys=True) + "\n"))
    return written


def _read_csv(path: Path) -> dict[str, list[str]]:
    if not path.is_file():
        raise CraquelureError(f"published tables: {path} is missing")
    with open(path, newline="") as fh:
        rows = list(csv.reader(fh))
    return {name: [row[i] for row in rows[1:]] for i, name in enumerate(rows[0])}


def _column(values: list[str], name: str) -> np.ndarray:
    return np.array(values, dtype=np.int64 if name in INTEGER_COLUMNS else float)


def read_tables(folder: str | Path) -> list[xr.Dataset]:
    """The fragment datasets (one per sample, in seed order) of the tables in folder/tables/."""
    tables = Path(folder) / "tables"
    common_path = tables / "common.json"
    if not common_path.is_file():
        raise CraquelureError(f"published tables: {common_path} is missing")
    common = json.loads(common_path.read_text())
    seeds = _read_csv(tables / "seeds.csv")
    out = []
    for k, seed in enumerate(seeds["seed"]):
        snaps = _read_csv(tables / f"seed{int(float(seed))}_snapshots.csv")
        times = _column(snaps["time"], "time")
        frags = _read_csv(tables / f"seed{int(float(seed))}_fragments.csv")
        f_time = _column(frags["time"], "time")
        labelling = np.array(frags["labelling"])
        data = {c: ("time", _column(snaps[c], c)) for c in SNAPSHOT_COLUMNS}
        for name, (area, index) in LABELLING_VARIABLES.items():
            sel = labelling == name
            dim = "fragment" if name == "periodic" else "fragment_open"
            data[area] = (dim, _column(np.array(frags["area"])[sel].tolist(), "area"))
            data[index] = (dim, np.searchsorted(times, f_time[sel]).astype(np.int64))
        ds = xr.Dataset(data, coords={"time": ("time", times)})
        ds.attrs.update(common)
        for c in SEED_COLUMNS:
            value = seeds[c][k]
            ds.attrs[c] = (value if c == "run_git_commit"
                           else int(float(value)) if c in INTEGER_COLUMNS | {"kappa_records"}
                           else float(value))
        out.append(ds)
    return out


# What the rebuild adds beside the tables (rule drying_published's outputs, copied on publish).
REBUILT = ("summary.json", "validation.json", "validation.html", "figures")


def _merged_seeds(old: Path, new: Path) -> str:
    """seeds.csv rows of both files, one per seed (the new row wins), in seed order."""
    rows = {}
    for path in (old, new):
        if path.is_file():
            with open(path, newline="") as fh:
                rows.update({int(float(r["seed"])): r for r in csv.DictReader(fh)})
    return _csv(SEED_COLUMNS, ([r[c] for c in SEED_COLUMNS] for _, r in sorted(rows.items())))


def _merged_provenance(old: dict, new: dict) -> dict:
    """Provenance of an ensemble grown by ``new``: seeds and commits joined, costs per job."""
    out = {**old, **new}
    for key in ("seeds", "run_git_commits"):
        out[key] = sorted(set(old.get(key, [])) | set(new.get(key, [])))
    out["cpu_seconds"] = {kind: {**old.get("cpu_seconds", {}).get(kind, {}), **jobs}
                          for kind, jobs in new.get("cpu_seconds", {}).items()}
    out["cpu_hours_total"] = sum(sum(c.values()) for c in out["cpu_seconds"].values()) / 3600
    if "snapshot_run" in old:  # Fig. 2 keeps the sample it was first drawn from
        out["snapshot_run"] = old["snapshot_run"]
    return out


def publish(tables_dir: str | Path, rebuilt_dir: str | Path | None, dest: str | Path) -> Path:
    """Install an ensemble's archived result in ``dest``, or grow the one there: the tables,
    snapshots and provenance of ``tables_dir`` (rule drying_publish_tables; seeds already in
    ``dest`` stay, a seed in both is replaced, Fig. 2's snapshots stay those first installed),
    the summary, validation rows and figures rebuilt from the whole (rule drying_published;
    None: not yet, the tables alone), and the SHA-256 manifest that ``craquelure verify dest``
    checks. Every file is written to a temporary name first."""
    tables_dir, dest = Path(tables_dir), Path(dest)
    common = tables_dir / "tables" / "common.json"
    if (dest / "tables" / "common.json").is_file() and common.is_file() and json.loads(
            common.read_text()) != json.loads((dest / "tables" / "common.json").read_text()):
        raise CraquelureError(f"publish: {tables_dir} is another scene or binarisation than "
                              f"the ensemble in {dest}; publish it under another name")
    texts = {"tables/seeds.csv": _merged_seeds(dest / "tables" / "seeds.csv",
                                               tables_dir / "tables" / "seeds.csv")}
    if (dest / "provenance.json").is_file():
        texts["provenance.json"] = json.dumps(_merged_provenance(
            json.loads((dest / "provenance.json").read_text()),
            json.loads((tables_dir / "provenance.json").read_text())), indent=1) + "\n"
    keep = {"snapshots.nc"} if (dest / "snapshots.nc").is_file() else set()
    sources = [p for p in sorted(tables_dir.rglob("*")) if p.is_file()
               and p.name != SNAKEMAKE_MARKER
               and p.relative_to(tables_dir).as_posix() not in keep | set(texts)]
    for name in REBUILT if rebuilt_dir is not None else ():
        path = Path(rebuilt_dir) / name
        if not path.exists():
            raise CraquelureError(f"publish: {path} is missing (run the rebuild first)")
        # PNG figures and the series they plot: the PDFs would multiply the folder's size
        sources += (sorted(p for p in path.rglob("*") if p.suffix in (".png", ".json"))
                    if path.is_dir() else [path])
    for src in sources:
        base = tables_dir if src.is_relative_to(tables_dir) else Path(rebuilt_dir)
        target = dest / src.relative_to(base)
        target.parent.mkdir(parents=True, exist_ok=True)
        tmp = target.with_name(target.name + ".tmp")
        shutil.copyfile(src, tmp)
        tmp.replace(target)
    for name, text in texts.items():
        write_text_atomic(dest / name, text)
    # every file of the folder (a README written by hand too), as `craquelure verify` expects
    digests = {p.relative_to(dest).as_posix(): sha256_file(p) for p in sorted(dest.rglob("*"))
               if p.is_file() and p.name != MANIFEST}
    write_text_atomic(dest / MANIFEST, manifest_text(digests))
    return dest
