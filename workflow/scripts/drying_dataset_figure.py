"""Snakemake script of rules drying_accuracy_figure, drying_thickness_figure,
drying_speed_figure, drying_kappa_figure and drying_transition_figure: one figure
(PNG + PDF) from one analysis dataset; nothing is simulated here.

Outside Snakemake:
``python workflow/scripts/drying_dataset_figure.py FIGURE DATASET.nc OUT.png PROFILE``, FIGURE one
of accuracy, thickness, speed, kappa, transition.
"""

import sys

from craquelure.drying.figures import (
    fig_accuracy,
    fig_kappa,
    fig_speed,
    fig_thickness,
    fig_transition,
    save_figure,
)
from craquelure.io import open_dataset

FIGURES = {"accuracy": fig_accuracy, "thickness": fig_thickness, "speed": fig_speed,
           "kappa": fig_kappa, "transition": fig_transition}


def main(figure: str, dataset: str, png: str, profile: str) -> None:
    written = save_figure(FIGURES[figure](open_dataset(dataset), profile), png)
    print("wrote " + ", ".join(map(str, written)))


if "snakemake" in globals():
    with open(snakemake.log[0], "w") as log:  # noqa: F821
        sys.stdout = sys.stderr = log
        main(snakemake.params.figure, snakemake.input[0], snakemake.output.png,  # noqa: F821
             snakemake.params.profile)  # noqa: F821
elif __name__ == "__main__":
    main(*sys.argv[1:5])
