# Archived drying ensembles (results/published/<name>/, committed; src/craquelure/drying/
# published.py): rule drying_published rebuilds the paper's figures, the summary with checks
# 14-16 for both labellings and the validation rows from the committed tables, without a
# simulation (target `published`; CI runs it). An ensemble whose provenance names companions
# (config drying.companions) shows those that are archived beside it: their rows in its
# validation report, and rule drying_published_companions draws Fig. 3 and Figs. 4-6 for all
# of them. Rule drying_publish_tables writes the tables of a finished ensemble of any drying
# scene; `make publish` installs both in the folder.
from craquelure.drying.figures import COMPARISON

PUBLISHED_DRYING = glob_wildcards("results/published/{name}/tables/common.json").name
# Archived check 12 of the impact campaign (craquelure.impact.published): rule impact_published
# decides it again from the committed summaries' per-run measurements.
PUBLISHED_IMPACT = glob_wildcards("results/published/{name}/summary_rate.json").name
PUBLISHED_OUTPUTS = ["summary.json", "validation.json", "validation.html"] + [
    f"figures/drying_{name}.png" for name in DRYING_FIGURES
]
COMPANION_OUTPUTS = [f"figures/drying_companions_{name}.png" for name in COMPARISON] + [
    "figures/drying_companions.json"
]


localrules:
    drying_published,
    drying_published_companions,
    drying_publish_tables,
    impact_published,
    published,


rule drying_published:
    input:
        tables="results/published/{name}/tables/seeds.csv",
        snapshots="results/published/{name}/snapshots.nc",
        provenance="results/published/{name}/provenance.json",
        companions=lambda wildcards: [
            f"{folder}/summary.json"
            for folder in drying_workflow.rebuilt_with_companions(wildcards)[1:]
        ],
    output:
        [f"results/drying_published/{{name}}/{path}" for path in PUBLISHED_OUTPUTS],
        campaigns=[
            f"results/drying_published/{{name}}/campaign_{labelling}.nc"
            for labelling in ("periodic", "open")
        ],
    params:
        published=lambda wildcards, input: Path(input.tables).parents[1],
        outdir=lambda wildcards, output: Path(output[0]).parent,
    log:
        "logs/drying_published/{name}.log",
    threads: 1
    resources:
        mem_mb=2000,
        runtime=30,
    script:
        "../scripts/drying_published.py"


rule drying_published_companions:
    input:
        lambda wildcards: [
            f"{folder}/{path}"
            for folder in drying_workflow.rebuilt_with_companions(wildcards)
            for path in ("summary.json", "campaign_periodic.nc", "campaign_open.nc")
        ],
    output:
        [f"results/drying_published/{{name}}/{path}" for path in COMPANION_OUTPUTS],
    params:
        outdir=lambda wildcards, output: Path(output[0]).parents[1],
        rebuilt=drying_workflow.rebuilt_with_companions,
    log:
        "logs/drying_published_companions/{name}.log",
    threads: 1
    resources:
        mem_mb=2000,
        runtime=30,
    script:
        "../scripts/drying_published_companions.py"


rule impact_published:
    input:
        "results/published/{name}/summary.json",
        "results/published/{name}/summary_rate.json",
        "results/published/{name}/provenance.json",
    output:
        [
            f"results/impact_published/{{name}}/{path}"
            for path in ("summary.json", "summary_rate.json", "validation.json")
        ],
    params:
        published=lambda wildcards, input: Path(input[0]).parent,
        outdir=lambda wildcards, output: Path(output[0]).parent,
    log:
        "logs/impact_published/{name}.log",
    threads: 1
    resources:
        mem_mb=1000,
        runtime=5,
    script:
        "../scripts/impact_published.py"


rule published:
    input:
        [f"results/impact_published/{name}/validation.json" for name in PUBLISHED_IMPACT],
        [
            f"results/drying_published/{name}/{path}"
            for name in PUBLISHED_DRYING
            for path in PUBLISHED_OUTPUTS
        ],
        [
            f"results/drying_published/{name}/{path}"
            for name in PUBLISHED_DRYING
            if drying_workflow.published_companions(name)
            for path in COMPANION_OUTPUTS
        ],


rule drying_publish_tables:
    input:
        fragments=DRYING_JOBS.campaign_fragments,
        run=lambda wildcards: f"results/drying/{wildcards.scene}/run/seed{DRYING_JOBS.seeds()[0]}.nc",
    output:
        directory("results/drying/{scene}/published"),
    params:
        profile=config["profile"],
        companions=config["drying"].get("companions", []),
        benchmarks=DRYING_JOBS.publish_benchmarks,
    log:
        "logs/drying_publish_tables/{scene}.log",
    threads: 1
    resources:
        mem_mb=config["drying"]["mem_mb"],
        runtime=config["drying"]["runtime_init"],
    script:
        "../scripts/drying_publish_tables.py"
