"""Snakemake script of rule drying_accuracy_figure: error versus wall time (PNG + PDF) from the
dataset of rule drying_accuracy; nothing is simulated here.

Outside Snakemake: ``python workflow/scripts/drying_accuracy_figure.py STUDY.nc OUT.png PROFILE``.
"""

import sys

from craquelure.drying.figures import fig_accuracy, save_figure
from craquelure.io import open_dataset


def main(study: str, png: str, profile: str) -> None:
    written = save_figure(fig_accuracy(open_dataset(study), profile), png)
    print("wrote " + ", ".join(map(str, written)))


if "snakemake" in globals():
    with open(snakemake.log[0], "w") as log:  # noqa: F821
        sys.stdout = sys.stderr = log
        main(snakemake.input[0], snakemake.output.png, snakemake.params.profile)  # noqa: F821
elif __name__ == "__main__":
    main(*sys.argv[1:4])
