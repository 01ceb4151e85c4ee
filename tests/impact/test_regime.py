"""Regime map (craquelure.impact.regime, the regime helpers of craquelure.impact.workflow and
workflow/scripts/impact_regime.py) in 2D and 3D: run paths and overrides per dimension, the
classification of a 3D run on its mid-thickness layer, the figure and regime.json with both."""

import json
import runpy
import shlex
import sys
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
import yaml

from craquelure.impact import regime, workflow
from craquelure.impact.api import run
from craquelure.io import open_dataset
from craquelure.scene import load_scene, project_root

ROOT = project_root()


def section(profile: str) -> dict:
    """A profile's ``impact`` section merged over the default's, as Snakemake merges
    ``--configfile`` over config/config.yaml (nested dictionaries key by key)."""
    def merge(base, over):
        if not isinstance(base, dict) or not isinstance(over, dict):
            return over
        return {k: merge(base[k], over[k]) if k in base and k in over else over.get(k, base.get(k))
                for k in {**base, **over}}
    default = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())["impact"]
    if profile == "config":
        return default
    other = yaml.safe_load((ROOT / "config" / f"{profile}.yaml").read_text()).get("impact", {})
    return merge(default, other)


def wildcards(path: str) -> SimpleNamespace:
    """The wildcards of rule impact_regime_run for one of its outputs."""
    _, _, scene, _, name = path.split("/")
    ft, a, v = name.removesuffix(".nc").split("_")
    return SimpleNamespace(scene=scene, ft=ft[2:], a=a[1:], v=v[1:])


def scene_of(path: str, sec: dict):
    w = wildcards(path)
    args = shlex.split(workflow.regime_overrides(sec)(w))
    return load_scene(f"impact/{w.scene}", args[1::2])


def test_default_profile_maps_2d_only_and_keeps_its_paths():
    """The default profile's 20-minute budget has no room for 3D runs: 24 2D runs, no 3D."""
    sec = section("config")
    assert workflow.regime_three_d(sec) is None and workflow.regime_runs_3d(sec) == []
    runs = workflow.regime_runs(sec)
    assert len(runs) == 24
    assert runs[0] == "results/impact/default/regime/ft3.216_a0.1_v5.nc"


@pytest.mark.parametrize("profile", ["ci", "medium", "paper"])
def test_3d_grid_has_its_own_scene_end_time_and_resources(profile):
    sec = section(profile)
    cfg = workflow.regime_three_d(sec)
    runs3, runs2 = workflow.regime_runs_3d(sec), workflow.regime_runs(sec)
    assert len(runs3) == len(set(runs3)) == (
        len(cfg["f_t"]) * len(cfg["contact_a"]) * len(cfg["velocities"]))
    assert all(r.startswith(f"results/impact/{cfg['scene']}/regime/") for r in runs3)
    assert not set(runs3) & set(runs2)
    if profile != "ci":  # 12-25 runs of the source's disc
        assert 12 <= len(runs3) <= 25 and cfg["scene"] == "disc3d"
    for path in (runs3[0], runs3[-1]):
        scene = scene_of(path, sec)
        assert scene.get("domain.dim") == 3
        assert scene.get("outputs.t_end") == pytest.approx(cfg["t_end"])
        assert scene.get("outputs.snapshot_times") == pytest.approx(
            [k * cfg["t_end"] / 5 for k in range(1, 5)])  # the class's history
        assert scene.get("particles.masses.distribution") == "homogeneous"
        w = wildcards(path)
        assert scene.get("material.f_t") == pytest.approx(float(w.ft) * 1e6)
        assert scene.get("particles.impact_velocity") == pytest.approx(float(w.v))
        for key in ("threads", "mem_mb", "runtime_run"):
            assert workflow.regime_resource(sec, key)(w) == cfg[key]
    # the 2D runs keep the 2D grid's end time and the 2D section's resources
    flat = scene_of(runs2[0], sec)
    assert flat.get("domain.dim") == 2
    assert flat.get("outputs.t_end") == pytest.approx(sec["regime"]["t_end"])
    assert workflow.regime_resource(sec, "threads")(wildcards(runs2[0])) == sec["threads"]


