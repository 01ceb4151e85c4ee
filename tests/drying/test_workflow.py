"""DAG helpers of the drying rules (craquelure.drying.workflow) and the drying-speed settings
the job of rule drying_speed_scene writes: the same `--set` arguments, to the character, as the
workflow passed when it derived them while building the DAG (old formula kept below)."""

from __future__ import annotations

import runpy
import shlex
from pathlib import Path
from types import SimpleNamespace

import pytest
import yaml

from craquelure.drying import workflow
from craquelure.drying.speed import speed_run_settings
from craquelure.scene import load_scene, overrides_from_file, project_root

ROOT = project_root()


def section(profile: str) -> dict:
    """The drying section of a profile as Snakemake sees it: merged over config/config.yaml."""
    def merge(base: dict, over: dict) -> dict:
        return {**base, **{k: merge(base[k], v) if isinstance(v, dict) and k in base else v
                           for k, v in over.items()}}
    base = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())["drying"]
    return merge(base, yaml.safe_load((ROOT / "config" / profile).read_text())["drying"])


def old_speed_run_settings(study: dict, scene_path: str, pi_label: str) -> str:
    """workflow/rules/common.smk before the drying workflow module (commit 8497a7e), verbatim
    but for its inputs: what the DAG passed to `craquelure run`."""
    def speed_label(pi):
        return f"{pi:g}".replace(".", "p")

    def speed_end_over_t_star(study, pi):
        ends = study["t_end_over_t_star"]
        if not isinstance(ends, list):
            return float(ends)
        by_pi = {speed_label(p): float(e) for p, e in zip(study["pis"], ends, strict=True)}
        return by_pi[speed_label(pi)]

    scene = load_scene(scene_path)
    pi = float(pi_label.replace("p", "."))
    tau = scene.get("material.eta") / (2.0 * scene.get("material.lame_mu"))
    sigma_y = scene.get("material.yield_stress")
    t_star = tau / pi
    end = speed_end_over_t_star(study, pi)
    times = ", ".join(
        f"{f * t_star:.6g}" for f in study["times_over_t_star"] if f <= end * (1 + 1e-9)
    )
    items = [
        f"material.drying_rate={pi * sigma_y / tau:.6g}",
        f"outputs.t_end={end * t_star:.6g}",
        f"outputs.times=[{times}]",
        *study.get("set", []),
    ]
    return " ".join(f"--set {shlex.quote(item)}" for item in items)


def new_speed_settings(jobs: workflow.Jobs, wildcards) -> dict:
    """What rule drying_speed_scene's job computes from its input and params."""
    scene = load_scene(ROOT / jobs.scene_path(wildcards))
    return speed_run_settings(scene, jobs.speed_value(wildcards),
                              jobs.speed_end_over_t_star(wildcards),
                              jobs.section["speed"]["times_over_t_star"])


PROFILE_SPEEDS = [(profile, pi) for profile in ("medium.yaml", "config.yaml")
                  for pi in section(profile)["speed"]["pis"]]


@pytest.mark.parametrize("profile,pi", PROFILE_SPEEDS)
def test_speed_run_gets_the_same_settings_as_before(profile, pi, monkeypatch):
    """Each speed run of config/medium.yaml and config/config.yaml gets the same drying rate,
    end and snapshot times (6 significant digits) as when the DAG derived them, in the same
    order before the study's own overrides."""
    monkeypatch.chdir(ROOT)
    sec = section(profile)
    jobs = workflow.Jobs(sec)
    wildcards = SimpleNamespace(scene=sec["scene"], pi=workflow.label(pi))
    old = shlex.split(old_speed_run_settings(sec["speed"], jobs.scene_path(wildcards),
                                             wildcards.pi))
    settings = new_speed_settings(jobs, wildcards)
    new = [*(w for item in settings["set"] for w in ("--set", item)),
           *shlex.split(jobs.speed_overrides())]
    assert new == old
    # and the physics: t* = sigma_Y / v_r = tau / Pi, the end in units of t*
    scene = load_scene(jobs.scene_path(wildcards))
    tau = scene.get("material.eta") / (2 * scene.get("material.lame_mu"))
    assert settings["tau"] == pytest.approx(tau, rel=1e-15)
    assert settings["t_star"] == pytest.approx(scene.get("material.yield_stress")
                                               / settings["drying_rate"], rel=1e-12)
    assert settings["t_end"] / settings["t_star"] == pytest.approx(
        jobs.speed_end_over_t_star(wildcards), rel=1e-12)
    assert settings["times"][-1] <= settings["t_end"] * (1 + 1e-9)


