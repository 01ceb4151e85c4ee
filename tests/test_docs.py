"""The documentation site's generators (docs/site_hooks/): the docstrings' reST math becomes
arithmatex's Markdown, and the API pages cover every effect and module of the package. The
site is built with warnings as errors (`mkdocs build --strict`, as `make docs` does), which
also checks every internal link and anchor, and its equations are checked in a browser."""

from __future__ import annotations

import importlib.util
import json
import re
import textwrap

import pytest

from craquelure.models import MODELS
from craquelure.registry import known_effects
from craquelure.scene import project_root

ROOT = project_root()


def _load(name: str):
    spec = importlib.util.spec_from_file_location(name, ROOT / "docs" / "site_hooks" /
                                                  f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def rest_math():
    return _load("rest_math")


@pytest.fixture(scope="module")
def hooks():
    return _load("hooks")


def test_rest_math_becomes_arithmatex(rest_math):
    text = ("Rate (Eq. 15):\n\n.. math::\n\n    a = b\n    + c\n\n    d = e\n\nwith :math:`x_i^2`, "
            "see :func:`~craquelure.codegen.generate` and ``scene.get``.\n\n    .. math::\n"
            "        :label: eq1\n\n        f = g\n\nend")
    out = rest_math.rest_to_markdown(text)
    assert "\\[\na = b\n+ c\n\\]" in out and "\\[\nd = e\n\\]" in out
    assert "\\(x_i^2\\)" in out and "`craquelure.codegen.generate`" in out
    assert "`scene.get`" in out and "``" not in out and ":math:" not in out
    assert "    \\[\n    f = g\n    \\]" in out and ":label:" not in out
    assert out.endswith("end")
    one_line = rest_math.rest_to_markdown(".. math:: u = v\n\ntext")
    assert "\\[\nu = v\n\\]" in one_line and one_line.endswith("text")


def test_every_effect_docstring_converts_to_balanced_math(rest_math):
    for model in MODELS:
        for effect in known_effects(model).values():
            path = next(p for p in (ROOT / "src" / "craquelure").rglob("*.py")
                        if f'"{effect.name}"' in p.read_text() and "EFFECT = Effect(" in
                        p.read_text() and f'"{model}"' in p.read_text())
            doc = re.search(r'^r?"""(.*?)"""', path.read_text(), re.S)
            assert doc, path
            out = rest_math.rest_to_markdown(doc.group(1))
            assert ":math:" not in out and ".. math::" not in out, path
            assert out.count("\\(") == out.count("\\)"), path
            assert out.count("\\[") == out.count("\\]"), path


def test_api_pages_cover_every_model_effect_and_module(hooks):
    pages = hooks.api_pages()
    assert set(pages) == {f"api/{m}.md" for m in MODELS} | {"api/core.md"}
    listed = {}
    for page, text in pages.items():
        for name in re.findall(r"^::: (\S+)$", text, re.M):
            assert name not in listed, (name, page, listed.get(name))
            listed[name] = page
    for model in MODELS:
        effects_part = pages[f"api/{model}.md"].split("## Modules")[0]
        for effect in known_effects(model):
            assert re.search(rf"^::: craquelure\.[\w.]*effects\.{effect}$", effects_part, re.M), (
                model, effect)
    package = ROOT / "src" / "craquelure"
    modules = {".".join(p.relative_to(package.parent).with_suffix("").parts)
               for p in package.rglob("*.py") if p.name != "__init__.py"}
    assert modules == set(listed)


def test_links_are_rewritten_for_the_site_and_missing_targets_warned(hooks, caplog):
    text = ("[a](docs/drying.md#cost) [b](config/README.md) [c](LICENSE) "
            "![d](docs/export_drying_default.png) [e](https://example.org) [f](docs/nope.md)")
    out = hooks.rewrite_links(text, "README.md", "index.md")
    assert "[a](drying.md#cost)" in out and "[b](configuration.md)" in out
    assert "`LICENSE`" in out and "![d](export_drying_default.png)" in out
    assert "[e](https://example.org)" in out
    assert any("docs/nope.md" in r.getMessage() for r in caplog.records)
    page = hooks.rewrite_links("[x](../config/README.md#keys)", "docs/outputs.md", "outputs.md")
    assert page == "[x](configuration.md#keys)"


@pytest.mark.slow
def test_site_builds_strict_and_renders_every_equation_offline(tmp_path):
    """`mkdocs build --strict` (warnings, broken links and anchors are errors; the tutorials
    executed, with their figures; no script loaded from the network), then each API page in
    headless Chromium without network: every equation typeset by the site's own MathJax, none
    left as TeX, no MathJax error."""
    import os
    import subprocess
    import sys

    from tests.chromium import FLAGS, require_chromium

    site = tmp_path / "site"
    env = {**os.environ, "NO_MKDOCS_2_WARNING": "1"}
    built = subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict", "--quiet",
                            "--site-dir", str(site)], cwd=ROOT, env=env, capture_output=True,
                           text=True)
    assert built.returncode == 0, built.stdout + built.stderr
    for model in MODELS:  # the tutorials, executed by the build, with their figures
        tutorial = (site / "tutorials" / model / "index.html").read_text()
        assert "data:image/png;base64," in tutorial and "Traceback" not in tutorial, model
    external = [str(p.relative_to(site)) for p in site.rglob("*.html")
                if re.search(r"<script[^>]+src=\"(https?:)?//", p.read_text())]
    assert external == []  # the site reads offline: no script from the network
    browser = require_chromium()
    for model in (*MODELS, "core"):
        page = site / "api" / model / "index.html"
        text = page.read_text()
        equations = text.count('class="arithmatex"')
        if model != "core":
            assert equations > 0, model  # every model's effects state their equations
        dom = subprocess.run([browser, *FLAGS, f"--user-data-dir={tmp_path}/profile",
                              "--window-size=1280,800", "--virtual-time-budget=30000",
                              "--dump-dom", page.as_uri()], capture_output=True, text=True,
                             timeout=180).stdout
        assert dom.count('class="arithmatex"') == equations, model
        assert dom.count("<mjx-container") == equations, model
        assert "<mjx-merror" not in dom and "data-mjx-error" not in dom, model


