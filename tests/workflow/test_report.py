"""The Snakemake report's first page (workflow/report/workflow.rst), rendered as Snakemake
renders it (Jinja, then docutils): it leads with the validation summary when the report holds
the validation page, and is plain text when it does not."""

from __future__ import annotations

import os
from types import SimpleNamespace

from docutils.core import publish_parts
from jinja2 import Environment

from craquelure.scene import project_root

ROOT = project_root()


def render(tmp_path, files) -> str:
    text = (ROOT / "workflow" / "report" / "workflow.rst").read_text()
    snakemake = SimpleNamespace(config={"profile": "ci"})
    cwd = os.getcwd()
    os.chdir(tmp_path)  # Snakemake renders in the working directory: results/ is relative
    try:
        rst = Environment().from_string(text).render(snakemake=snakemake, categories={},
                                                     files=files)
        return publish_parts(rst, writer="html")["html_body"]
    finally:
        os.chdir(cwd)


def test_first_page_leads_with_the_validation_summary(tmp_path):
    (tmp_path / "results").mkdir()
    summary = '<section class="cq-summary"><table class="cq-table"></table></section>'
    (tmp_path / "results" / "validation_summary.html").write_text(summary)
    page = render(tmp_path, [SimpleNamespace(target="validation.html")])
    assert summary in page
    assert page.index("cq-summary") < page.index("craquelure reproduces four particle models")
    assert ".prose:has(.cq-summary) { max-width: none; }" in page  # full width, graph below


def test_without_the_validation_page_the_first_page_is_the_description(tmp_path):
    page = render(tmp_path, [SimpleNamespace(target="drying_speed.png")])
    assert "cq-summary" not in page and "System Message" not in page
    assert "craquelure reproduces four particle models" in page
