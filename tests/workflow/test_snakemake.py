"""The Snakemake frame: DAGs of the default and paper profiles, lint, the profiles' shape,
and an end-to-end run of ``rule all`` on the CI profile in a temporary copy of the workflow.

The end-to-end test is generic on purpose: whatever rules the models register, every produced
dataset must open with xarray, every figure must be a non-empty PNG, nothing may be left to do
afterwards, and no temporary file may survive.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
import tarfile
from pathlib import Path

import pytest
import xarray as xr
import yaml

from craquelure.scene import project_root

ROOT = project_root()
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"
ALLOWED_LINT = "Specify a conda environment or container for each rule."
# What Snakemake prints when it loads the embedded default profile (profiles/default/).
DEFAULT_PROFILE_LINE = "Using workflow specific profile profiles/default"


def workflow_copy(dest: Path) -> Path:
    """Snakefile, workflow/, config/ and profiles/ copied into ``dest`` (no results, no
    .snakemake), as in a fresh clone."""
    shutil.copy2(ROOT / "Snakefile", dest / "Snakefile")
    for folder in ("workflow", "config", "profiles"):
        shutil.copytree(ROOT / folder, dest / folder,
                        ignore=shutil.ignore_patterns("__pycache__", "*.pyc"))
    return dest


def snakemake(cwd: Path, *args: str, timeout: float = 300) -> subprocess.CompletedProcess:
    """Run the venv's Snakemake (the interpreter running the tests) in ``cwd``."""
    env = dict(os.environ)
    env["PATH"] = f"{Path(sys.executable).parent}{os.pathsep}{env.get('PATH', '')}"
    return subprocess.run([sys.executable, "-m", "snakemake", *args], cwd=cwd, env=env,
                          capture_output=True, text=True, timeout=timeout)


def job_stats(text: str) -> dict[str, int]:
    """The 'Job stats' table of a dry run as {rule: count}."""
    lines = text.splitlines()
    start = next(i for i, line in enumerate(lines) if line.strip() == "Job stats:")
    counts: dict[str, int] = {}
    for line in lines[start + 3:]:
        m = re.fullmatch(r"\s*(\S+)\s+(\d+)\s*", line)
        if not m:
            break
        counts[m.group(1)] = int(m.group(2))
    return counts


def profile(name: str) -> dict:
    return yaml.safe_load((ROOT / "config" / f"{name}.yaml").read_text())


@pytest.fixture(scope="module")
def fresh(tmp_path_factory) -> Path:
    return workflow_copy(tmp_path_factory.mktemp("dag"))


@pytest.mark.parametrize("config", ["config", "paper", "ci", "medium", "faithful"])
def test_dry_run_builds_the_dag(fresh, config):
    proc = snakemake(fresh, "-n", "--configfile", f"config/{config}.yaml")
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert DEFAULT_PROFILE_LINE in proc.stderr, proc.stderr[:2000]
    counts = job_stats(proc.stdout + proc.stderr)
    assert counts["all"] == 1
    # One mass-consistency job per seed of the profile (paper: Table I with 100 seeds).
    n_seeds = profile(config)["drying"]["n_seeds"]
    assert counts["mass_consistency"] == n_seeds
    if config == "paper":
        assert n_seeds == 100
    # The drying-speed study runs where its section has seeds (medium): one run per Pi and seed.
    study = {**profile("config")["drying"]["speed"], **profile(config)["drying"]["speed"]}
    assert counts.get("drying_speed_run", 0) == len(study["pis"]) * study["n_seeds"]
    # and one settings job per Pi (drying rate, end and snapshot times derived from the scene)
    assert counts.get("drying_speed_scene", 0) == (len(study["pis"]) if study["n_seeds"] else 0)
    assert counts.get("drying_speed_figure", 0) == (1 if study["n_seeds"] else 0)
    assert counts["total"] == sum(v for k, v in counts.items() if k != "total")