def test_repository_paths_named_in_the_docs_exist():
    """Every file or folder of the repository a page names in code (`src/...`, `tests/...`,
    `config/...`, `workflow/...`, `benchmarks/...`, `profiles/...`, `docs/...`) exists: moved
    code takes its documentation along. Patterns (`<model>`, `*`, `{scene}`) are not paths."""
    pages = [ROOT / "README.md", ROOT / "CHANGELOG.md", ROOT / "config" / "README.md",
             ROOT / "results" / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
    roots = ("src/", "tests/", "config/", "workflow/", "benchmarks/", "profiles/", "docs/")
    # named as written by runs (benchmark: files) or as where Snakemake never looks
    not_files = {"benchmarks/results/", "workflow/profiles/"}
    missing = []
    for page in pages:
        for token in re.findall(r"`([^`\s]+)`", page.read_text()):
            path = token.split("::")[0].rstrip(".,;:")
            if (path.startswith(roots) and not re.search(r"[<>*{}]", path)
                    and not path.startswith(tuple(not_files))):
                if not (ROOT / path).exists():
                    missing.append(f"{page.relative_to(ROOT)}: {token}")
    assert missing == [], "\n".join(missing)


def test_documented_snakemake_commands_name_their_targets_before_configfile():
    """`--configfile` takes every following word as a config file, so a target written after
    it is read as a file and the command fails (as config/README.md's commands did until
    2026-12-03): in every page and config comment, the words after `--configfile` up to the
    next option or the end of the command are .yaml files."""
    pages = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md")),
             *sorted((ROOT / "config").glob("*.md")), *sorted((ROOT / "config").glob("*.yaml"))]
    bad = []
    for page in pages:
        text = re.sub(r"\\\n\s*#?\s*", " ", page.read_text())  # join continued lines
        for command in re.findall(r"snakemake [^`\n|]*", text):
            words = command.split()
            if "--configfile" not in words:
                continue
            after = words[words.index("--configfile") + 1:]
            files = after[:next((i for i, w in enumerate(after) if w.startswith("-")),
                                len(after))]
            if any(not w.rstrip(".,;)'\"").endswith(".yaml") for w in files):
                bad.append(f"{page.relative_to(ROOT)}: {command.strip()}")
    assert bad == [], "\n".join(bad)


DOC_PAGES = [ROOT / "README.md", ROOT / "config" / "README.md", ROOT / "results" / "README.md",
             *sorted((ROOT / "docs").glob("*.md"))]


def code_blocks(text: str, language: str) -> list[str]:
    """The fenced code blocks of ``language`` of a Markdown text (indented fences included)."""
    return [textwrap.dedent(m.group(2)) for m in re.finditer(
        rf"^([ \t]*)```{language}[ \t]*\n(.*?)^\1```", text, re.M | re.S)]


def documented_commands() -> list[tuple[str, str]]:
    """(page, command) of every `craquelure ...` line of the pages' bash blocks, without its
    comment and optional parts in [brackets]."""
    found = []
    for page in DOC_PAGES:
        for block in code_blocks(page.read_text(), "bash"):
            for line in block.splitlines():
                line = re.sub(r"\[[^\]]*\]", "", line.split(" #")[0]).strip()
                if line.startswith("craquelure "):
                    found.append((page.relative_to(ROOT).as_posix(), line))
    return found


