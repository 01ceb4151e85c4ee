"""CF-1.11 metadata (craquelure.cf, applied by io.write_dataset): global attributes, units that
UDUNITS parses (cf_units), reduced units as "1" with the scale named, the writer's own
attributes kept, history appended on each write. The workflow's real datasets are checked in
tests/workflow/test_snakemake.py (every variable of every CI dataset, and compliance-checker
on one dataset per model)."""

from __future__ import annotations

import re

import cf_units
import netCDF4
import numpy as np
import pytest
import xarray as xr

from craquelure import cf
from craquelure.io import open_dataset, write_dataset
from craquelure.models import MODELS, model_module

SOFTDYN, IMPACT = (model_module(m, "metadata").METADATA for m in ("softdyn", "impact"))


def parses(units: str) -> bool:
    try:
        cf_units.Unit(units)
    except ValueError:
        return False
    return True


@pytest.mark.parametrize("model", MODELS)
def test_every_table_unit_becomes_udunits(model):
    meta = model_module(model, "metadata").METADATA
    assert meta.title and meta.references
    for name, (long_name, units) in meta.variables.items():
        assert long_name, name
        if units is None:
            continue
        udunits, reduced = cf._units(meta, units)
        assert parses(udunits), (name, units, udunits)
        if meta.reduced_unit_system is None:
            assert reduced is None
        elif udunits == "1" and units != "1":
            assert reduced == units  # the scale is named, never dropped


def test_reduced_model_scale_names_are_not_read_as_si():
    # "R" (sphere radius) parses in UDUNITS as roentgen and "tau" does not parse at all:
    # reduced units must never be passed through as if they were SI.
    assert parses("R") and cf_units.Unit("R") != cf_units.Unit("m")
    assert cf._units(SOFTDYN, "R") == ("1", "R")
    assert cf._units(SOFTDYN, "tau") == ("1", "tau")
    assert cf._units(SOFTDYN, "s") == ("s", None)  # wall time stays SI
    assert cf._units(SOFTDYN, "deg") == ("degree", None)
    assert cf._units(IMPACT, "N/m") == ("N m-1", None)


def run_like(model: str) -> xr.Dataset:
    n = 5
    return xr.Dataset(
        {"x": (("time", "particle"), np.ones((2, n)), {"units": "length",
                                                      "long_name": "position x (writer)"}),
         "mass": (("particle",), np.ones(n))},
        coords={"time": [0.0, 1.0]},
        attrs={"model": model, "scene_name": "ci", "seed": 3},
    )


def test_write_adds_global_attributes_and_history(tmp_path):
    argv = ["/x/src/craquelure/__main__.py", "run", "drying/ci", "--out", "a b.nc"]
    ds = cf.apply(run_like("drying"), argv)
    assert ds.attrs["Conventions"] == "CF-1.11"
    assert ds.attrs["title"].startswith("Drying paste") and "scene ci, seed 3" in ds.attrs["title"]
    assert ds.attrs["source"].startswith("craquelure ") and "drying model" in ds.attrs["source"]
    assert "arXiv:1209.6114" in ds.attrs["references"]
    assert "eta/lambda" in ds.attrs["reduced_unit_system"]
    assert re.fullmatch(r"\d{4}-\d\d-\d\dT\d\d:\d\d:\d\dZ craquelure run drying/ci --out 'a b.nc'",
                        ds.attrs["history"])
    # The writer's long name wins; reduced units become "1" with the scale kept.
    assert ds["x"].attrs == {"units": "1", "reduced_units": "length",
                             "long_name": "position x (writer)"}
    # Bare variables are filled from the model's table.
    assert ds["time"].attrs == {"long_name": "snapshot time", "units": "1",
                                "reduced_units": "eta/lambda"}

    # On disk, and again after a second write: history grows by one line, the rest is stable.
    path = write_dataset(run_like("drying"), tmp_path / "run.nc")
    first = open_dataset(path)
    write_dataset(first, tmp_path / "again.nc")
    second = open_dataset(tmp_path / "again.nc")
    assert len(second.attrs["history"].splitlines()) == 2
    assert second.attrs["history"].startswith(first.attrs["history"] + "\n")
    for name in ("x", "time"):
        assert second[name].attrs == first[name].attrs
    for var in second.variables.values():
        assert parses(var.attrs["units"]) and var.attrs["long_name"]


def test_si_model_keeps_its_units_and_coordinates_have_no_fill_value(tmp_path):
    ds = run_like("impact")
    ds["x"].attrs = {}
    path = write_dataset(ds, tmp_path / "impact.nc")
    with xr.open_dataset(path, decode_times=False) as back:
        assert back["x"].attrs["units"] == "m" and "reduced_units" not in back["x"].attrs
        assert back["mass"].attrs["units"] == "kg m-1"
        assert back["time"].attrs["units"] == "s"
        assert "reduced_unit_system" not in back.attrs
    with netCDF4.Dataset(path) as nc:  # CF 2.5.1: coordinate variables carry no _FillValue
        assert "_FillValue" not in nc["time"].ncattrs()
        assert "_FillValue" in nc["mass"].ncattrs()  # data variables keep it


def test_dataset_without_model_gets_global_attributes_only():
    ds = cf.apply(xr.Dataset({"a": ("i", [1.0])}), ["tool"])
    assert ds.attrs["Conventions"] == "CF-1.11" and ds.attrs["history"].endswith(" tool")
    assert ds["a"].attrs == {}


def test_drying_speed_study_is_cf():
    """The drying-speed study is off in the CI config, so the end-to-end check never sees it:
    its dataset (synthetic campaigns) gets a long name and parsable units on every variable."""
    from craquelure.drying.speed import speed_study
    from tests.drying.test_speed import speed_campaign

    groups = {pi: speed_campaign(pi, onset) for pi, onset in ((0.01, 0.5), (0.05, 0.3))}
    ds = speed_study(groups, fixed_over_t_star=[1.5, 2.0], n_boot=50)
    ds.attrs["model"] = "drying"
    cf.apply(ds, ["test"])
    for name, var in ds.variables.items():
        assert var.attrs.get("long_name"), name
        assert parses(var.attrs["units"]), (name, var.attrs.get("units"))


# One small scene per model and arrangement (CI sizes): the initial states `craquelure init`
# writes. The CI workflow writes only some of them (drying's masses); the end-to-end check
# (tests/workflow/test_snakemake.py) covers every dataset the workflow writes.
INITIAL_STATES = [("drying/ci", []), ("impact/ci", []), ("impact/ci3d", []),
                  ("lattice/gravity_block", ["domain.nx=16", "domain.ny=6"]),
                  ("softdyn/t1_single_ci", []), ("softdyn/two_sphere_separation", [])]


@pytest.mark.parametrize(("scene", "overrides"), INITIAL_STATES,
                         ids=[s for s, _ in INITIAL_STATES])
def test_initial_states_describe_every_variable(scene, overrides, tmp_path):
    """Every variable of an initial state has a long name; every numeric one units that UDUNITS
    parses (softdyn's pair_i / pair_j included: indices along particle, units "1")."""
    from craquelure import cli

    args = [a for o in overrides for a in ("--set", o)]
    assert cli.main(["init", scene, *args, "--seed", "1", "--out", str(tmp_path / "s.nc")]) == 0
    with xr.open_dataset(tmp_path / "s.nc", decode_times=False) as ds:
        assert ds.variables
        for name, var in ds.variables.items():
            assert var.attrs.get("long_name"), (scene, name)
            if var.dtype.kind in "fiub":
                assert parses(var.attrs.get("units", "")), (scene, name, var.attrs)
