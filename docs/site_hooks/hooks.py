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
"""

from __future__ import annotations

import ast
import logging
import posixpath
import re
from pathlib import Path

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


def _site_path(repo_path: str) -> str | None:
    if repo_path in ROOT_PAGES:
        return ROOT_PAGES[repo_path]
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
            if not full.exists():
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


def on_files(files: Files, config) -> Files:
    files.append(File.generated(config, MATHJAX, abs_src_path=str(mathjax_file())))
    for repo_path, site_path in ROOT_PAGES.items():
        text = (ROOT / repo_path).read_text()
        files.append(File.generated(config, site_path,
                                    content=rewrite_links(text, repo_path, site_path)))
    for site_path, text in api_pages().items():
        files.append(File.generated(config, site_path, content=text))
    return files


def on_page_markdown(markdown: str, page, config, files) -> str:
    src = page.file.src_uri
    if src in ROOT_PAGES.values() or src.startswith("api/"):
        return markdown  # the generated pages are rewritten when generated
    return rewrite_links(markdown, "docs/" + src, src)