def test_documented_commands_parse_and_their_scenes_are_valid():
    """Every documented `craquelure` command parses with the CLI's own parser, and a command
    that takes a scene names a valid scene with valid overrides (what `check` would say)."""
    import shlex

    from craquelure import cli
    from craquelure.api import load_scene

    commands = documented_commands()
    assert len(commands) >= 15 and {c.split()[1] for _, c in commands} >= {
        "scenes", "check", "init", "run", "fragments", "export"}
    parser = cli.build_parser()
    for page, command in commands:
        args = parser.parse_args(shlex.split(command)[1:])
        if getattr(args, "scene", None):
            load_scene(args.scene, args.overrides)  # raises the one-line SceneError
        assert page


def test_documented_scripts_exist():
    """Every script a bash block runs (`python benchmarks/x.py`, `.venv/bin/python ...`)."""
    missing = []
    for page in DOC_PAGES:
        for block in code_blocks(page.read_text(), "bash"):
            for script in re.findall(r"python\s+(\S+\.py)", block):
                if not (ROOT / script).is_file():
                    missing.append(f"{page.relative_to(ROOT)}: {script}")
    assert missing == []


@pytest.mark.slow
@pytest.mark.parametrize("page", [p for p in DOC_PAGES if code_blocks(p.read_text(), "python")],
                         ids=lambda p: p.relative_to(ROOT).as_posix())
def test_documented_python_blocks_run(page, tmp_path):
    """A page's Python blocks, in order, in one fresh process (a block may use what an earlier
    one defined), in an empty folder: each documented snippet runs as written."""
    import os
    import subprocess
    import sys

    code = "\n\n".join(code_blocks(page.read_text(), "python"))
    env = {**os.environ, "MPLBACKEND": "Agg",
           "PYTHONPATH": os.pathsep.join([str(ROOT / "src"), os.environ.get("PYTHONPATH", "")])}
    proc = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, env=env,
                          capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr[-3000:]


def test_include_and_verdicts_markers(hooks):
    """`{{ include: ... }}` inserts a Markdown file or renders a JSON table, `{{ verdicts: ...
    model=... }}` a model's validation rows; a file that does not exist fails the build."""
    from mkdocs.exceptions import PluginError

    page = "Before\n\n{{ include: benchmarks/tables/cost_softdyn.md }}\n\nAfter\n"
    out = hooks.expand_markers(page, "softdyn.md")
    assert "| `softdyn/t1_single_ci` |" in out and out.endswith("\n\nAfter\n")
    out = hooks.expand_markers(
        "{{ verdicts: tests/reference/ci/validation.json model=drying }}\n", "drying.md")
    rows = [c for c in json.loads((ROOT / "tests/reference/ci/validation.json").read_text())[
        "claims"] if c["model"] == "drying"]
    assert len(rows) >= 4  # head, rule, one line per row
    assert sum(line.startswith("|") for line in out.splitlines()) == 2 + len(rows)
    assert "**not reproduced**" in out and "0.78 t\\*" in out  # t* is text, not emphasis
    for missing in ("{{ include: benchmarks/tables/nope.md }}",
                    "{{ verdicts: results/published/nope/validation.json model=drying }}"):
        with pytest.raises(PluginError, match="does not exist"):
            hooks.expand_markers(f"x\n{missing}\n", "drying.md")
    assert "value" in hooks.json_table({"a": 1.5, "b": 2}) and "| a | 1.5 |" in \
        hooks.json_table({"a": 1.5, "b": 2})


