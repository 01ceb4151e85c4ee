"""Validation report: the papers' claims with measurements and verdicts (craquelure.validation)."""

import sys

from craquelure import validation

if "snakemake" in globals():
    sys.stderr = sys.stdout = open(snakemake.log[0], "w")  # noqa: F821, SIM115
    sources = {model: list(snakemake.input[model]) for model in validation.MODELS  # noqa: F821
               if model in snakemake.input.keys()}  # noqa: F821
    claims = validation.collect(sources)
    validation.write_json(claims, snakemake.output.json, snakemake.params.profile,  # noqa: F821
                          sources)
    figures = list(snakemake.input.figures)  # noqa: F821
    validation.write_html(claims, snakemake.output.html, snakemake.params.profile,  # noqa: F821
                          figures)
    validation.write_summary(claims, snakemake.output.summary,  # noqa: F821
                             snakemake.params.profile, figures)  # noqa: F821
    for c in claims:
        print(f"[{c.model}] {c.verdict:>14}: {c.claim} | {c.measured}")