def test_settings_file_of_the_job_round_trips(tmp_path, monkeypatch):
    """The script of rule drying_speed_scene writes the `set` list that `--set-file` reads."""
    monkeypatch.chdir(ROOT)
    sec = section("medium.yaml")
    jobs = workflow.Jobs(sec)
    wildcards = SimpleNamespace(scene=sec["scene"], pi="0p022")
    script = runpy.run_path(str(ROOT / "workflow/scripts/drying_speed_scene.py"),
                            run_name="drying_speed_scene")
    out = tmp_path / "medium_Pi0p022" / "speed_settings.yaml"
    script["main"](jobs.scene_path(wildcards), jobs.speed_value(wildcards),
                   jobs.speed_end_over_t_star(wildcards), sec["speed"]["times_over_t_star"],
                   str(out))
    assert overrides_from_file(out) == new_speed_settings(jobs, wildcards)["set"]
    assert yaml.safe_load(out.read_text())["pi"] == 0.022
    assert not list(out.parent.glob(".*tmp*"))


def test_speed_inputs_and_ends_per_pi():
    sec = section("medium.yaml")
    jobs = workflow.Jobs(sec)
    groups = jobs.speed_fragments(SimpleNamespace(scene="medium"))
    assert list(groups) == ["P0p022", "P0p066", "P0p22", "P0p66"]
    assert all(len(paths) == sec["speed"]["n_seeds"] == 7 for paths in groups.values())
    assert groups["P0p022"][0] == "results/drying/medium_Pi0p022/fragments/seed1.nc"
    ends = [jobs.speed_end_over_t_star(SimpleNamespace(pi=p)) for p in ("0p022", "0p066",
                                                                      "0p22", "0p66")]
    assert ends == [1.5, 2.0, 4.0, 5.0]
    # each speed's snapshots stop at its own end, so later snapshots leave slower speeds alone
    slow = jobs.speed_times_over_t_star(SimpleNamespace(pi="0p022"))
    assert slow[-1] == 1.5 and slow == [t for t in sec["speed"]["times_over_t_star"] if t <= 1.5]
    assert jobs.speed_times_over_t_star(SimpleNamespace(pi="0p66"))[-1] == 5.0
    assert jobs.speed_overrides() == "--set numerics.integrator=rkc2"
    one_end = workflow.Jobs(section("config.yaml"))
    assert one_end.speed_end_over_t_star(SimpleNamespace(pi="0p66")) == 2.0
    assert one_end.speed_overrides() == ""


def test_one_end_per_pi_or_one_for_all():
    sec = section("medium.yaml")
    bad = {**sec, "speed": {**sec["speed"], "t_end_over_t_star": [1.5, 2.0]}}
    with pytest.raises(ValueError, match=r"t_end_over_t_star: one number or one value per "
                                         r"entry of drying.speed.pis \(4\)"):
        workflow.Jobs(bad)


def test_thickness_sweep_reuses_the_scenes_own_runs(monkeypatch):
    """config.yaml: H = 0.2, 0.25, 0.316; the default scene's own H = 0.316 reads its runs."""
    monkeypatch.chdir(ROOT)
    jobs = workflow.Jobs(section("config.yaml"))
    wildcards = SimpleNamespace(scene="default")
    assert load_scene(jobs.scene_path(wildcards)).get("material.thickness") == 0.316
    assert jobs.thickness_fragments(wildcards) == {
        "H0p2": ["results/drying/default_H0p2/fragments/seed1.nc"],
        "H0p25": ["results/drying/default_H0p25/fragments/seed1.nc"],
        "H0p316": ["results/drying/default/fragments/seed1.nc"],
    }
    assert jobs.thickness_value(SimpleNamespace(thickness="0p25")) == "0.25"
    assert jobs.seeds() == [1, 2, 3]
    assert Path(ROOT / jobs.scene_path(wildcards)).is_file()


