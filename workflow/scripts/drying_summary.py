"""Snakemake script of rule drying_summary: statistics of the campaign dataset (alpha with its
bootstrap interval, 1/<S>_t fit, onset, collapse; spec checks 14-15) to summary.json.

Outside Snakemake: ``python workflow/scripts/drying_summary.py CAMPAIGN.nc OUT.json PROFILE``.
"""

import sys

from craquelure.drying.statistics import write_summary


def main(campaign: str, out: str, profile: str, scene: str = "") -> None:
    summary = write_summary(campaign, out, profile=profile, scene_name=scene)
    checks = summary["checks"]
    print(f"wrote {out}: alpha = {summary['fit'].get('alpha')}, R^2 = {summary['fit'].get('r2')}"
          f", check 14 pass = {checks['check14_inverse_mean_area_linear']['pass']}, "
          f"check 15 pass = {checks['check15_scaling_collapse']['pass']}")


if "snakemake" in globals():
    with open(snakemake.log[0], "w") as log:  # noqa: F821
        sys.stdout = sys.stderr = log
        main(snakemake.input[0], snakemake.output[0], snakemake.params.profile,  # noqa: F821
             snakemake.params.scene)  # noqa: F821
elif __name__ == "__main__":
    main(*sys.argv[1:])
