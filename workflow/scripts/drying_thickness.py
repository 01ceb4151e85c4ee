"""Snakemake script of rule drying_thickness: fragment datasets grouped by layer thickness ->
the sweep dataset of :func:`craquelure.drying.thickness.thickness_sweep` (with provenance).

Outside Snakemake: ``python workflow/scripts/drying_thickness.py OUT.nc H=FRAG.nc [H=FRAG.nc ...]``.
"""

import sys
from collections import defaultdict

from craquelure.drying.analysis import grouped_study
from craquelure.drying.thickness import thickness_sweep
from craquelure.io import write_dataset


def main(groups: dict[float, list[str]], out: str) -> None:
    sweep = grouped_study(groups, thickness_sweep)
    write_dataset(sweep, out)
    print(f"wrote {out}: exponent (late mean) {sweep.attrs['exponent_late_mean']:.3g} "
          f"+- {sweep.attrs['exponent_late_std']:.2g} over {sweep.attrs['n_late_times']} times")


if "snakemake" in globals():
    with open(snakemake.log[0], "w") as log:  # noqa: F821
        sys.stdout = sys.stderr = log
        inputs = snakemake.input  # noqa: F821
        # Input names are H<value> with the decimal point spelled p (rule drying_thickness).
        main({float(key[1:].replace("p", ".")): list(inputs[key]) for key in inputs.keys()},
             snakemake.output[0])  # noqa: F821
elif __name__ == "__main__":
    by_h: dict[float, list[str]] = defaultdict(list)
    for item in sys.argv[2:]:
        value, path = item.split("=", 1)
        by_h[float(value)].append(path)
    main(dict(by_h), sys.argv[1])