def test_labels_round_trip():
    for value in (0.022, 0.66, 1.0, 4.0, 0.316):
        assert workflow.label_value(workflow.label(value)) == value
    assert workflow.label(0.25) == "0p25" and workflow.label(2.0) == "2"


def _merged(*files: str) -> dict:
    """The drying section of config/config.yaml with the given overlays merged over it."""
    def merge(base: dict, over: dict) -> dict:
        out = dict(base)
        for key, value in over.items():
            out[key] = (merge(base[key], value) if isinstance(value, dict)
                        and isinstance(base.get(key), dict) else value)
        return out
    data = yaml.safe_load((project_root() / "config" / "config.yaml").read_text())
    for name in files:
        data = merge(data, yaml.safe_load((project_root() / "config" / name).read_text()))
    data["drying"].setdefault("criterion", {"measures": ["trace"], "n_seeds": 0})
    data["drying"].setdefault("transition", {"variant": "", "scenes": ["a", "b"],
                                             "n_seeds": [0, 0]})
    return data["drying"]


def test_criterion_campaign_takes_its_own_seed_count():
    jobs = workflow.Jobs(_merged("faithful.yaml", "faithful_trace.yaml",
                                 "faithful_trace_reduced.yaml"))
    main = jobs.campaign_fragments(SimpleNamespace(scene="paper_speed"))
    trace = jobs.campaign_fragments(SimpleNamespace(scene="paper_speed_Ctrace"))
    assert len(main) == 37 and len(trace) == 8
    assert trace[0] == "results/drying/paper_speed_Ctrace/fragments/seed1.nc"
    assert jobs.criterion_folders() == ["paper_speed_Ctrace"]


def test_table1_overlay_plans_eight_seeds_per_criterion_and_the_transition():
    jobs = workflow.Jobs(_merged("faithful.yaml", "table1_l10.yaml"))
    assert len(jobs.campaign_fragments(SimpleNamespace(scene="table1_rkc2"))) == 8
    assert len(jobs.campaign_fragments(SimpleNamespace(scene="table1_rkc2_Ctrace"))) == 8
    groups = jobs.transition_fragments()
    assert list(groups) == ["paper_speed_small", "paper_speed", "table1_rkc2"]
    assert all(len(paths) == 8 for paths in groups.values())
    assert groups["table1_rkc2"][-1] == "results/drying/table1_rkc2_Ctrace/fragments/seed8.nc"
    assert groups["paper_speed_small"][0] == (
        "results/drying/paper_speed_small_Ctrace/fragments/seed1.nc")


def test_transition_groups_skip_sizes_without_seeds():
    groups = workflow.Jobs(_merged("faithful.yaml", "transition.yaml")).transition_fragments()
    assert list(groups) == ["paper_speed_tiny", "paper_speed_small"]
    assert len(groups["paper_speed_small"]) == 8
    assert groups["paper_speed_tiny"][0] == (
        "results/drying/paper_speed_tiny_Pi0p22/fragments/seed1.nc")


def test_kappa_points_and_their_overrides():
    kappa = workflow.KappaJobs({"kappa": {"gaps": [0.6, 0.8], "h_over_spacing": [5],
                                          "seeds": [1]}})
    assert kappa.labels() == ["gap0p6_hd4_clamped_cg", "gap0p8_hd4_truncated_cg",
                              "gap0p8_hd5_truncated_cg"]
    args = kappa.point_overrides(SimpleNamespace(point="gap0p8_hd5_truncated_cg"))
    # N from h/Delta at the scene's L = 2.5 and h = 0.2: (5 x 12.5)^2
    assert "--set particles.n=3906" in args and "rsa_min_separation=0.8" in args
    assert "numerics.mass_solve.method=truncated_cg" in args
    with pytest.raises(ValueError, match="does not match"):
        kappa.point_overrides(SimpleNamespace(point="gap0p8"))


