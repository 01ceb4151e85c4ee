"""Render frames of a ``craquelure export`` time series (.pvd of VTU point clouds) the way a
ParaView point-Gaussian view shows them: each particle a dot coloured by one point field.

It reads only the exported files (the .pvd and its VTU frames, with meshio), never the run
dataset, so the picture shows what ParaView or OVITO would load. Rendered with matplotlib;
this is not ParaView itself.

    python docs/render_export.py RUN.pvd --field mean_stress --out picture.png [--frames 3]
"""

from __future__ import annotations

import argparse
import xml.etree.ElementTree as ET
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import meshio  # noqa: E402
import numpy as np  # noqa: E402


def frames(pvd: Path) -> list[tuple[float, Path]]:
    entries = ET.parse(pvd).getroot().find("Collection").findall("DataSet")
    return [(float(e.get("timestep")), pvd.parent / e.get("file")) for e in entries]


def render(pvd: Path, field: str, out: Path, n_frames: int) -> None:
    series = frames(pvd)
    picks = np.unique(np.linspace(0, len(series) - 1, n_frames).round().astype(int))
    meshes = [(series[k][0], meshio.read(series[k][1])) for k in picks]
    values = np.concatenate([m.point_data[field].ravel() for _, m in meshes])
    lo, hi = np.percentile(values, [1, 99])
    fig, axes = plt.subplots(1, len(meshes), figsize=(4.2 * len(meshes), 4.6),
                             facecolor="#323440", squeeze=False)
    for ax, (time, mesh) in zip(axes[0], meshes, strict=True):
        shown = np.ones(len(mesh.points), bool)
        if "alive" in mesh.point_data:  # removed particles are hidden, as a threshold filter
            shown = mesh.point_data["alive"].ravel() > 0
        pts = mesh.points[shown]
        sc = ax.scatter(pts[:, 0], pts[:, 1], c=mesh.point_data[field].ravel()[shown],
                        s=1.2, cmap="coolwarm", vmin=lo, vmax=hi, linewidths=0)
        ax.set_aspect("equal")
        ax.set_facecolor("#323440")
        ax.set_xticks([])
        ax.set_yticks([])
        ax.set_title(f"t = {time:.4g}, {shown.sum()} particles", color="white", fontsize=10)
    cbar = fig.colorbar(sc, ax=axes[0].tolist(), shrink=0.8, pad=0.02)
    cbar.set_label(field, color="white")
    cbar.ax.tick_params(colors="white")
    fig.suptitle(f"{pvd.name}: point field '{field}' (from the exported VTU frames)",
                 color="white", fontsize=11)
    fig.savefig(out, dpi=110, facecolor=fig.get_facecolor(), bbox_inches="tight")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("pvd", type=Path)
    parser.add_argument("--field", default="mean_stress")
    parser.add_argument("--out", type=Path, required=True)
    parser.add_argument("--frames", type=int, default=3)
    args = parser.parse_args()
    render(args.pvd, args.field, args.out, args.frames)


if __name__ == "__main__":
    main()
