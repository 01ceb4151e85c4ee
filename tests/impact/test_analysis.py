"""Impact analysis (craquelure.impact.analysis): per-run metrics are computed from a run
dataset's state, series and stored scene, never read back from the run; older datasets (with
the ``metric_*`` attributes runs used to write, or a scene key renamed since) stay analysable."""

import numpy as np
import pytest

from craquelure.impact import analysis
from craquelure.impact.api import run
from craquelure.io import open_dataset
from craquelure.scene import load_scene

CI = ["outputs.t_end=6.0e-5", "outputs.snapshot_times=[]", "particles.precrack=pf1"]


@pytest.fixture(scope="module")
def run_path(tmp_path_factory):
    scene = load_scene("impact/ci", CI)
    return run(scene, tmp_path_factory.mktemp("analysis") / "run.nc", seed=0)


def _equal(a: dict, b: dict) -> None:
    assert a.keys() == b.keys()
    for key, value in a.items():
        assert b[key] == value, key


def test_metrics_come_from_state_series_and_scene(run_path):
    ds = open_dataset(run_path)
    m = analysis.run_metrics(ds)
    assert m["kappa"] == 1.0 and m["precrack_layout"] == "pf1" and m["dim"] == 2
    assert m["distribution"] == "homogeneous"
    # from the series and fields, not from attributes
    assert m["energy_balance_error_max"] == float(np.abs(ds["series_balance_error"]).max())
    assert m["min_y_final"] == float(ds["y"].min())
    assert m["n_zero_mass"] == int((ds["mass"] == 0).sum()) > 0  # the pre-crack line
    assert m["contact_force_peak"] == float(ds["series_contact_force"].max())
    assert m["cracked_fraction"] == float(np.mean(ds["softening"].values >= 0.9))
    assert m["steps"] == ds.attrs["run_steps"] and m["as_epsilon"] == ds.attrs["as_epsilon"]


def test_old_dataset_with_stale_metric_attributes_is_recomputed(run_path):
    """A dataset as runs wrote them before the move: resolved numbers as metric_<name>, the
    analysis's metrics as attributes too (here deliberately stale). The metrics are recomputed
    from the state; only the resolved numbers are read from metric_<name>."""
    ds = open_dataset(run_path)
    today = analysis.run_metrics(ds)
    old = ds.copy()
    for name, key in analysis.RUN_FACTS.items():
        old.attrs[f"metric_{name}"] = old.attrs.pop(key)
    old.attrs.update(metric_cracked_fraction=0.99, metric_n_main_cracks=7,
                     metric_energy_balance_error_max=0.5)
    _equal(today, analysis.run_metrics(old))


def test_scene_key_renamed_since_does_not_stop_the_analysis(run_path):
    """The stored scene is read as written: a key today's schema no longer knows (as if renamed
    since the run) is no error."""
    ds = open_dataset(run_path)
    today = analysis.run_metrics(ds)
    old = ds.copy()
    old.attrs["scene"] = ds.attrs["scene"].replace("numerics:\n", "numerics:\n  old_key: 1\n", 1)
    assert "old_key" in old.attrs["scene"]
    _equal(today, analysis.run_metrics(old))


def test_summary_groups_by_dimension(run_path, tmp_path):
    summary = analysis.summarise([run_path], "test", "ci", "uniform")
    assert summary["dimensions"] == ["2D"]
    assert "homogeneous/pf1/kappa1" in summary["cases"]
    assert {f["dim"] for f in summary["findings"]} <= {"2D"}


def _synthetic(dim, masses, kappa, seed, n_main, phi):
    """A run's metrics as read_metrics returns them (the 3D engine lands on another branch)."""
    m = {q: None for q in analysis.PER_RUN}
    m.update(dim=dim, distribution=masses, precrack_layout="none", kappa=kappa, seed=seed,
             n_main_cracks=n_main, n_main_cracks_revised=n_main, cracked_fraction=phi,
             n_secondary_cracks=1, spacing=0.004, energy_balance_error_max=0.001,
             wall_time_s=10.0 * dim, material_model="cap", main_crack_x_mid=0.0,
             main_crack_theta_deg=0.0, crushed_area=1e-4, main_crack_length_revised=0.15,
             second_crack_length=0.0, n_main_cracks_opening=n_main,
             n_secondary_cracks_opening=1, main_run_x_mid=0.0, main_run_share=0.9,
             main_run_opening=1e-3, main_run_opening_growth=1.0,
             main_crack_theta_opening_deg=0.0, main_crack_length_opening=0.15,
             second_crack_length_opening=0.0)
    return m


def test_summary_gives_3d_and_2d_verdicts_separately(monkeypatch):
    """3D runs with 8 seeds per heterogeneous case (two or more main cracks in every one), 2D
    runs with 3: the 3D finding is decided, the 2D one inconclusive; every seed's metrics are in
    summary.json for both, 2D cases keep their keys, 3D ones are prefixed."""
    runs = {}
    for dim, n in ((3, 8), (2, 3)):
        runs[f"{dim}/homogeneous/0"] = _synthetic(dim, "homogeneous", 1.0, 0, 1, 0.05)
        for s in range(1, n + 1):
            runs[f"{dim}/uniform/{s}"] = _synthetic(dim, "uniform", 1.0, s, 3, 0.3 + 0.01 * s)
    monkeypatch.setattr(analysis, "read_metrics", lambda p: dict(runs[str(p)]))
    summary = analysis.summarise(list(runs), "test", "default", "uniform")
    assert summary["dimensions"] == ["3D", "2D"]
    assert summary["n_seeds_heterogeneous_by_dim"] == {"3D": 8, "2D": 3}
    assert summary["cases"]["3D/uniform/none/kappa1"]["seeds"] == list(range(1, 9))
    assert summary["cases"]["uniform/none/kappa1"]["dim"] == "2D"
    het = {f["dim"]: f for f in summary["findings"]
           if f["finding"].startswith("heterogeneous kappa = 1")}
    assert het["3D"]["status"] == "reproduced" and het["2D"]["status"] == "inconclusive"
    assert set(het["3D"]["per_seed"]) == {str(s) for s in range(1, 9)}
    assert set(summary["reported_without_verdict"]) == {"3D", "2D"}
    assert summary["run_wall_time_s_by_dim"] == {"3D": 270.0, "2D": 80.0}
