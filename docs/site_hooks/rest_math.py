"""Griffe extension: the package's reST docstrings as Markdown for the documentation site.

The docstrings are written for reST (``.. math::`` blocks, ``:math:`` roles, ``:func:`` and other
roles, double-backtick literals). mkdocstrings renders docstrings as Markdown, so this extension
rewrites them on load: math into pymdownx.arithmatex's generic form (``\\(...\\)`` inline,
``\\[...\\]`` blocks, typeset by MathJax in the browser), roles and literals into code spans.
"""

from __future__ import annotations

import re

import griffe

_ROLE = re.compile(r":(?:py:)?(?:func|class|mod|meth|data|attr|obj|exc|const):`~?([^`]+)`")
_MATH_ROLE = re.compile(r":math:`([^`]+)`")
_LITERAL = re.compile(r"``(.+?)``")
_DIRECTIVE = re.compile(r"^(?P<indent>[ \t]*)\.\. math::[ \t]*(?P<rest>.*)$")


def _math_blocks(text: str) -> str:
    """Every ``.. math::`` directive (same-line content and its indented body) as display math;
    equations separated by blank lines in the body become separate blocks."""
    lines = text.split("\n")
    out: list[str] = []
    i = 0
    while i < len(lines):
        m = _DIRECTIVE.match(lines[i])
        if not m:
            out.append(lines[i])
            i += 1
            continue
        indent = len(m.group("indent").expandtabs())
        body: list[str] = [m.group("rest")] if m.group("rest").strip() else []
        i += 1
        while i < len(lines):
            line = lines[i]
            if line.strip() and len(line) - len(line.lstrip()) <= indent:
                break
            body.append(line.strip())
            i += 1
        equations: list[list[str]] = [[]]
        for line in body:
            if re.match(r":\w+:", line):
                continue  # directive options (:label: ...)
            if line:
                equations[-1].append(line)
            elif equations[-1]:
                equations.append([])
        pad = " " * indent
        for eq in (e for e in equations if e):
            out.extend(["", pad + "\\[", *(pad + line for line in eq), pad + "\\]", ""])
    return "\n".join(out)


def rest_to_markdown(text: str) -> str:
    text = _math_blocks(text)
    text = _MATH_ROLE.sub(lambda m: "\\(" + m.group(1) + "\\)", text)
    text = _ROLE.sub(lambda m: "`" + m.group(1) + "`", text)
    return _LITERAL.sub(lambda m: "`" + m.group(1) + "`", text)


class RestMath(griffe.Extension):
    """Rewrites every docstring of every loaded object (see the module docstring)."""

    def on_object(self, *, obj: griffe.Object, **kwargs) -> None:
        if obj.docstring is not None:
            obj.docstring.value = rest_to_markdown(obj.docstring.value)