def test_faithful_profile_is_the_paper_regime_at_l5():
    """config/faithful.yaml: Table I material and drying speed, t = 0..300 with the paper's
    window, L = 5 (N = 1e4), the rkc2 integrator; only L differs from drying/table1."""
    from craquelure.scene import load_scene

    faithful = profile("faithful")
    assert faithful["profile"] == "faithful" and faithful["drying"]["window"] == "paper"
    scene = load_scene(ROOT / "config/scenes/drying" / f"{faithful['drying']['scene']}.yaml")
    table1 = load_scene(ROOT / "config/scenes/drying/table1.yaml")
    assert scene.get("numerics.integrator") == "rkc2" and scene.get("outputs.t_end") == 300.0
    assert scene.get("domain.box_length") == 5.0 and scene.get("particles.n") == 10000
    for key in ("material.rho0", "material.lame_lambda", "material.lame_mu", "material.eta",
                "material.thickness", "material.yield_stress", "material.drying_rate",
                "material.initial_stress_amplitude", "numerics.h",
                "particles.rsa_min_separation", "outputs.times"):
        assert scene.get(key) == table1.get(key), key


def test_plain_snakemake_loads_the_default_profile(fresh):
    """`snakemake` with no option at all: the default profile supplies the cores (else
    Snakemake stops asking for --cores), keep-going and rerun-incomplete."""
    proc = snakemake(fresh, "-n")
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert DEFAULT_PROFILE_LINE in proc.stderr, proc.stderr[:2000]
    settings = yaml.safe_load((ROOT / "profiles" / "default" / "config.yaml").read_text())
    assert settings["cores"] == "all" and settings["keep-going"] and settings["rerun-incomplete"]
    # Where Snakemake 9 never looks (the old place): nothing may be left there.
    assert not list((ROOT / "workflow").glob("profiles/*/*.yaml"))


def test_slurm_profile_is_one_workflow_profile_option(fresh):
    """--workflow-profile profiles/slurm replaces the default profile (one workflow profile is
    loaded, so its default-resources are not overwritten); the paper DAG builds with it."""
    proc = snakemake(fresh, "-n", "--configfile", "config/paper.yaml",
                     "--workflow-profile", "profiles/slurm")
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    assert "Using workflow specific profile profiles/slurm" in proc.stderr
    assert "profiles/default" not in proc.stderr
    settings = yaml.safe_load((ROOT / "profiles" / "slurm" / "config.yaml").read_text())
    assert settings["executor"] == "slurm"
    assert {"mem_mb", "runtime"} <= set(settings["default-resources"])
    # No cpus_per_task: SLURM then allocates each job's `threads:`.
    assert "cpus_per_task" not in settings["default-resources"]


def test_profiles_have_the_same_sections():
    # Snakemake merges --configfile into the default config/config.yaml: a section or key
    # missing from a profile would silently take the default profile's value.
    default = profile("config")
    for name in ("ci", "paper"):
        other = profile(name)
        assert set(other) == set(default), name
        for section, body in default.items():
            if isinstance(body, dict):
                assert set(other[section]) == set(body), (name, section)
    assert {profile(n)["profile"] for n in ("config", "ci", "paper")} == {
        "default", "ci", "paper"}


def test_lint_reports_only_conda_and_container(fresh):
    proc = snakemake(fresh, "--lint", "--configfile", "config/ci.yaml")
    text = proc.stdout + proc.stderr
    bullets = [line.strip()[2:] for line in text.splitlines()
               if line.lstrip().startswith("* ")]
    unexpected = [b for b in bullets if b.rstrip(":") != ALLOWED_LINT]
    assert unexpected == [], text
    # Lint exits 1 whenever it reports anything; then it must be only the allowed lint.
    assert proc.returncode == 0 or bullets, text
    headers = [line for line in text.splitlines() if line.startswith("Lints for")]
    assert all(h.startswith("Lints for rule ") for h in headers), headers
    assert "Traceback" not in text


# --- end to end on the CI profile ---------------------------------------------------------


# ci_run (tests/workflow/conftest.py): the uninterrupted run, also the reference of test_faults


def test_ci_workflow_runs(ci_run):
    work, proc = ci_run
    assert proc.returncode == 0, proc.stdout[-5000:] + proc.stderr[-5000:]
    # Nothing left to do: every target of `rule all` exists and is up to date.
    again = snakemake(work, "-n", "--configfile", "config/ci.yaml")
    assert again.returncode == 0
    assert "Nothing to be done" in again.stdout + again.stderr, again.stdout + again.stderr


