"""Snakemake script of rule drying_transition: fragment datasets grouped by scene (one box size
each) -> the damage-to-fragmentation transition dataset of
:func:`craquelure.drying.transition.transition` (with provenance).

Outside Snakemake:
``python workflow/scripts/drying_transition.py OUT.nc VARIANT SCENE=FRAG.nc [SCENE=FRAG.nc ...]``.
"""

import sys
from collections import defaultdict

from craquelure.drying.analysis import grouped_study
from craquelure.drying.transition import transition
from craquelure.io import write_dataset


def main(groups: dict[str, list[str]], out: str, variant: str) -> None:
    ds = grouped_study(groups, lambda fragments: transition(fragments, variant))
    write_dataset(ds, out)
    print(f"wrote {out}: d_c = {ds.attrs['d_c']:.4g} {ds.attrs['d_c_ci95']}, beta/nu = "
          f"{ds.attrs['beta_over_nu']:.3g}, gamma/nu = {ds.attrs['gamma_over_nu']:.3g}, "
          f"1/nu = {ds.attrs['one_over_nu']:.3g}")


if "snakemake" in globals():
    with open(snakemake.log[0], "w") as log:  # noqa: F821
        sys.stdout = sys.stderr = log
        inputs = snakemake.input  # noqa: F821
        main({key: list(inputs[key]) for key in inputs.keys()}, snakemake.output[0],  # noqa: F821
             snakemake.params.variant)  # noqa: F821
elif __name__ == "__main__":
    by_scene: dict[str, list[str]] = defaultdict(list)
    for item in sys.argv[3:]:
        scene, path = item.split("=", 1)
        by_scene[scene].append(path)
    main(dict(by_scene), sys.argv[1], sys.argv[2])
