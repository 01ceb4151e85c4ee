"""Snakemake script of rule drying_thickness_figure: <S> against H (PNG + PDF) from the sweep
dataset; nothing is simulated here.

Outside Snakemake: ``python workflow/scripts/drying_thickness_figure.py SWEEP.nc OUT.png PROFILE``.
"""

import sys

from craquelure.drying.figures import fig_thickness, save_figure
from craquelure.io import open_dataset


def main(sweep: str, png: str, profile: str) -> None:
    written = save_figure(fig_thickness(open_dataset(sweep), profile), png)
    print("wrote " + ", ".join(map(str, written)))


if "snakemake" in globals():
    with open(snakemake.log[0], "w") as log:  # noqa: F821
        sys.stdout = sys.stderr = log
        main(snakemake.input[0], snakemake.output.png, snakemake.params.profile)  # noqa: F821
elif __name__ == "__main__":
    main(*sys.argv[1:4])