def test_cost_tables_are_those_the_benchmark_writes():
    """benchmarks/tables/cost_<model>.md equal what benchmarks/cost_table.py writes today:
    a scene or a calibration change without re-running it fails here."""
    spec = importlib.util.spec_from_file_location("cost_table",
                                                  ROOT / "benchmarks" / "cost_table.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    for model in MODELS:
        assert (ROOT / "benchmarks" / "tables" / f"cost_{model}.md").read_text() == \
            module.cost_table(model), model


def test_model_pages_read_as_a_manual():
    """Each model page is at most about 300 lines, has the manual's sections, shows its
    verdicts from a committed report and carries no dated measurement prose."""
    for model in MODELS:
        text = (ROOT / "docs" / f"{model}.md").read_text()
        assert text.count("\n") <= 300, model
        for heading in ("## The model", "## Scenes and keys", "## How to run it",
                        "## What it shows now", "## Departures from the source", "## Cost"):
            assert heading in text, (model, heading)
        marker = rf"^\{{\{{ verdicts: \S+ model={model}( \w+=\S+)* \}}\}}$"
        assert re.search(marker, text, re.M), model
        assert not re.search(r"20\d\d-\d\d-\d\d|measured on|under load", text), model


def test_verdicts_show_the_figures_beside_the_report(hooks, tmp_path, monkeypatch):
    """A report's figures, in its folder or its figures/ folder, are shown in the rows (and
    copied into the site); a figure that is not there is named, not linked."""
    import json

    monkeypatch.setattr(hooks, "ROOT", tmp_path)
    report = tmp_path / "results" / "published" / "x" / "validation.json"
    (report.parent / "figures").mkdir(parents=True)
    (report.parent / "figures" / "a.png").write_bytes(b"\x89PNG")
    rows = [{"model": "drying", "claim": "c1", "verdict": "reproduced", "figure": "a.png"},
            {"model": "drying", "claim": "c2", "verdict": "partly", "figure": "b.png"}]
    report.write_text(json.dumps({"profile": "p", "claims": rows}))
    (tmp_path / "docs").mkdir()
    (tmp_path / "docs" / "drying.md").write_text(
        "{{ verdicts: results/published/x/validation.json model=drying }}\n")
    out = hooks.verdicts_table(report, "drying", "drying.md")
    assert "(figures/results/published/x/figures/a.png)" in out and "`b.png`" in out
    assert hooks.marked_figures() == [report.parent / "figures" / "a.png"]


def test_verdicts_show_the_figures_named_by_also(hooks, tmp_path, monkeypatch):
    """`also=` shows figures beside the report that no row names (and copies them into the
    site); one that is not there fails the build."""
    import json

    monkeypatch.setattr(hooks, "ROOT", tmp_path)
    report = tmp_path / "results" / "published" / "x" / "validation.json"
    (report.parent / "figures").mkdir(parents=True)
    (report.parent / "figures" / "sweep.png").write_bytes(b"\x89PNG")
    rows = [{"model": "impact", "claim": "c1", "verdict": "partly", "figure": ""}]
    report.write_text(json.dumps({"profile": "p", "claims": rows}))
    (tmp_path / "docs").mkdir()
    marker = "{{ verdicts: results/published/x/validation.json model=impact also=sweep.png }}\n"
    (tmp_path / "docs" / "impact.md").write_text(marker)
    out = hooks.expand_markers(marker, "impact.md")
    assert out.rstrip().endswith("(figures/results/published/x/figures/sweep.png)")
    assert hooks.marked_figures() == [report.parent / "figures" / "sweep.png"]
    with pytest.raises(hooks.PluginError, match="figure gone.png"):
        hooks.expand_markers(marker.replace("sweep.png", "gone.png"), "impact.md")


def test_companions_show_their_rows_and_the_comparison_figures(hooks, tmp_path, monkeypatch):
    """`{{ companions: ... }}` shows each companion ensemble of a report with its setting and
    rows (a verdict, or "not judged" and why) and the comparison figures beside the report
    (copied into the site); a report without companions says so."""
    import json

    monkeypatch.setattr(hooks, "ROOT", tmp_path)
    report = tmp_path / "results" / "published" / "x" / "validation.json"
    (report.parent / "figures").mkdir(parents=True)
    report.write_text(json.dumps({"profile": "p", "claims": []}))
    (tmp_path / "docs").mkdir()
    (tmp_path / "docs" / "drying.md").write_text(
        "{{ companions: results/published/x/validation.json }}\n")
    assert "No companion ensemble" in hooks.expand_markers(
        "{{ companions: results/published/x/validation.json }}\n", "drying.md")
    fig = report.parent / "figures" / "drying_companions_inverse_mean_area.png"
    fig.write_bytes(b"\x89PNG")
    row = {"model": "drying", "claim": "c", "source": "s", "measured": "t* = 1"}
    tally = {"all": {"reproduced": 0, "partly": 1, "not reproduced": 0, "inconclusive": 0}}
    report.write_text(json.dumps({"profile": "p", "claims": [], "companions": [
        {"name": "a", "setting": "L = 10", "judged": True, "why": "", "tally": tally,
         "claims": [{**row, "verdict": "partly"}]},
        {"name": "b", "setting": "L = 5", "judged": False, "why": "a variant", "tally": None,
         "claims": [{**row, "verdict": None}, {**row, "verdict": None}]}]}))
    out = hooks.companions_section(report, "drying.md")
    assert "**a**, L = 5" not in out and "**a**, L = 10: 0 reproduced, 1 partly" in out
    assert "**b**, L = 5: not judged: a variant." in out
    assert sum(line.startswith("|") for line in out.splitlines()) == 2 + 1 + 2 + 2
    assert out.count("| not judged |") == 2 and "t\\* = 1" in out
    assert "(figures/results/published/x/figures/drying_companions_inverse_mean_area.png)" in out
    assert hooks.marked_figures() == [fig]
