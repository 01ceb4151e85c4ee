"""Snakemake script of rule drying_speed: fragment datasets grouped by drying speed -> the study
dataset of :func:`craquelure.drying.speed.speed_study` (with provenance).

Outside Snakemake: ``python workflow/scripts/drying_speed.py OUT.nc FIXED PI=FRAG.nc ...``,
FIXED the comma-separated t/t* of the fragment densities.
"""

import sys
from collections import defaultdict

from craquelure.drying.analysis import grouped_study
from craquelure.drying.speed import speed_study
from craquelure.io import write_dataset


def main(groups: dict[str, list[str]], out: str, fixed: list[float]) -> None:
    study = grouped_study(groups, lambda fragments: speed_study(fragments, fixed))
    write_dataset(study, out)
    print(f"wrote {out}: Pi = {', '.join(f'{v:.3g}' for v in study['speed'].values)}; all "
          f"samples broken at {', '.join(f'{v:.2f}' for v in study['all_samples_broken'].values)}"
          f" t*")


if "snakemake" in globals():
    with open(snakemake.log[0], "w") as log:  # noqa: F821
        sys.stdout = sys.stderr = log
        inputs = snakemake.input  # noqa: F821
        main({key: list(inputs[key]) for key in inputs.keys()}, snakemake.output[0],  # noqa: F821
             [float(v) for v in snakemake.params.fixed])  # noqa: F821
elif __name__ == "__main__":
    by_pi: dict[str, list[str]] = defaultdict(list)
    for item in sys.argv[3:]:
        value, path = item.split("=", 1)
        by_pi[value].append(path)
    main(dict(by_pi), sys.argv[1], [float(v) for v in sys.argv[2].split(",")])
