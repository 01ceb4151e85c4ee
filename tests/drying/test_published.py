"""The archived tables of a drying ensemble (craquelure.drying.published): written from the
fragment datasets and read back, they give the same campaign, in both labellings."""

from __future__ import annotations

import json

import numpy as np
import pytest

from craquelure.archive import verify
from craquelure.drying.analysis import analyse_run
from craquelure.drying.campaign import LABELLINGS, build_campaign
from craquelure.drying.published import publish, read_tables, write_tables
from craquelure.errors import CraquelureError

from .synthetic_run import lattice_run

BANDS = {
    1: ((), (("y", 0.5, 0.7),), (("y", 0.5, 0.7), ("x", 1.0, 1.2))),
    2: ((("x", 0.3, 0.5),), (("x", 0.3, 0.5), ("y", 1.1, 1.3)),
        (("x", 0.3, 0.5), ("y", 1.1, 1.3), ("x", 1.4, 1.6))),
}


@pytest.fixture(scope="module")
def fragments():
    out = []
    for seed, bands in BANDS.items():
        ds = analyse_run(lattice_run(40, 2.0, bands_per_time=bands, seed=seed), progress=False)
        ds.attrs.update(seed=seed, scene=lattice_run(40, 2.0).attrs["scene"],
                        scene_name="drying/ci", effects="elasticity,fracture",
                        run_git_commit="abc123", run_wall_time_s=12.5, wall_time_s=0.25)
        out.append(ds)
    return out


def test_tables_read_back_as_the_same_campaign(tmp_path, fragments):
    write_tables(fragments, tmp_path)
    back = read_tables(tmp_path)
    assert [int(ds.attrs["seed"]) for ds in back] == [1, 2]
    for labelling in LABELLINGS:
        a = build_campaign(fragments, n_bins=8, window_mode="all_broken", labelling=labelling)
        b = build_campaign(back, n_bins=8, window_mode="all_broken", labelling=labelling)
        # not vacuous: both labellings have fragments, and they differ (the box edges cut)
        assert a["fragment_area"].size > 2
        for name, var in a.data_vars.items():
            np.testing.assert_array_equal(var.values, b[name].values, err_msg=name)
        assert ({k: repr(v) for k, v in a.attrs.items()}
                == {k: repr(v) for k, v in b.attrs.items()})
    periodic, open_image = (build_campaign(fragments, 8, "all_broken", name)
                            for name in LABELLINGS)
    assert open_image["n_fragments"].values.sum() > periodic["n_fragments"].values.sum()
    for ds, original in zip(back, fragments, strict=True):
        for name in ("first_removal_time", "run_git_commit", "run_wall_time_s", "h", "scene"):
            assert ds.attrs[name] == original.attrs[name] or (
                np.isnan(ds.attrs[name]) and np.isnan(original.attrs[name]))


def test_a_sample_of_another_scene_is_refused(tmp_path, fragments):
    other = fragments[1].copy()
    other.attrs = {**other.attrs, "phi0": 0.7}
    with pytest.raises(CraquelureError, match="seed 2 differs in `phi0`"):
        write_tables([fragments[0], other], tmp_path)


def test_missing_table_is_named(tmp_path, fragments):
    write_tables(fragments, tmp_path)
    (tmp_path / "tables" / "seed2_fragments.csv").unlink()
    with pytest.raises(CraquelureError, match="seed2_fragments.csv is missing"):
        read_tables(tmp_path)


def test_tables_are_plain_text_rows(tmp_path, fragments):
    write_tables(fragments, tmp_path)
    lines = (tmp_path / "tables" / "seed1_fragments.csv").read_text().splitlines()
    assert lines[0] == "time,labelling,area"
    assert {line.split(",")[1] for line in lines[1:]} == {"periodic", "open"}


def _tables(tmp_path, name, datasets, snapshot_seed):
    folder = tmp_path / name
    write_tables(datasets, folder)
    (folder / "snapshots.nc").write_bytes(f"seed {snapshot_seed}".encode())
    seeds = [int(d.attrs["seed"]) for d in datasets]
    (folder / "provenance.json").write_text(json.dumps({
        "seeds": seeds, "run_git_commits": [f"c{seeds[0]}"], "snapshot_run": {"seed": seeds[0]},
        "cpu_seconds": {"drying_run": {f"seed{s}": 100.0 * s for s in seeds}}}))
    return folder


def test_a_campaign_grows_its_archive_across_sessions(tmp_path, fragments):
    """Seeds published in one session stay when the next publishes the rest: the tables read
    back as the whole ensemble, costs and commits add up, Fig. 2 keeps its first sample."""
    dest = tmp_path / "published" / "ensemble"
    publish(_tables(tmp_path, "first", fragments[:1], 1), None, dest)
    publish(_tables(tmp_path, "second", fragments[1:], 2), None, dest)
    assert [int(d.attrs["seed"]) for d in read_tables(dest)] == [1, 2]
    provenance = json.loads((dest / "provenance.json").read_text())
    assert provenance["seeds"] == [1, 2] and provenance["run_git_commits"] == ["c1", "c2"]
    assert provenance["cpu_hours_total"] == pytest.approx(300.0 / 3600)
    assert (dest / "snapshots.nc").read_bytes() == b"seed 1"
    assert verify(dest) == ([], len([p for p in dest.rglob("*") if p.is_file()]) - 1)
    other = fragments[1].copy()
    other.attrs = {**other.attrs, "phi0": 0.7, "seed": 3}
    with pytest.raises(CraquelureError, match="another scene or binarisation"):
        publish(_tables(tmp_path, "third", [other], 3), None, dest)


def test_an_archive_is_refreshed_from_its_own_tables(tmp_path, fragments):
    """`make republish` (publish a folder onto itself with a new rebuild, e.g. once a companion
    it names is archived): tables and snapshots stay byte for byte, the provenance keeps every
    entry, the rebuilt files and the comparison's series are installed, the manifest checks."""
    dest = tmp_path / "published" / "ensemble"
    publish(_tables(tmp_path, "first", fragments, 1), None, dest)
    kept = {p: p.read_bytes() for p in dest.rglob("*")
            if p.is_file() and p.name not in ("MANIFEST.sha256", "provenance.json")}
    provenance = json.loads((dest / "provenance.json").read_text())
    rebuilt = tmp_path / "rebuilt"
    (rebuilt / "figures").mkdir(parents=True)
    for name in ("summary.json", "validation.json", "validation.html"):
        (rebuilt / name).write_text(name)
    for name in ("drying_companions.json", "drying_companions_x.png", "drying_x.pdf"):
        (rebuilt / "figures" / name).write_text(name)
    publish(dest, rebuilt, dest)
    assert all(path.read_bytes() == data for path, data in kept.items())
    assert json.loads((dest / "provenance.json").read_text()).items() >= provenance.items()
    assert sorted(p.name for p in (dest / "figures").iterdir()) == [
        "drying_companions.json", "drying_companions_x.png"]  # no PDF
    assert (dest / "validation.json").read_text() == "validation.json"
    assert verify(dest) == ([], len([p for p in dest.rglob("*") if p.is_file()]) - 1)
