"""Snakemake script of rule drying_validation: the drying rows of the validation report
(:mod:`craquelure.drying.claims`) from the drying claim sources alone, so that a drying
campaign's rows come out without the other models' runs.

Outside Snakemake: ``python workflow/scripts/drying_validation.py OUT.json PROFILE SOURCE ...``.
"""

import sys

from craquelure import validation


def main(out: str, profile: str, sources: list[str]) -> None:
    claims = validation.collect({"drying": sources})
    validation.write_json(claims, out, profile, {"drying": sources})
    for c in claims:
        print(f"[{c.model}] {c.verdict:>14}: {c.claim} | {c.measured} | {c.note}")


if "snakemake" in globals():
    with open(snakemake.log[0], "w") as log:  # noqa: F821
        sys.stdout = sys.stderr = log
        main(snakemake.output[0], snakemake.params.profile,  # noqa: F821
             list(snakemake.input))  # noqa: F821
elif __name__ == "__main__":
    main(sys.argv[1], sys.argv[2], sys.argv[3:])
