"""MkDocs hooks of the documentation site (``mkdocs.yml``: ``hooks:``).

* The repository's own Markdown files outside ``docs/`` join the site: ``README.md`` as the home
  page, ``CHANGELOG.md``, ``config/README.md`` (configuration) and ``results/README.md``.
* One API page per model, generated from the package itself: the models are the packages under
  ``src/craquelure/`` that have an ``api`` module, in the order of the package's model list;
  a model's page shows every effect module that declares ``EFFECT = Effect("<model>", ...)``
  (wherever it lives) and every module of the model's package. A page for the shared core
  (everything else) follows. Nothing lists a module path by hand, so moving a module moves its
  documentation with it.
* MathJax (the docstrings' equations) is served by the site itself, so the pages read offline:
  the hook adds MathJax 3's self-contained ``tex-svg.js`` from the pinned package that ships it
  (``sphinx-mathjax-offline``) as ``javascripts/mathjax/tex-svg.js``.
* Links are written for the repository (they work when the files are read on disk or on a code
  host); this hook rewrites each relative link to the site page it becomes, and a link whose
  target does not exist in the repository is a warning (an error under ``--strict``), so the
  build is also the link check. Links to repository files that are not pages (``LICENSE``,
  sources) become code spans. Anchors are checked by MkDocs' own ``validation.anchors``.
* Numbers that a benchmark or the workflow writes are included from its output file, never
  retyped: a line ``{{ include: path/from/repo.md }}`` is replaced by that Markdown file (a
  ``.json`` file becomes a table: a list of rows, or a mapping of names to values), and
  ``{{ verdicts: path/to/validation.json model=drying }}`` by the model's rows of a validation
  report (claim, verdict, what was measured, the figure when it lies beside the report; with
  ``also=a.png,b.png`` those figures beside it below the rows);
  ``{{ companions: path/to/validation.json }}`` by the rows of the companion ensembles shown
  beside that report's (each with its setting, verdicts or why it has none) and the comparison
  figures beside it (``figures/drying_companions_*.png``). A marker whose file does not exist
  fails the build.
* The tutorials (``docs/tutorials/*.ipynb``) are executed during the build (nbclient, in a
  temporary folder) and become pages with their outputs; a cell that raises fails the build.
  ``CRAQUELURE_DOCS_EXECUTE=0`` renders them without executing (outputs as stored).
"""

from __future__ import annotations

import ast
import base64
import json
import logging
import os
import posixpath
import re
import tempfile
from pathlib import Path

from mkdocs.exceptions import PluginError
from mkdocs.structure.files import File, Files

log = logging.getLogger("mkdocs.hooks.craquelure")

ROOT = Path(__file__).resolve().parents[2]
PACKAGE = ROOT / "src" / "craquelure"
# repository path -> site path of the Markdown files outside docs/
ROOT_PAGES = {"README.md": "index.md", "CHANGELOG.md": "changelog.md",
              "config/README.md": "configuration.md", "results/README.md": "results.md"}
_LINK = re.compile(r"(!?\[[^\]]*\]\()([^)\s]+)(\))")
_FENCE = re.compile(r"^(```|~~~)")


def model_names() -> list[str]:
    """The package's models that have a package with an ``api`` module, in the order of the
    package's model list (``craquelure.models``, else ``craquelure.scene``)."""
    import importlib

    listed: list[str] = []
    for module in ("craquelure.models", "craquelure.scene"):
        try:
            mod = importlib.import_module(module)
        except ImportError:
            continue
        for value in vars(mod).values():
            if (isinstance(value, (tuple, list)) and value
                    and all(isinstance(v, str) for v in value)
                    and all((PACKAGE / v / "api.py").exists() for v in value)):
                listed = list(value)
                break
        if listed:
            break
    found = sorted(p.parent.name for p in PACKAGE.glob("*/api.py"))
    return [m for m in listed if m in found] + [m for m in found if m not in listed]


