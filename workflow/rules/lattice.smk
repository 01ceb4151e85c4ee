# Beam lattice (NUMFRAC style): Glen's-law sweep, gravity settlement, calving, fretting and a
# weak-scaling benchmark, each with a report figure and a JSON summary of measured numbers.

from craquelure.lattice import workflow as lattice_workflow

LATTICE = config["lattice"]
LATTICE_JOBS = lattice_workflow.Jobs(LATTICE, config["profile"])


# Aggregation, figure and report rules: seconds each, run by the submitting Snakemake
# process instead of waiting in a cluster queue.
localrules:
    lattice_glen_figure,
    lattice_scene_figure,


wildcard_constraints:
    kind="glen|frozen",
    k="[0-9]+",


rule lattice_glen_point:
    input:
        scene=LATTICE_JOBS.glen_scene_file,
    output:
        "results/lattice/glen/{kind}/tau{k}.nc",
    params:
        lattice=LATTICE,
        seed=LATTICE["seed"],
    log:
        "logs/lattice_glen/{kind}/tau{k}.log",
    benchmark:
        "benchmarks/results/lattice_glen/{kind}/tau{k}.tsv"
    threads: LATTICE["threads"]
    resources:
        mem_mb=LATTICE["mem_mb"],
        runtime=LATTICE["runtime"],
    script:
        "../scripts/lattice_glen_point.py"


rule lattice_glen_figure:
    input:
        glen=LATTICE_JOBS.glen_points("glen"),
        frozen=LATTICE_JOBS.glen_points("frozen"),
    output:
        figure=report(
            "results/lattice/glen/glen.png",
            caption="../report/lattice_glen.rst",
            category="Beam lattice",
            labels={"figure": "Glen's law (Fig. 1)"},
        ),
        summary="results/lattice/glen/summary.json",
        table="results/lattice/glen/glen.tsv",
    params:
        title=LATTICE_JOBS.title(LATTICE["glen"]["scene"]),
    log:
        "logs/lattice_glen_figure.log",
    threads: 1
    resources:
        mem_mb=LATTICE["mem_mb"],
        runtime=10,
    script:
        "../scripts/lattice_glen.py"


rule lattice_run:
    input:
        scene="config/scenes/lattice/{scene}.yaml",
    output:
        "results/lattice/{scene}/run.nc",
    params:
        cli=CRAQUELURE,
        overrides=LATTICE_JOBS.run_set,
        seed=LATTICE["seed"],
    log:
        "logs/lattice_run/{scene}.log",
    benchmark:
        "benchmarks/results/lattice_run/{scene}.tsv"
    threads: LATTICE["threads"]
    resources:
        mem_mb=LATTICE["mem_mb"],
        runtime=LATTICE["runtime"],
    wildcard_constraints:
        scene="gravity_block|calving|fretting",
    shell:
        "{params.cli} run {input.scene} --seed {params.seed} --out {output} --resume "
        "--threads {threads} {params.overrides} > {log} 2>&1"


rule lattice_scene_figure:
    input:
        "results/lattice/{scene}/run.nc",
    output:
        figure=report(
            "results/lattice/{scene}/{scene}.png",
            caption="../report/lattice_scene.rst",
            category="Beam lattice",
            labels={"figure": "{scene}"},
        ),
        summary="results/lattice/{scene}/summary.json",
    params:
        title=LATTICE_JOBS.scene_title,
    log:
        "logs/lattice_figure/{scene}.log",
    threads: 1
    resources:
        mem_mb=LATTICE["mem_mb"],
        runtime=10,
    wildcard_constraints:
        scene="gravity_block|calving|fretting",
    script:
        "../scripts/lattice_figures.py"


rule lattice_scaling:
    output:
        figure=report(
            "results/lattice/scaling/scaling.png",
            caption="../report/lattice_scaling.rst",
            category="Beam lattice",
            labels={"figure": "weak scaling (Fig. 4)"},
        ),
        table="results/lattice/scaling/scaling.tsv",
    params:
        particles=LATTICE["scaling"]["particles"],
        steps=LATTICE["scaling"]["steps"],
        title=LATTICE_JOBS.title("benchmark block (beams only)"),
    log:
        "logs/lattice_scaling.log",
    benchmark:
        "benchmarks/results/lattice_scaling.tsv"
    threads: LATTICE["threads"]
    resources:
        mem_mb=LATTICE["mem_mb"],
        runtime=LATTICE["runtime"],
    script:
        "../scripts/lattice_scaling.py"


rule lattice_accuracy:
    output:
        figure=report(
            "results/lattice/accuracy/accuracy.png",
            caption="../report/lattice_accuracy.rst",
            category="Beam lattice",
            labels={"figure": "error versus wall time"},
        ),
        table="results/lattice/accuracy/accuracy.tsv",
        summary="results/lattice/accuracy/summary.json",
    params:
        rows=LATTICE["accuracy"]["rows"],
        dt_factors=LATTICE["accuracy"]["dt_factors"],
        title=LATTICE_JOBS.title(
            "column mode (H = 1, periodic x), reference: continuum period 4H/c_P"
        ),
    log:
        "logs/lattice_accuracy.log",
    benchmark:
        "benchmarks/results/lattice_accuracy.tsv"
    threads: 1
    resources:
        mem_mb=LATTICE["mem_mb"],
        runtime=LATTICE["runtime"],
    script:
        "../scripts/lattice_accuracy.py"


TARGETS["lattice"] = LATTICE_JOBS.targets()
CLAIM_SOURCES["lattice"] = [
    *(path for path in TARGETS["lattice"] if path.endswith("summary.json")),
    "results/lattice/accuracy/summary.json",
]
# The scaling table is a timing: no claim is judged on it (benchmarks/lattice_scaling.py
# judges spec check 12); the archive packs it with the figure.
DATASETS["lattice"] = [
    "results/lattice/scaling/scaling.tsv",
    *LATTICE_JOBS.glen_points("glen"),
    *LATTICE_JOBS.glen_points("frozen"),
    *(f"results/lattice/{scene}/run.nc" for scene in LATTICE["runs"]),
]
