"""Figure output shared by the models' figures modules: matplotlib's non-interactive Agg
backend (figures are written by jobs, never shown) and one way to write a figure."""

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def label_axes(ax, xlabel: str | None = None, ylabel: str | None = None,
           legend: dict | None = None) -> None:
    """Set the axis labels given and, with ``legend`` (its keywords), draw the legend."""
    if xlabel is not None:
        ax.set_xlabel(xlabel)
    if ylabel is not None:
        ax.set_ylabel(ylabel)
    if legend is not None:
        ax.legend(**legend)


def save(fig, path: str | Path, *, dpi: int = 120, tight: bool = True, pdf: bool = False) -> Path:
    """Write ``fig`` to ``path`` (its folder created; ``tight``: tight layout first; ``pdf``:
    also a PDF beside it with the same stem) and close it."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    if tight:
        fig.tight_layout()
    fig.savefig(path, dpi=dpi)
    if pdf:
        fig.savefig(path.with_suffix(".pdf"))
    plt.close(fig)
    return path
