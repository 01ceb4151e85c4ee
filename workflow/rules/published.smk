# Archived drying ensembles (results/published/<name>/, committed; src/craquelure/drying/
# published.py): rule drying_published rebuilds the paper's figures, the summary with checks
# 14-16 for both labellings and the validation rows from the committed tables, without a
# simulation (target `published`; CI runs it). Rule drying_publish_tables writes the tables of
# a finished ensemble of the config's drying scene; `make publish` installs both in the folder.
PUBLISHED_DRYING = glob_wildcards("results/published/{name}/tables/common.json").name
PUBLISHED_OUTPUTS = ["summary.json", "validation.json", "validation.html"] + [
    f"figures/drying_{name}.png" for name in DRYING_FIGURES
]


localrules:
    drying_published,
    drying_publish_tables,
    published,


rule drying_published:
    input:
        tables="results/published/{name}/tables/seeds.csv",
        snapshots="results/published/{name}/snapshots.nc",
        provenance="results/published/{name}/provenance.json",
    output:
        [f"results/drying_published/{{name}}/{path}" for path in PUBLISHED_OUTPUTS],
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


rule published:
    input:
        [
            f"results/drying_published/{name}/{path}"
            for name in PUBLISHED_DRYING
            for path in PUBLISHED_OUTPUTS
        ],


rule drying_publish_tables:
    input:
        fragments=DRYING_JOBS.campaign_fragments,
        run=lambda wildcards: f"results/drying/{wildcards.scene}/run/seed{DRYING_JOBS.seeds()[0]}.nc",
    output:
        directory("results/drying/{scene}/published"),
    params:
        profile=config["profile"],
        benchmarks=lambda wildcards: {
            kind: [
                f"benchmarks/results/{kind}/{wildcards.scene}/seed{seed}.tsv"
                for seed in DRYING_JOBS.seeds()
            ]
            for kind in ("mass_consistency", "drying_run", "drying_fragments")
        },
    log:
        "logs/drying_publish_tables/{scene}.log",
    threads: 1
    resources:
        mem_mb=config["drying"]["mem_mb"],
        runtime=config["drying"]["runtime_init"],
    script:
        "../scripts/drying_publish_tables.py"