def test_3d_grid_needs_dim_3_and_its_own_scene():
    sec = section("ci")
    assert workflow.regime_runs_3d({**sec, "dims": [2]}) == []
    same = {**sec, "regime": {**sec["regime"], "three_d": {
        **sec["regime"]["three_d"], "scene": sec["scene"]}}}
    with pytest.raises(ValueError, match="impact.regime.three_d.scene"):
        workflow.regime_three_d(same)


def test_3d_grid_defaults_to_the_2d_grid():
    sec = section("ci")
    cfg = workflow.regime_three_d(sec)
    for key in ("f_t", "contact_a", "velocities"):
        assert cfg[key] == sec["regime"][key]


# --- classification of runs -------------------------------------------------------------------

@pytest.fixture(scope="module")
def runs(tmp_path_factory) -> dict[str, Path]:
    """The CI discs, 2D (about 200 particles) and 3D (336, three layers), to 0.1 ms with one
    snapshot at 50 us: seconds each."""
    tmp = tmp_path_factory.mktemp("regime")
    args = ["outputs.t_end=1.0e-4", "outputs.snapshot_times=[5.0e-5]"]
    return {dim: run(load_scene(f"impact/{name}", args), tmp / f"{name}.nc", seed=0)
            for dim, name in (("2D", "ci"), ("3D", "ci3d"))}


def test_3d_run_row(runs):
    row = regime.regime_row(runs["3D"])
    assert row["dim"] == "3D" and row["scene"] == "ci3d"
    assert row["t_end"] == pytest.approx(1e-4)
    assert row["class"] == regime.classify(row["n_main_cracks"])
    hist = row["class_history"]
    assert [h["t"] for h in hist] == pytest.approx([5e-5, 1e-4], rel=0.02)
    assert hist[-1]["class"] == row["class"]
    assert row["class_settled_from"] in [h["t"] for h in hist]


