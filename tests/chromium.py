"""What a reader sees on the first screen of a page, measured in headless Chromium.

``first_screen(page)`` opens a copy of ``page`` (an HTML file) in Debian's Chromium at a
1280 x 800 viewport with a measuring script added at its end; the script waits until the
validation summary (``.cq-summary``) is in the document (the Snakemake report builds its pages
with JavaScript), decodes every embedded figure and writes the bounding boxes of the summary's
tables, rows and thumbnails into the DOM, which ``--dump-dom`` prints. Tests skip with the
reason where Chromium is missing (``.ci/run`` installs it where it can).
"""

from __future__ import annotations

import html
import json
import re
import shutil
import subprocess
import tempfile
from pathlib import Path

import pytest

VIEWPORT = (1280, 800)
CANDIDATES = ("/usr/bin/chromium", "chromium", "chromium-browser")
FLAGS = ("--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync",
         "--hide-scrollbars", "--mute-audio")

_MEASURE = """
<script>
(function () {
  function box(el) {
    const r = el.getBoundingClientRect();
    return {top: r.top, left: r.left, bottom: r.bottom, right: r.right,
            width: r.width, height: r.height};
  }
  function urls(el) {
    const m = getComputedStyle(el).backgroundImage.match(/url\\("?(data:[^")]+)"?\\)/);
    return m ? m[1] : null;
  }
  function report(out) {
    const pre = document.createElement("pre");
    pre.id = "cq-measure";
    pre.textContent = JSON.stringify(out);
    document.documentElement.appendChild(pre);
  }
  let tries = 0;
  function measure() {
    const summary = document.querySelector(".cq-summary");
    if (!summary) {
      if (++tries < 200) { setTimeout(measure, 50); return; }
      report({found: false}); return;
    }
    const thumbs = Array.from(summary.querySelectorAll(".cq-thumb"));
    const sources = Array.from(new Set(thumbs.map(urls).filter(Boolean)));
    Promise.all(sources.map(src => new Promise(done => {
      const img = new Image();
      img.onload = () => done(img.naturalWidth > 0);
      img.onerror = () => done(false);
      img.src = src;
    }))).then(decoded => report({
      found: true,
      viewport: [window.innerWidth, window.innerHeight],
      summary: box(summary),
      tables: Array.from(summary.querySelectorAll("table.cq-table")).map(box),
      rows: Array.from(summary.querySelectorAll("tr.cq-row")).map(box),
      badges: Array.from(summary.querySelectorAll("tr.cq-row .cq-badge")).map(box),
      thumbs: thumbs.map(t => Object.assign(box(t), {figure: urls(t) !== null})),
      figures_decoded: decoded,
      details_open: summary.querySelectorAll("details[open]").length,
      details: summary.querySelectorAll("tr.cq-row details").length,
    }));
  }
  if (document.readyState === "complete") measure();
  else window.addEventListener("load", measure);
})();
</script>
"""


def chromium() -> str | None:
    for name in CANDIDATES:
        path = shutil.which(name)
        if path:
            return path
    return None


def require_chromium() -> str:
    path = chromium()
    if path is None:
        pytest.skip("Chromium is missing (Debian: apt-get install chromium); the first-screen "
                    "check of the validation page and the report needs a real browser")
    return path


def _measure(browser: str, page: Path, size: tuple[int, int], timeout: float) -> dict:
    with tempfile.TemporaryDirectory() as tmp:
        copy = page.with_name(f".{page.stem}.measure{page.suffix}")  # beside it: same relative
        text = page.read_text()                                     # links
        end = text.rfind("</body>")  # the last: embedded data may hold the string too
        text = text[:end] + _MEASURE + text[end:] if end >= 0 else text + _MEASURE
        copy.write_text(text)
        try:
            proc = subprocess.run(
                [browser, *FLAGS, f"--user-data-dir={tmp}/profile",
                 f"--window-size={size[0]},{size[1]}", "--virtual-time-budget=20000",
                 "--dump-dom", copy.as_uri()],
                capture_output=True, text=True, timeout=timeout)
        finally:
            copy.unlink()
    m = re.search(r'<pre id="cq-measure">(.*?)</pre>', proc.stdout, re.S)
    assert m, f"no measurement (exit {proc.returncode}): {proc.stderr[-2000:]}"
    return json.loads(html.unescape(m.group(1)))


def first_screen(page: Path, timeout: float = 120) -> dict:
    """Bounding boxes (CSS pixels, relative to the 1280 x 800 viewport) of the validation
    summary on the page as first opened; ``found`` is False if the page never shows it.
    Headless Chromium's window is larger than its viewport by what it reserves for a browser's
    frame; a first run measures that and, if needed, a second one opens the page at the
    window size whose viewport is 1280 x 800."""
    browser = require_chromium()
    seen = _measure(browser, page, VIEWPORT, timeout)
    if seen.get("viewport", list(VIEWPORT)) != list(VIEWPORT):
        w, h = seen["viewport"]
        size = (2 * VIEWPORT[0] - w, 2 * VIEWPORT[1] - h)
        seen = _measure(browser, page, size, timeout)
    return seen


def on_screen(box: dict, viewport=VIEWPORT) -> bool:
    """Wholly inside the first screen."""
    return (box["width"] > 0 and box["height"] > 0 and box["top"] >= 0 and box["left"] >= 0
            and box["bottom"] <= viewport[1] and box["right"] <= viewport[0])