def _module_name(path: Path) -> str:
    rel = path.relative_to(PACKAGE.parent).with_suffix("")
    parts = list(rel.parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def effect_model(path: Path) -> str | None:
    """The model an effect module declares (``EFFECT = Effect("<model>", ...)``), else None."""
    try:
        tree = ast.parse(path.read_text())
    except SyntaxError:
        return None
    for node in tree.body:
        if (isinstance(node, ast.Assign) and any(isinstance(t, ast.Name) and t.id == "EFFECT"
                                                 for t in node.targets)
                and isinstance(node.value, ast.Call)):
            call = node.value
            if call.args and isinstance(call.args[0], ast.Constant):
                return str(call.args[0].value)
            for kw in call.keywords:
                if kw.arg == "model" and isinstance(kw.value, ast.Constant):
                    return str(kw.value.value)
    return None


def api_pages() -> dict[str, str]:
    """``{site path: Markdown}`` of the API pages."""
    models = model_names()
    sources = sorted(p for p in PACKAGE.rglob("*.py") if "__pycache__" not in p.parts)
    effects: dict[str, list[str]] = {m: [] for m in models}
    claimed: set[Path] = set()
    for path in sources:
        model = effect_model(path)
        if model in effects:
            effects[model].append(_module_name(path))
            claimed.add(path)
    pages: dict[str, str] = {}
    for model in models:
        modules = [_module_name(p) for p in sources
                   if p not in claimed and p.name != "__init__.py"
                   and p.relative_to(PACKAGE).parts[0] == model]
        claimed.update(p for p in sources if p.relative_to(PACKAGE).parts[0] == model)
        text = [f"# `{model}` API", "",
                f"Generated from the package: the effects of the `{model}` model (each with its "
                "equations) and the modules of `craquelure." + model + "`. The physics and the "
                f"results are on the [model page](../{model}.md).", "", "## Effects", ""]
        text += [f"::: {name}" for name in effects[model]] or ["(none)"]
        text += ["", "## Modules", ""] + [f"::: {name}" for name in modules]
        pages[f"api/{model}.md"] = "\n".join(text) + "\n"
    core = [_module_name(p) for p in sources if p not in claimed and p.name != "__init__.py"]
    pages["api/core.md"] = "\n".join(
        ["# Core API", "",
         "Generated from the package: the modules every model shares (the code generator, the "
         "run loop, scenes, datasets, the validation report, the command line and the shared SPH "
         "numerics).", ""] + [f"::: {name}" for name in core]) + "\n"
    return pages


def generated_pages() -> set[str]:
    """Site paths of the pages the hooks generate (API pages, tutorials): link targets that are
    no file of the repository."""
    api = {f"api/{m}.md" for m in model_names()} | {"api/core.md"}
    return api | {f"tutorials/{p.stem}.md" for p in (ROOT / "docs" / "tutorials").glob("*.ipynb")}


def _site_path(repo_path: str) -> str | None:
    if repo_path in ROOT_PAGES:
        return ROOT_PAGES[repo_path]
    if repo_path.startswith("docs/tutorials/") and repo_path.endswith(".ipynb"):
        return repo_path[len("docs/"):].removesuffix(".ipynb") + ".md"  # its page
    if repo_path.startswith("docs/"):
        return repo_path[len("docs/"):]
    return None


def rewrite_links(markdown: str, repo_path: str, site_path: str) -> str:
    """Relative links of the file at ``repo_path`` (repository-relative) rewritten for its site
    page ``site_path``; missing targets are logged as warnings."""
    out, fenced = [], False
    for line in markdown.split("\n"):
        if _FENCE.match(line.lstrip()):
            fenced = not fenced
        if fenced:
            out.append(line)
            continue

        def fix(m: re.Match) -> str:
            target = m.group(2)
            if re.match(r"^[a-z][a-z0-9+.-]*:", target) or target.startswith("#"):
                return m.group(0)
            path, sep, anchor = target.partition("#")
            repo_target = posixpath.normpath(posixpath.join(posixpath.dirname(repo_path), path))
            full = ROOT / repo_target
            if not full.exists() and _site_path(repo_target) not in generated_pages():
                log.warning("%s links to %s, which does not exist", repo_path, target)
                return m.group(0)
            site_target = _site_path(repo_target)
            if site_target is None and full.is_dir() and repo_target == "docs":
                site_target = "index.md"
            if site_target is None:  # a repository file that is not part of the site
                return f"`{repo_target}`" if not m.group(1).startswith("!") else m.group(0)
            rel = posixpath.relpath(site_target, posixpath.dirname(site_path) or ".")
            return m.group(1) + rel + (sep + anchor if sep else "") + m.group(3)

        out.append(_LINK.sub(fix, line))
    return "\n".join(out)


MATHJAX = "javascripts/mathjax/tex-svg.js"


def mathjax_file() -> Path:
    """MathJax 3's tex-svg component as installed with the docs extra."""
    from importlib.metadata import PackageNotFoundError, distribution

    try:
        files = distribution("sphinx-mathjax-offline").files or []
    except PackageNotFoundError as exc:
        raise RuntimeError("MathJax for the site comes with sphinx-mathjax-offline: "
                           "pip install -e '.[docs]'") from exc
    return Path(next(f for f in files if str(f).endswith("mathjax/tex-svg.js")).locate())


_MARKER = re.compile(
    r"^\{\{[ \t]*(include|verdicts|companions):[ \t]*(\S+)((?:[ \t]+\w+=\S+)*)[ \t]*\}\}"
    r"[ \t]*$", re.M)
# site folder of the figures that validation reports name
FIGURES = "figures"


def _marker_file(kind: str, path: str, where: str) -> Path:
    full = ROOT / path
    if not full.is_file():
        raise PluginError(f"{where}: {{{{ {kind}: {path} }}}}: {path} does not exist")
    return full


def _cell(value) -> str:
    if isinstance(value, float):
        value = f"{value:.4g}"
    elif isinstance(value, (list, tuple)):
        value = ", ".join(_cell(v) for v in value)
    return str(value).replace("|", "\\|").replace("\n", " ")


def plain(text: str) -> str:
    """Text of a report shown as is in Markdown (``t*`` is not emphasis, ``<S>`` no tag)."""
    return (str(text).replace("\\", "\\\\").replace("*", "\\*").replace("_", "\\_")
            .replace("<", "&lt;").replace(">", "&gt;"))


def markdown_table(rows: list[dict]) -> str:
    """A Markdown table of ``rows`` (columns: every key, in order of first appearance)."""
    columns = list(dict.fromkeys(k for row in rows for k in row))
    lines = ["| " + " | ".join(columns) + " |", "|" + "---|" * len(columns)]
    lines += ["| " + " | ".join(_cell(row.get(c, "")) for c in columns) + " |" for row in rows]
    return "\n".join(lines)


def json_table(data) -> str:
    """A JSON benchmark output as a table: a list of rows, or ``{name: value}`` (nested
    mappings become one row each: ``{name: {column: value}}``)."""
    if isinstance(data, dict) and all(isinstance(v, dict) for v in data.values()):
        data = [{"": k, **v} for k, v in data.items()]
    elif isinstance(data, dict):
        data = [{"": k, "value": v} for k, v in data.items()]
    return markdown_table(data)


def figure_path(report: Path, name: str) -> Path | None:
    """The figure a validation row names, if it lies beside the report (or in its
    ``figures/`` folder)."""
    for folder in (report.parent / "figures", report.parent):
        if name and (folder / name).is_file():
            return folder / name
    return None


def also_figures(report: Path, also: str) -> list[Path]:
    """The figures a ``{{ verdicts: ... also=a.png,b.png }}`` marker shows below the rows
    (beside the report, named by no row: e.g. a sensitivity's); one that is not there fails."""
    found = []
    for name in filter(None, also.split(",")):
        fig = figure_path(report, name)
        if fig is None:
            raise PluginError(f"{report.relative_to(ROOT)}: figure {name} (also=) is not beside "
                              "the report")
        found.append(fig)
    return found


def verdicts_table(report: Path, model: str, site_path: str, also: str = "") -> str:
    """A validation report's rows of ``model``: a tally line, then one row per claim, then
    the ``also`` figures (:func:`also_figures`)."""
    data = json.loads(report.read_text())
    rows = [c for c in data.get("claims", []) if c.get("model") == model]
    if not rows:
        raise PluginError(f"{report.relative_to(ROOT)} has no claims of model {model!r}")
    tally = data.get("tally", {}).get(model, {})
    head = (f"Profile **{data.get('profile', '?')}**, from "
            f"`{report.relative_to(ROOT)}`: " + ", ".join(f"{n} {v}" for v, n in tally.items()))
    table = []
    for row in rows:
        fig = figure_path(report, row.get("figure", ""))
        if fig is not None:
            link = posixpath.relpath(f"{FIGURES}/{fig.relative_to(ROOT).as_posix()}",
                                     posixpath.dirname(site_path) or ".")
            shown = f"[![{row['figure']}]({link})]({link})"
        else:
            shown = f"`{row['figure']}`" if row.get("figure") else ""
        table.append({"claim (source)": plain(f"{row['claim']} ({row.get('source', '')})"),
                      "verdict": f"**{row['verdict']}**",
                      "measured": plain(row.get("measured", "")), "figure": shown})
    return "\n\n".join([head + ".", markdown_table(table)]
                       + [_figure_link(f, site_path) for f in also_figures(report, also)])


def _figure_link(fig: Path, site_path: str) -> str:
    link = posixpath.relpath(f"{FIGURES}/{fig.relative_to(ROOT).as_posix()}",
                             posixpath.dirname(site_path) or ".")
    return f"[![{fig.name}]({link})]({link})"


def companion_figures(report: Path) -> list[Path]:
    """The comparison figures of a report's ensemble and its companions, beside the report."""
    return sorted((report.parent / "figures").glob("drying_companions_*.png"))


def companions_section(report: Path, site_path: str) -> str:
    """A validation report's companion ensembles (``companions``): per ensemble its setting and
    rows (verdicts, or why it has none), then the comparison figures beside the report."""
    parts = []
    for c in json.loads(report.read_text()).get("companions", []):
        judged = (", ".join(f"{n} {v}" for v, n in c["tally"]["all"].items()) if c["judged"]
                  else f"not judged: {plain(c['why'])}")
        rows = [{"claim (source)": plain(f"{r['claim']} ({r.get('source', '')})"),
                 "verdict": f"**{r['verdict']}**" if r["verdict"] else "not judged",
                 "measured": plain(r.get("measured", ""))} for r in c["claims"]]
        parts.append(f"**{c['name']}**, {plain(c['setting'])}: {judged}.\n\n"
                     + markdown_table(rows))
    if not parts:
        parts.append(f"No companion ensemble of `{report.relative_to(ROOT)}` is archived.")
    return "\n\n".join(parts + [_figure_link(f, site_path) for f in companion_figures(report)])


def expand_markers(markdown: str, site_path: str) -> str:
    """Replace the ``{{ include: ... }}`` and ``{{ verdicts: ... }}`` lines of a page."""

    def expand(m: re.Match) -> str:
        kind, path = m.group(1), m.group(2)
        options = dict(o.split("=", 1) for o in m.group(3).split())
        full = _marker_file(kind, path, site_path)
        if kind == "verdicts":
            if "model" not in options:
                raise PluginError(f"{site_path}: {{{{ verdicts: {path} }}}} needs model=<model>")
            return verdicts_table(full, options["model"], site_path, options.get("also", ""))
        if kind == "companions":
            return companions_section(full, site_path)
        if full.suffix == ".json":
            return json_table(json.loads(full.read_text()))
        return rewrite_links(full.read_text().rstrip("\n"), path, site_path)

    return _MARKER.sub(expand, markdown)


def marked_figures() -> list[Path]:
    """Every figure that a ``{{ verdicts: ... }}`` or ``{{ companions: ... }}`` marker of a
    page shows."""
    pages = [ROOT / p for p in ROOT_PAGES] + sorted((ROOT / "docs").rglob("*.md"))
    found = []
    for page in filter(Path.is_file, pages):
        for m in _MARKER.finditer(page.read_text()):
            report = ROOT / m.group(2)
            if m.group(1) == "verdicts" and report.is_file():
                found += [f for c in json.loads(report.read_text()).get("claims", [])
                          if (f := figure_path(report, c.get("figure", ""))) is not None]
                options = dict(o.split("=", 1) for o in m.group(3).split())
                found += also_figures(report, options.get("also", ""))
            if m.group(1) == "companions" and report.is_file():
                found += companion_figures(report)
    return sorted(set(found))


def notebook_markdown(path: Path, execute: bool = True) -> str:
    """A tutorial notebook as a page: its Markdown cells, its code cells as Python blocks and
    their outputs (text, and images inline), after executing it in a temporary folder."""
    import nbformat

    nb = nbformat.read(path, as_version=4)
    if execute:
        from nbclient import NotebookClient
        from nbclient.exceptions import CellExecutionError

        with tempfile.TemporaryDirectory() as tmp:
            try:
                NotebookClient(nb, timeout=600, kernel_name="python3",
                               resources={"metadata": {"path": tmp}}).execute()
            except CellExecutionError as exc:
                raise PluginError(f"{path.relative_to(ROOT)}: a cell failed:\n{exc}") from exc
    out = []
    for cell in nb.cells:
        if cell.cell_type == "markdown":
            out.append(cell.source)
            continue
        if cell.cell_type != "code":
            continue
        out.append(f"```python\n{cell.source}\n```")
        for o in cell.get("outputs", []):
            data = o.get("data", {})
            if o.get("output_type") == "stream" and o.get("name") == "stdout":
                out.append(f"```text\n{o['text'].rstrip()}\n```")
            elif "image/png" in data:
                png = data["image/png"]
                png = png if isinstance(png, str) else base64.b64encode(png).decode()
                out.append(f"![output](data:image/png;base64,{png.replace(chr(10), '')})")
            elif "text/plain" in data:
                out.append(f"```text\n{data['text/plain'].rstrip()}\n```")
            elif o.get("output_type") == "error":
                raise PluginError(f"{path.relative_to(ROOT)}: stored error output")
    return "\n\n".join(out) + "\n"


def on_files(files: Files, config) -> Files:
    files.append(File.generated(config, MATHJAX, abs_src_path=str(mathjax_file())))
    for fig in marked_figures():
        files.append(File.generated(config, f"{FIGURES}/{fig.relative_to(ROOT).as_posix()}",
                                    abs_src_path=str(fig)))
    execute = os.environ.get("CRAQUELURE_DOCS_EXECUTE", "1") != "0"
    for nb in sorted((ROOT / "docs" / "tutorials").glob("*.ipynb")):
        site_path = f"tutorials/{nb.stem}.md"
        log.info("executing %s", nb.relative_to(ROOT))
        files.append(File.generated(config, site_path, content=notebook_markdown(nb, execute)))
    for repo_path, site_path in ROOT_PAGES.items():
        text = (ROOT / repo_path).read_text()
        files.append(File.generated(config, site_path,
                                    content=rewrite_links(text, repo_path, site_path)))
    for site_path, text in api_pages().items():
        files.append(File.generated(config, site_path, content=text))
    return files


def on_page_markdown(markdown: str, page, config, files) -> str:
    src = page.file.src_uri
    if src.startswith(("api/", "tutorials/")):
        return markdown
    if src not in ROOT_PAGES.values():  # the root pages are rewritten when generated
        markdown = rewrite_links(markdown, "docs/" + src, src)
    return expand_markers(markdown, src)
