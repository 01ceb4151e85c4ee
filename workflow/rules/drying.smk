# Drying paste (SPH): mass-consistency initial states, runs, fragments, campaign, figures.


rule mass_consistency:
    input:
        scene=drying_scene,
    output:
        "results/mass/{scene}/seed{seed}.nc",
    params:
        cli=CRAQUELURE,
        overrides=scene_overrides("drying"),
    log:
        "logs/mass_consistency/{scene}/seed{seed}.log",
    benchmark:
        "benchmarks/results/mass_consistency/{scene}/seed{seed}.tsv"
    threads: config["drying"]["threads"]
    resources:
        mem_mb=config["drying"]["mem_mb"],
        runtime=config["drying"]["runtime_init"],
    shell:
        "{params.cli} init {input.scene} --seed {wildcards.seed} --out {output} "
        "--threads {threads} {params.overrides} > {log} 2>&1"


TARGETS["drying"] = expand(
    "results/mass/{scene}/seed{seed}.nc",
    scene=config["drying"]["scene"],
    seed=seeds("drying"),
)