def split_at_columns(ds, columns_x: list[float], layer: str, opening: float = 1e-3):
    """A copy of ``ds`` at rest (positions = reference) but for rigid splits at reference x in
    ``columns_x``: the particles of one layer (the mid-thickness layer or a face layer) beyond
    each column moved ``opening`` away from the centre line; nothing softened, damaged or
    crushed. Written into the final fields and the last snapshot."""
    x0, y0, z0 = ds["x0"].values, ds["y0"].values, ds["z0"].values
    layers = np.unique(np.round(z0, 9))
    z = layers[len(layers) // 2] if layer == "mid" else layers[0]
    in_layer = np.isclose(z0, z)
    x = x0.copy()
    for col in columns_x:
        side = np.sign(col) if col != 0 else 1.0
        beyond = in_layer & (side * (x0 - col) > 0)
        x[beyond] += side * opening
    zero = np.zeros(x0.size)
    out = ds.copy(deep=True)
    for key, value in (("x", x), ("y", y0), ("softening", zero), ("damage", zero),
                       ("plastic_strain", zero)):
        out[key].values[:] = value
        out[f"snap_{key}"].values[-1] = value
    return out


@pytest.mark.parametrize("columns_x,layer,expected", [
    ([0.0], "mid", "splits once"),          # one vertical split through the centre
    ([-0.015, 0.015], "mid", "fans out"),   # two, 30 mm apart
    ([0.0], "face", "no main crack"),       # a split of a face layer only: not on the measured one
])
def test_3d_classification_counts_openings_on_the_mid_thickness_layer(runs, tmp_path, columns_x,
                                                                     layer, expected):
    """Cracks are counted by their opening (as check 12 counts them): a rigid split with nothing
    softened is a crack, and the softening clusters' count (secondary) sees none."""
    ds = split_at_columns(open_dataset(runs["3D"]), columns_x, layer)
    path = tmp_path / "synthetic.nc"
    ds.to_netcdf(path)
    row = regime.regime_row(path)
    assert row["dim"] == "3D" and row["class"] == expected
    assert row["class_history"][-1]["class"] == expected
    assert row["n_main_cracks_softening"] == 0


def test_class_settles_from_the_last_change():
    hist = [{"t": t, "class": c} for t, c in ((1, "no main crack"), (2, "fans out"),
                                               (3, "splits once"), (4, "splits once"))]
    assert regime.settled_from(hist) == 3
    assert regime.settled_from(hist[:2]) == 2 and regime.settled_from([]) is None
    assert not regime.changed_at_end({"class_history": hist})
    assert regime.changed_at_end({"class_history": hist[:3]})
    assert not regime.changed_at_end({"class_history": hist[:1]})


def _row(dim, a, f_t, v, n):
    return {"dim": dim, "scene": "s" + dim, "contact_a": a, "f_t": f_t, "impact_velocity": v,
            "t_end": 3e-4 if dim == "3D" else 5e-4, "n_main_cracks": n, "centre_crossings": n,
            "n_main_cracks_softening": n, "strength_to_load": 5.0 / (1 + n),
            "class": regime.classify(n), "class_settled_from": 2e-4}


def test_figure_has_a_row_of_panels_per_dimension(tmp_path):
    rows = [_row("2D", a, f, v, n) for a, f, v, n in ((0.1, 3.2e6, 5.0, 1), (6.27, 3.2e6, 5.0, 3),
                                                       (0.1, 6.4e6, 15.0, 0))]
    rows += [_row("3D", 6.27, 3.2e6, 15.0, 2)]
    maps = regime.regime_maps(rows)
    assert list(maps) == ["2D", "3D"] and maps["3D"]["t_end"] == 3e-4
    assert maps["2D"]["classes"] == {"no main crack": 1, "splits once": 1, "fans out": 1}
    assert maps["2D"]["n_changed_at_end"] == 0
    titles = regime.figure_regime(rows, tmp_path / "map.png", "test")
    ratio = "class against peak contact force / static splitting load"
    assert titles == ["2D, s2D, 500 us: penalty scale a = 0.1",
                      "2D, s2D, 500 us: penalty scale a = 6.27", f"2D: {ratio}",
                      "3D, s3D, 300 us: penalty scale a = 6.27", f"3D: {ratio}"]
    assert (tmp_path / "map.png").read_bytes()[:4] == b"\x89PNG"


def test_script_writes_both_dimensions(runs, tmp_path, monkeypatch):
    """workflow/scripts/impact_regime.py as rule impact_regime runs it: regime.json with a map
    per dimension and every run, and the figure."""
    out = SimpleNamespace(json=str(tmp_path / "regime.json"), png=str(tmp_path / "map.png"))
    smk = SimpleNamespace(input=[str(runs["2D"]), str(runs["3D"])], output=out,
                          params=SimpleNamespace(profile="test"),
                          log=[str(tmp_path / "regime.log")])
    monkeypatch.setattr(sys, "stdout", sys.stdout)  # the script sends both to its log
    monkeypatch.setattr(sys, "stderr", sys.stderr)
    runpy.run_path(str(ROOT / "workflow" / "scripts" / "impact_regime.py"),
                   init_globals={"snakemake": smk})
    sys.stdout.close()
    doc = json.loads(Path(out.json).read_text())
    assert doc["dims"] == ["2D", "3D"]
    assert doc["maps"]["2D"]["scene"] == ["ci"] and doc["maps"]["3D"]["scene"] == ["ci3d"]
    assert [r["dim"] for r in doc["runs"]] == ["2D", "3D"]
    assert Path(out.png).stat().st_size > 1000
    assert "3D f_t 3.22 MPa" in Path(smk.log[0]).read_text()  # one line per run