def test_ci_outputs_are_valid(ci_run):
    work, proc = ci_run
    assert proc.returncode == 0
    results = work / "results"
    files = [p for p in results.rglob("*") if p.is_file()]
    datasets = [p for p in files if p.suffix == ".nc"]
    figures = [p for p in files if p.suffix == ".png"]
    assert any(p.parts[-3:-1] == ("mass", "ci") for p in datasets)
    for path in datasets:
        with xr.open_dataset(path) as ds:
            # Provenance (craquelure.provenance) on every dataset, whichever model wrote it.
            for key in ("git_commit", "scene", "version_numpy", "start_time", "wall_time_s"):
                assert key in ds.attrs, (path, key)
            assert ds.sizes, path
    for path in figures:
        data = path.read_bytes()
        assert data[:8] == PNG_MAGIC and len(data) > 1000, path
    # No temporary file survives (io.write_dataset names them .<name>.tmp-<pid>).
    assert [p for p in files if ".tmp" in p.name] == []
    # Everything is written under results/, logs/ and benchmarks/ (plus Snakemake's state).
    allowed = {"Snakefile", "workflow", "config", "profiles", "results", "logs", "benchmarks",
               ".snakemake"}
    assert {p.name for p in work.iterdir()} <= allowed
    # The mass-consistency datasets carry what the issue asks for.
    for path in (results / "mass" / "ci").glob("seed*.nc"):
        with xr.open_dataset(path) as ds:
            for key in ("h", "rho0", "box_length", "cg_iterations", "cg_residual"):
                assert key in ds.attrs, (path, key)
            assert ds.attrs["cg_residual"] <= 3e-3
            assert ds.attrs["seed"] == int(path.stem.removeprefix("seed"))
            for name in ("x", "y", "mass"):
                assert ds[name].dims == ("particle",)


def test_ci_validation_report_covers_every_model(ci_run):
    """results/validation.json: claims of all four models, each with a computed verdict."""
    work, proc = ci_run
    assert proc.returncode == 0
    doc = json.loads((work / "results" / "validation.json").read_text())
    assert doc["profile"] == "ci"
    assert {c["model"] for c in doc["claims"]} == {"drying", "impact", "lattice", "softdyn"}
    assert all(c["verdict"] in ("reproduced", "partly", "not reproduced", "inconclusive")
               for c in doc["claims"])
    assert sum(doc["tally"]["all"].values()) == len(doc["claims"])
    html = (work / "results" / "validation.html").read_text()
    assert html.count('<tr class="cq-row"') == len(doc["claims"])
    assert html.count("<details>") == len(doc["claims"])
    # the summary for the report's first page is the page's summary
    summary = (work / "results" / "validation_summary.html").read_text()
    assert summary.startswith('<section class="cq-summary">') and summary in html


def test_ci_numbers_match_the_reference(ci_run):
    """The CI run's summary.json files and validation claims equal tests/reference/ci/ (exact;
    timings and provenance left out: tests/reference/guard.py states why per quantity). A
    change that moves a number fails here, naming the keys, until the reference is regenerated
    with the CHANGELOG.md line (tests/reference/test_guard.py checks that line)."""
    from tests.reference import guard

    work, proc = ci_run
    assert proc.returncode == 0
    reference, _ = guard.load_reference()
    diffs = guard.differences(reference, guard.snapshot(work))
    assert not diffs, guard.report(diffs)


BUSY_LOOP = "import time\nend = time.monotonic() + 600\nwhile time.monotonic() < end:\n    pass\n"


VALIDATION_OUTPUTS = ("validation.json", "validation.html", "validation_summary.html")


def rerun_validation_report(work: Path) -> dict[str, bytes]:
    """Rule validation_report run again on the finished run's analysis outputs (a fresh
    interpreter, nothing cached from the first report); its outputs' bytes."""
    proc = snakemake(work, "--cores", "1", "--configfile", "config/ci.yaml",
                     "--forcerun", "validation_report", timeout=900)
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    assert "validation_report" in proc.stdout + proc.stderr
    return {name: (work / "results" / name).read_bytes() for name in VALIDATION_OUTPUTS}


