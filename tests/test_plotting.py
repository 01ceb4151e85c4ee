"""One way to write a figure: PNG (and optionally a PDF beside it) in a folder created on
demand, with the figure closed afterwards (a job drawing many figures does not accumulate
them)."""

import matplotlib.pyplot as plt

from craquelure import plotting


def test_save_writes_png_and_pdf_and_closes_the_figure(tmp_path):
    before = set(plt.get_fignums())
    fig, ax = plt.subplots()
    ax.plot([0, 1], [1, 0])
    out = plotting.save(fig, tmp_path / "deep" / "folder" / "line.png", pdf=True)
    assert out == tmp_path / "deep" / "folder" / "line.png"
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert out.with_suffix(".pdf").read_bytes()[:5] == b"%PDF-"
    assert set(plt.get_fignums()) == before


def test_backend_is_non_interactive():
    assert plt.get_backend().lower() == "agg"