def test_explicit_seeds_and_the_archived_ones(tmp_path, monkeypatch):
    """`seeds` replaces the range; the seeds of the archived ensemble `published` are not run
    again (the campaign continues with the rest in a later session)."""
    sec = _merged("faithful.yaml", "table1_ensemble.yaml")
    n = sec["n_seeds"]
    assert 40 <= n <= 100  # the floor, the paper's count
    assert workflow.Jobs({**sec, "published": None}).seeds() == list(range(1, n + 1))
    assert workflow.Jobs({**sec, "seeds": [35, 12], "published": None}).seeds() == [35, 12]
    tables = tmp_path / "results/published/drying-table1/tables"
    tables.mkdir(parents=True)
    (tables / "seeds.csv").write_text("seed,first_removal_time\n12,80.5\n3,81.0\n")
    monkeypatch.chdir(tmp_path)
    jobs = workflow.Jobs(sec)
    assert sec["published"] == "drying-table1"
    assert jobs.seeds() == [s for s in range(1, n + 1) if s not in (3, 12)]
    fragments = jobs.campaign_fragments(type("W", (), {"scene": "table1_trace"})())
    assert "results/drying/table1_trace/fragments/seed12.nc" not in fragments
    assert len(fragments) == n - 2


def test_companion_overlays_archive_their_own_ensembles(tmp_path, monkeypatch):
    """Each companion overlay grows its own archived ensemble from its own scene (the L = 5
    tr(sigma) one from the criterion runs of the faithful states, whose mass solves are the
    scene's); the headline names the companions, and those archived are shown beside it.
    Run in an empty tree: seeds archived under results/published/ are not run again."""
    monkeypatch.chdir(tmp_path)
    seeds = {}
    for name, scene, folder in (("table1_source_ensemble.yaml", "table1_rkc2", "table1_rkc2"),
                                ("l5_source_ensemble.yaml", "paper_speed", "paper_speed"),
                                ("l5_trace_ensemble.yaml", "paper_speed",
                                 "paper_speed_Ctrace")):
        sec = _merged("faithful.yaml", name)
        jobs = workflow.Jobs(sec)
        assert sec["scene"] == scene and sec["published"].startswith("drying-")
        fragments = jobs.campaign_fragments(SimpleNamespace(scene=folder))
        assert fragments[0] == f"results/drying/{folder}/fragments/seed1.nc"
        seeds[sec["published"]] = len(fragments)
        bench = jobs.publish_benchmarks(SimpleNamespace(scene=folder))
        assert bench["mass_consistency"][0].endswith(f"/mass_consistency/{scene}/seed1.tsv")
        assert bench["drying_run"][0].endswith(f"/drying_run/{folder}/seed1.tsv")
    assert seeds == {"drying-table1-source": 8, "drying-l5-source": 16, "drying-l5-trace": 16}
    headline = _merged("faithful.yaml", "table1_ensemble.yaml")
    assert headline["companions"] == list(seeds)
    root = tmp_path / "results/published"
    for name in ("drying-table1", "drying-l5-trace"):
        (root / name / "tables").mkdir(parents=True)
        (root / name / "tables/common.json").write_text("{}")
    (root / "drying-table1/provenance.json").write_text(
        '{"companions": ["drying-table1-source", "drying-l5-trace", "drying-table1"]}')
    assert workflow.published_companions("drying-table1") == ["drying-l5-trace"]
    assert workflow.published_companions("drying-l5-trace") == []
    assert workflow.rebuilt_with_companions(SimpleNamespace(name="drying-table1")) == [
        "results/drying_published/drying-table1", "results/drying_published/drying-l5-trace"]
