# Validation report: every model's claims (craquelure.<model>.claims) computed from the
# analysis outputs the model files registered in CLAIM_SOURCES, one table for the report,
# each claim shown with the figure that decides it (claim_figures).


# Aggregation, figure and report rules: seconds each, run by the submitting Snakemake
# process instead of waiting in a cluster queue.
localrules:
    validation_report,


rule validation_report:
    input:
        unpack(claim_sources),
        figures=claim_figures,
    output:
        html=report(
            "results/validation.html",
            caption="../report/validation.rst",
            category="Validation",
            labels={"table": "claims, measured, verdicts"},
        ),
        json="results/validation.json",
        # the same summary as a fragment: the report's first page leads with it
        summary="results/validation_summary.html",
    params:
        profile=config["profile"],
    log:
        "logs/validation_report.log",
    threads: 1
    resources:
        mem_mb=1000,
        runtime=5,
    script:
        "../scripts/validation_report.py"


TARGETS["validation"] = [
    "results/validation.html",
    "results/validation.json",
    "results/validation_summary.html",
]