def test_ci_validation_report_does_not_depend_on_the_load(ci_run):
    """The validation report of a fixed set of analysis outputs (the CI run's) is byte-identical
    whether the machine is idle or loaded: the rule runs again twice, the second time with two
    busy-loop processes per core, and both equal the report of the workflow run. A claim that
    timed something, or read a clock, would differ."""
    work, proc = ci_run
    assert proc.returncode == 0
    made = {name: (work / "results" / name).read_bytes() for name in VALIDATION_OUTPUTS}
    again = rerun_validation_report(work)
    hogs = [subprocess.Popen([sys.executable, "-c", BUSY_LOOP])
            for _ in range(2 * (os.cpu_count() or 1))]
    try:
        loaded = rerun_validation_report(work)
    finally:
        for hog in hogs:
            hog.kill()
            hog.wait()
    for name in VALIDATION_OUTPUTS:
        assert again[name] == made[name], name
        assert loaded[name] == made[name], name


def test_ci_report_builds(ci_run):
    work, proc = ci_run
    assert proc.returncode == 0
    report = snakemake(work, "--cores", "1", "--configfile", "config/ci.yaml",
                       "--report", "results/report.html")
    assert report.returncode == 0, report.stdout[-3000:] + report.stderr[-3000:]
    html = (work / "results" / "report.html").read_bytes()
    assert len(html) > 10_000 and b"<html" in html[:2000].lower()


def test_ci_pages_open_on_the_summary(ci_run):
    """The CI profile's validation page and Snakemake report in headless Chromium at
    1280 x 800: the summary table, its verdict badges and the thumbnails of the deciding figures
    are on the first screen, every claim folded: both show every row at once."""
    from tests.chromium import first_screen, on_screen, require_chromium

    require_chromium()
    work, proc = ci_run
    assert proc.returncode == 0
    results = work / "results"
    if not (results / "report.html").exists():
        built = snakemake(work, "--cores", "1", "--configfile", "config/ci.yaml",
                          "--report", "results/report.html")
        assert built.returncode == 0, built.stdout[-3000:] + built.stderr[-3000:]
    claims = json.loads((results / "validation.json").read_text())["claims"]
    for name in ("validation.html", "report.html"):
        seen = first_screen(results / name)
        assert seen["found"], f"{name} does not show the validation summary"
        assert seen["viewport"] == [1280, 800]
        assert seen["tables"] and all(on_screen(t) for t in seen["tables"]), name
        assert len(seen["rows"]) == len(claims), name
        assert all(on_screen(r) for r in seen["rows"]), (name, seen["rows"][-1])
        assert all(on_screen(b) for b in seen["badges"]), name
        with_figure = [t for t in seen["thumbs"] if t["figure"]]
        assert with_figure and all(on_screen(t) for t in with_figure), name
        assert seen["figures_decoded"] and all(seen["figures_decoded"]), name
        assert seen["details"] == len(claims) and seen["details_open"] == 0, name


# The one high-priority finding compliance-checker makes on our datasets: its §5.1 heuristic
# takes any dimension named "time" for a calendar axis (standard_name "time", units
# "<unit> since <date>"). Simulated time is no date: such units would make xarray decode it
# into datetimes, and reduced-unit models (drying, softdyn) have no time in seconds at all.
TIME_AXIS_HEURISTIC = "Coordinate variable 'time' should have standard_name='time'"


def cf_findings(path: Path) -> list[str]:
    """High-priority failures of IOOS compliance-checker's CF-1.11 suite on ``path``."""
    from compliance_checker.runner import CheckSuite, ComplianceChecker

    CheckSuite().load_all_available_checkers()
    out = path.with_suffix(".cf.json")
    ComplianceChecker.run_checker(str(path), ["cf:1.11"], 0, "normal",
                                  output_filename=str(out), output_format="json")
    report = json.loads(out.read_text())["cf:1.11"]
    out.unlink()
    return [msg for check in report["high_priorities"]
            if check["value"][0] != check["value"][1] for msg in check["msgs"]]


