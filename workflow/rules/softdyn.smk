# Soft Dynamics: T1 time series (Fig. 4), duration sweep (Fig. 5, the grid points in
# config softdyn.sweep_batches batches of similar cost, one job each), T1 occurrence (Fig. 3),
# two-sphere runs, and the integrator accuracy-versus-wall-time study.
from craquelure.softdyn import workflow as softdyn_workflow

SOFTDYN_JOBS = softdyn_workflow.Jobs(config["softdyn"])


# Aggregation, figure and report rules: seconds each, run by the submitting Snakemake
# process instead of waiting in a cluster queue.
localrules:
    softdyn_sweep,
    softdyn_fig4,
    softdyn_fig3,
    softdyn_pair_figure,
    softdyn_summary,


wildcard_constraints:
    scene="[A-Za-z0-9_]+",
    i="[0-9]+",
    j="[0-9]+",
    b="[0-9]+",


rule softdyn_run:
    input:
        scene=SOFTDYN_JOBS.scene_path,
    output:
        "results/softdyn/{scene}/run.nc",
    params:
        cli=CRAQUELURE,
        overrides=scene_overrides("softdyn"),
    log:
        "logs/softdyn/{scene}/run.log",
    benchmark:
        "benchmarks/results/softdyn/{scene}/run.tsv"
    threads: config["softdyn"]["threads"]
    resources:
        mem_mb=config["softdyn"]["mem_mb"],
        runtime=config["softdyn"]["runtime"],
    shell:
        "{params.cli} run {input.scene} --out {output} --resume {params.overrides} > {log} 2>&1"


# A single grid point (not in the default DAG; for rerunning one point by its output path).
rule softdyn_sweep_point:
    input:
        scene=SOFTDYN_JOBS.scene_path,
    output:
        "results/softdyn/{scene}/points/p{i}_{j}.nc",
    params:
        overrides=SOFTDYN_JOBS.overrides(),
    log:
        "logs/softdyn/{scene}/p{i}_{j}.log",
    benchmark:
        "benchmarks/results/softdyn/{scene}/p{i}_{j}.tsv"
    threads: 1
    resources:
        mem_mb=config["softdyn"]["mem_mb"],
        runtime=config["softdyn"]["runtime"],
    script:
        "../scripts/softdyn_sweep_point.py"


rule softdyn_sweep_batch:
    input:
        scene=SOFTDYN_JOBS.scene_path,
    output:
        "results/softdyn/{scene}/batches/b{b}.nc",
    params:
        overrides=SOFTDYN_JOBS.overrides(),
        n_batches=SOFTDYN_JOBS.n_batches(),
    log:
        "logs/softdyn/{scene}/b{b}.log",
    benchmark:
        "benchmarks/results/softdyn/{scene}/b{b}.tsv"
    threads: 1
    resources:
        mem_mb=config["softdyn"]["mem_mb"],
        runtime=config["softdyn"]["runtime"],
    script:
        "../scripts/softdyn_sweep_batch.py"


rule softdyn_sweep:
    input:
        scene=SOFTDYN_JOBS.scene_path,
        points=SOFTDYN_JOBS.sweep_batch_files,
    output:
        data="results/softdyn/{scene}/sweep.nc",
        figure=report(
            "results/softdyn/{scene}/fig5.png",
            caption="../report/softdyn_fig5.rst",
            category="Soft Dynamics",
            subcategory="T1 duration",
        ),
    params:
        overrides=SOFTDYN_JOBS.overrides(),
    log:
        "logs/softdyn/{scene}/sweep.log",
    threads: 1
    resources:
        mem_mb=config["softdyn"]["mem_mb"],
        runtime=10,
    script:
        "../scripts/softdyn_sweep_aggregate.py"


rule softdyn_accuracy:
    input:
        scene=SOFTDYN_JOBS.scene_path,
    output:
        data="results/softdyn/{scene}/accuracy.nc",
        figure=report(
            "results/softdyn/{scene}/accuracy.png",
            caption="../report/softdyn_accuracy.rst",
            category="Soft Dynamics",
            subcategory="accuracy vs cost",
        ),
    params:
        overrides=SOFTDYN_JOBS.overrides(),
    log:
        "logs/softdyn/{scene}/accuracy.log",
    benchmark:
        "benchmarks/results/softdyn/{scene}/accuracy.tsv"
    threads: 1
    resources:
        mem_mb=config["softdyn"]["mem_mb"],
        runtime=config["softdyn"]["runtime"],
    script:
        "../scripts/softdyn_accuracy.py"


rule softdyn_fig4:
    input:
        "results/softdyn/{scene}/run.nc",
    output:
        report(
            "results/softdyn/{scene}/fig4.png",
            caption="../report/softdyn_fig4.rst",
            category="Soft Dynamics",
            subcategory="T1 in time",
        ),
    params:
        kind="fig4",
        scene="{scene}",
    log:
        "logs/softdyn/{scene}/fig4.log",
    threads: 1
    resources:
        mem_mb=1000,
        runtime=5,
    script:
        "../scripts/softdyn_figure.py"


rule softdyn_fig3:
    input:
        "results/softdyn/{scene}/run.nc",
    output:
        report(
            "results/softdyn/{scene}/fig3.png",
            caption="../report/softdyn_fig3.rst",
            category="Soft Dynamics",
            subcategory="T1 occurrence",
        ),
    params:
        kind="fig3",
        scene="{scene}",
    log:
        "logs/softdyn/{scene}/fig3.log",
    threads: 1
    resources:
        mem_mb=1000,
        runtime=5,
    script:
        "../scripts/softdyn_figure.py"


rule softdyn_pair_figure:
    input:
        "results/softdyn/{scene}/run.nc",
    output:
        report(
            "results/softdyn/{scene}/gaps.png",
            caption="../report/softdyn_pair.rst",
            category="Soft Dynamics",
            subcategory="two spheres",
        ),
    params:
        kind="pair",
        scene="{scene}",
    log:
        "logs/softdyn/{scene}/gaps.log",
    threads: 1
    resources:
        mem_mb=1000,
        runtime=5,
    script:
        "../scripts/softdyn_figure.py"


SOFTDYN_RUNS = (
    expand(
        "results/softdyn/{scene}/run.nc",
        scene=config["softdyn"]["single"] + config["softdyn"]["pairs"] + config["softdyn"]["phase"],
    )
    + expand("results/softdyn/{scene}/sweep.nc", scene=config["softdyn"]["sweep"])
    + expand("results/softdyn/{scene}/accuracy.nc", scene=config["softdyn"]["accuracy"])
)


rule softdyn_summary:
    input:
        SOFTDYN_RUNS,
    output:
        "results/softdyn/summary.json",
    log:
        "logs/softdyn/summary.log",
    benchmark:
        "benchmarks/results/softdyn/summary.tsv"
    threads: 1
    resources:
        runtime=10,
    script:
        "../scripts/softdyn_summary.py"


CLAIM_SOURCES["softdyn"] = ["results/softdyn/summary.json"] if SOFTDYN_RUNS else []
DATASETS["softdyn"] = SOFTDYN_RUNS
TARGETS["softdyn"] = (
    expand("results/softdyn/{scene}/fig4.png", scene=config["softdyn"]["single"])
    + expand("results/softdyn/{scene}/gaps.png", scene=config["softdyn"]["pairs"])
    + expand("results/softdyn/{scene}/fig5.png", scene=config["softdyn"]["sweep"])
    + expand("results/softdyn/{scene}/fig3.png", scene=config["softdyn"]["phase"])
    + expand("results/softdyn/{scene}/accuracy.png", scene=config["softdyn"]["accuracy"])
)
