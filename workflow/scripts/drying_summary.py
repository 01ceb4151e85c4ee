"""Snakemake script of rule drying_summary: statistics of the campaign dataset (alpha with its
bootstrap interval, 1/<S>_t fit, onset, collapse; spec checks 14-16 with their power and
verdicts, and the run's Pi = tau/t*) to summary.json.

Outside Snakemake: ``python workflow/scripts/drying_summary.py CAMPAIGN.nc OUT.json PROFILE
[SCENE [CAMPAIGN_OPEN.nc]]`` (the second campaign: the open-image labelling, judged as well).
"""

import sys

from craquelure.drying.summary import write_summary


def main(campaign: str, out: str, profile: str, scene: str = "",
         open_campaign: str | None = None) -> None:
    summary = write_summary(campaign, out, profile=profile, scene_name=scene,
                            open_campaign_path=open_campaign)
    checks = summary["checks"]
    verdicts = ", ".join(f"{key.split('_')[0]} {checks[key]['verdict']} ({checks[key]['note']})"
                         for key in ("check14_inverse_mean_area_linear",
                                     "check15_scaling_collapse", "check16_onset"))
    print(f"wrote {out}: Pi = tau/t* = {summary['pi']}, alpha = {summary['fit'].get('alpha')}; "
          f"{verdicts}")


if "snakemake" in globals():
    with open(snakemake.log[0], "w") as log:  # noqa: F821
        sys.stdout = sys.stderr = log
        main(snakemake.input.campaign, snakemake.output[0], snakemake.params.profile,  # noqa: F821
             snakemake.params.scene, snakemake.input.open)  # noqa: F821
elif __name__ == "__main__":
    main(*sys.argv[1:])