def test_ci_datasets_are_cf(ci_run, tmp_path):
    """Every variable of every dataset the CI workflow writes has a long name and units that
    UDUNITS parses; compliance-checker finds nothing high-priority on one dataset per model but
    the time-axis heuristic above."""
    import cf_units

    work, proc = ci_run
    assert proc.returncode == 0
    datasets = sorted((work / "results").rglob("*.nc"))
    per_model: dict[str, Path] = {}
    for path in datasets:
        with xr.open_dataset(path) as ds:
            assert ds.attrs["Conventions"] == "CF-1.11", path
            for key in ("title", "source", "history", "references"):
                assert ds.attrs.get(key), (path, key)
            assert re.match(r"\d{4}-\d\d-\d\dT\d\d:\d\d:\d\dZ \S", ds.attrs["history"])
            for name, var in ds.variables.items():
                assert var.attrs.get("long_name"), (path, name)
                if var.dtype.kind in "fiub":
                    cf_units.Unit(var.attrs["units"])  # raises ValueError if UDUNITS cannot
                    if var.attrs["units"] == "1" and "reduced_units" in var.attrs:
                        assert ds.attrs["reduced_unit_system"], (path, name)
            per_model.setdefault(ds.attrs["model"], path)
    assert set(per_model) == {"drying", "impact", "lattice", "softdyn"}
    for model, path in per_model.items():
        local = tmp_path / f"{model}.nc"
        shutil.copy2(path, local)
        findings = cf_findings(local)
        assert all(f.startswith(TIME_AXIS_HEURISTIC) for f in findings), (model, findings)


def test_ci_archive_verifies(ci_run):
    """Rule archive after the run; craquelure verify finds every file as packed."""
    work, proc = ci_run
    assert proc.returncode == 0
    packed = snakemake(work, "archive", "--cores", "1", "--configfile", "config/ci.yaml")
    assert packed.returncode == 0, packed.stdout[-3000:] + packed.stderr[-3000:]
    archives = list((work / "results" / "archive").glob("craquelure-ci-*.tar.gz"))
    assert len(archives) == 1
    check = subprocess.run([sys.executable, "-m", "craquelure", "verify", str(archives[0])],
                           capture_output=True, text=True)
    assert check.returncode == 0, check.stdout + check.stderr
    with tarfile.open(archives[0]) as tar:
        names = {n.split("/", 1)[1] for n in tar.getnames() if "/" in n}
    assert {"MANIFEST.sha256", "resolved-config.yaml", "config/ci.yaml",
            "results/validation.json", "results/validation.html", "results/report.html",
            "profiles/slurm/config.yaml"} <= names
    assert any(n.startswith("results/impact/ci/") and n.endswith(".nc") for n in names)
    # What a reviewer opens: every figure the run made, the report and the validation page.
    figures = {p.relative_to(work).as_posix() for p in (work / "results").rglob("*.png")}
    assert figures and figures <= names, sorted(figures - names)
    # The CI artefact: the archive under the checkout's results/archive/ (git-ignored).
    artefact = ROOT / "results" / "archive" / archives[0].name
    artefact.parent.mkdir(parents=True, exist_ok=True)
    shutil.copy2(archives[0], artefact)
    shutil.copy2(f"{archives[0]}.sha256", f"{artefact}.sha256")


def test_ci_runs_export_for_viewers(ci_run, tmp_path):
    """craquelure export on one real run per model: every frame's VTU holds every
    per-particle field the exporter found, equal to the dataset's values."""
    import meshio

    from craquelure.export_formats import export, frames_from_dataset

    work, proc = ci_run
    assert proc.returncode == 0
    runs = {
        "drying": "results/drying/ci/run/seed1.nc",
        "impact": "results/impact/ci/uniform_none/kappa1.0/seed1.nc",
        "lattice": "results/lattice/calving/run.nc",
        "softdyn": "results/softdyn/two_sphere_separation/run.nc",
    }
    for model, rel in runs.items():
        pvd, xyz = export(work / rel, "vtu", tmp_path / model)
        with xr.open_dataset(work / rel) as ds:
            frames = frames_from_dataset(ds.load())
        vtus = sorted((tmp_path / model).glob("frame_*.vtu"))
        assert len(vtus) == frames.n_frames >= 1, model
        assert frames.fields, model
        last = meshio.read(vtus[-1])
        assert set(last.point_data) == set(frames.fields), model
        assert (last.points == frames.positions[-1]).all(), model
        for name, values in frames.fields.items():
            got = last.point_data[name].reshape(values[-1].shape)
            assert (got == values[-1]).all(), (model, name)
        assert xyz.read_text().count("Properties=") == frames.n_frames
