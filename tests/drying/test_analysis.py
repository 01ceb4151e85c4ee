"""Stage 1 of the drying analysis (craquelure.drying.analysis; drying spec section 9): the
per-run fragment dataset and `craquelure fragments`; the workflow's plan of the three stages."""

import numpy as np
import pytest

from craquelure.cli import main as cli_main
from craquelure.drying.analysis import analyse_run
from craquelure.errors import SceneError
from craquelure.io import open_dataset, write_dataset
from craquelure.scene import load_scene_text

from .synthetic_run import lattice_run

# --- stage 1: fragments of one run ---------------------------------------------------------

BANDS = ((), [("y", 0.5, 0.8)], [("y", 1.4, 1.7)], [("x", 0.2, 0.5), ("x", 1.1, 1.4)])


@pytest.fixture(scope="module")
def run():
    return lattice_run(40, 2.0, bands_per_time=BANDS, times=[2.0, 4.0, 6.0, 8.0], seed=5)


def test_analyse_run_counts_fragments_over_time(run):
    ds = analyse_run(run, phi0=0.8, spacing_h=0.05, progress=False)
    assert ds["n_fragments"].values.tolist() == [1, 1, 2, 4]
    assert ds.sizes["fragment"] == 8
    # Ragged storage: fragment_time / fragment_time_index agree with the per-time counts.
    counts = np.bincount(ds["fragment_time_index"].values, minlength=4)
    assert counts.tolist() == ds["n_fragments"].values.tolist()
    assert np.all(ds["fragment_time"].values == ds["time"].values[ds["fragment_time_index"]])
    # Intact snapshot: one fragment = the whole box.
    assert ds["fragment_area"].values[0] == pytest.approx(4.0)
    for k in range(4):
        sel = ds["fragment_time_index"].values == k
        assert ds["mean_area"].values[k] == pytest.approx(ds["fragment_area"].values[sel].mean())
        # Paste area = sum of fragment areas.
        assert ds["paste_fraction"].values[k] * 4.0 == pytest.approx(
            ds["fragment_area"].values[sel].sum())
    assert ds.attrs["first_removal_time"] == pytest.approx(run["step_time"].values[
        np.argmax(run["n_removed"].values > 0)])
    assert ds.attrs["edge_depth"] == pytest.approx(0.199 * 0.2, abs=1e-4)


def test_defaults_come_from_the_scene(run):
    ds = analyse_run(run.isel(time=[0]), progress=False)
    assert ds.attrs["phi0"] == 0.8
    assert ds.attrs["mesh_spacing_h"] == 0.01  # schema default of outputs.binarisation_spacing
    assert ds.attrs["mesh_points_per_side"] == 1000


def test_fragments_command_writes_dataset_with_provenance(run, tmp_path):
    src = run.copy()
    src.attrs["git_commit"] = "abc123"
    write_dataset(src, tmp_path / "run.nc")
    out = tmp_path / "frag.nc"
    rc = cli_main(["fragments", str(tmp_path / "run.nc"), "--out", str(out), "--phi0", "0.8",
                   "--spacing", "0.05"])
    assert rc == 0
    ds = open_dataset(out)
    assert ds["n_fragments"].values.tolist() == [1, 1, 2, 4]
    assert ds.attrs["run_git_commit"] == "abc123"
    assert ds.attrs["seed"] == 5
    assert "drying" in ds.attrs["scene"] and "git_commit" in ds.attrs
    assert ds.attrs["effects"] == run.attrs["effects"]


def test_fragments_command_rejects_bad_input(tmp_path):
    assert cli_main(["fragments", str(tmp_path / "none.nc"), "--out", "x.nc"]) == 2
    bad = lattice_run(40, 2.0).drop_vars("alive")
    write_dataset(bad, tmp_path / "bad.nc")
    assert cli_main(["fragments", str(tmp_path / "bad.nc"), "--out",
                     str(tmp_path / "o.nc")]) == 2
    assert not (tmp_path / "o.nc").exists()


def test_archived_run_with_an_older_scene_key_stays_analysable(run):
    """A dataset's scene is read back as written: a key today's schema no longer knows (as
    after a rename) must not make the archived run unreadable, and the analysis is unchanged."""
    old = run.copy()
    old.attrs = {**run.attrs, "scene": run.attrs["scene"].replace(
        "material:\n", "material:\n  retired_key_from_an_older_schema: 1.0\n", 1)}
    with pytest.raises(SceneError, match="retired_key_from_an_older_schema"):
        load_scene_text(old.attrs["scene"])  # today's schema rejects it ...
    a = analyse_run(old, phi0=0.8, spacing_h=0.05, progress=False)  # ... the analysis does not
    b = analyse_run(run, phi0=0.8, spacing_h=0.05, progress=False)
    assert a["n_fragments"].values.tolist() == b["n_fragments"].values.tolist() == [1, 1, 2, 4]
    assert np.array_equal(a["fragment_area"].values, b["fragment_area"].values)



def test_paper_profile_plans_one_analysis_per_seed_and_one_campaign():
    """`snakemake -n --configfile config/paper.yaml`: 100 mass solves, 100 runs, 100 fragment
    analyses, one campaign aggregate, one summary, one figure job."""
    import re
    import subprocess
    import sys
    from pathlib import Path

    root = Path(__file__).resolve().parents[2]
    out = subprocess.run([sys.executable, "-m", "snakemake", "-n", "--configfile",
                          "config/paper.yaml"], cwd=root, capture_output=True, text=True,
                         timeout=300)
    assert out.returncode == 0, out.stderr[-2000:]
    counts = dict(re.findall(r"^(drying_\w+|mass_consistency)\s+(\d+)$", out.stdout,
                             re.MULTILINE))
    assert counts["mass_consistency"] == "100"
    assert counts["drying_run"] == "100"
    assert counts["drying_fragments"] == "100"
    assert counts["drying_campaign"] == "1"
    assert counts["drying_summary"] == "1"
    assert counts["drying_figures"] == "1"
