# Drying paste (SPH): mass-consistency initial states, runs, fragments, campaign, figures.
from craquelure.drying import workflow as drying_workflow

DRYING_JOBS = drying_workflow.Jobs(config["drying"])


rule mass_consistency:
    input:
        scene=DRYING_JOBS.scene_path,
    output:
        "results/mass/{scene}/seed{seed}.nc",
    params:
        cli=CRAQUELURE,
        overrides=scene_overrides("drying"),
    log:
        "logs/mass_consistency/{scene}/seed{seed}.log",
    benchmark:
        "benchmarks/results/mass_consistency/{scene}/seed{seed}.tsv"
    # Snakemake does not pass a job's priority on to its inputs: the (seconds-long) mass
    # solves must outrank the drying runs that wait for them, or those start late.
    priority: 20
    threads: config["drying"]["threads"]
    resources:
        mem_mb=config["drying"]["mem_mb"],
        runtime=config["drying"]["runtime_init"],
    shell:
        "{params.cli} init {input.scene} --seed {wildcards.seed} --out {output} "
        "--threads {threads} {params.overrides} > {log} 2>&1"


rule drying_run:
    input:
        scene=DRYING_JOBS.scene_path,
        state="results/mass/{scene}/seed{seed}.nc",
    output:
        "results/drying/{scene}/run/seed{seed}.nc",
    params:
        cli=CRAQUELURE,
        overrides=scene_overrides("drying"),
    log:
        "logs/drying_run/{scene}/seed{seed}.log",
    benchmark:
        "benchmarks/results/drying_run/{scene}/seed{seed}.tsv"
    # The longest jobs of the default workflow: start them first (critical path).
    priority: 10
    threads: config["drying"]["threads"]
    resources:
        mem_mb=config["drying"]["mem_mb"],
        runtime=config["drying"]["runtime_run"],
    shell:
        "{params.cli} run {input.scene} --init {input.state} --out {output} --resume "
        "--threads {threads} {params.overrides} > {log} 2>&1"


TARGETS["drying"] = expand(
    "results/drying/{scene}/run/seed{seed}.nc",
    scene=config["drying"]["scene"],
    seed=DRYING_JOBS.seeds(),
)


# Thickness sweep (rules drying_thickness*): the same initial states run with another layer
# thickness H; results/drying/<scene>_H<H>/ (H with its decimal point spelled p, e.g. H0p25:
# scene wildcards have no dots) then goes through drying_fragments like any run.
ruleorder: drying_thickness_run > drying_run


rule drying_thickness_run:
    input:
        scene=DRYING_JOBS.scene_path,
        state="results/mass/{scene}/seed{seed}.nc",
    output:
        "results/drying/{scene}_H{thickness}/run/seed{seed}.nc",
    wildcard_constraints:
        thickness=r"[0-9]+(?:p[0-9]+)?",
    params:
        cli=CRAQUELURE,
        overrides=scene_overrides("drying"),
        thickness=DRYING_JOBS.thickness_value,
    log:
        "logs/drying_run/{scene}_H{thickness}/seed{seed}.log",
    benchmark:
        "benchmarks/results/drying_run/{scene}_H{thickness}/seed{seed}.tsv"
    # The longest jobs of the default workflow: start them first (critical path).
    priority: 10
    threads: config["drying"]["threads"]
    resources:
        mem_mb=config["drying"]["mem_mb"],
        runtime=config["drying"]["runtime_run"],
    shell:
        "{params.cli} run {input.scene} --init {input.state} --out {output} --resume "
        "--threads {threads} {params.overrides} --set material.thickness={params.thickness} "
        "> {log} 2>&1"


# Drying-speed study (rules drying_speed*): the same initial states dried at other speeds
# Pi = tau/t* (config drying.speed), snapshots at fixed fractions of t*;
# results/drying/<scene>_Pi<Pi>/ (decimal point spelled p) then goes through drying_fragments.
# Rule drying_speed_scene derives each speed's drying rate, end and snapshot times from the
# scene (in a job, not while the DAG is built); the runs read them with --set-file.
ruleorder: drying_speed_run > drying_run


rule drying_speed_scene:
    localrule: True
    input:
        scene=DRYING_JOBS.scene_path,
    output:
        "results/drying/{scene}_Pi{pi}/speed_settings.yaml",
    wildcard_constraints:
        pi=r"[0-9]+(?:p[0-9]+)?",
    params:
        pi=DRYING_JOBS.speed_value,
        end_over_t_star=DRYING_JOBS.speed_end_over_t_star,
        times_over_t_star=DRYING_JOBS.speed_times_over_t_star,
    log:
        "logs/drying_speed_scene/{scene}_Pi{pi}.log",
    threads: 1
    resources:
        mem_mb=config["drying"]["mem_mb"],
        runtime=config["drying"]["runtime_init"],
    script:
        "../scripts/drying_speed_scene.py"


rule drying_speed_run:
    input:
        scene=DRYING_JOBS.scene_path,
        state="results/mass/{scene}/seed{seed}.nc",
        speed="results/drying/{scene}_Pi{pi}/speed_settings.yaml",
    output:
        "results/drying/{scene}_Pi{pi}/run/seed{seed}.nc",
    wildcard_constraints:
        pi=r"[0-9]+(?:p[0-9]+)?",
    params:
        cli=CRAQUELURE,
        overrides=scene_overrides("drying"),
        study=DRYING_JOBS.speed_overrides(),
    log:
        "logs/drying_run/{scene}_Pi{pi}/seed{seed}.log",
    benchmark:
        "benchmarks/results/drying_run/{scene}_Pi{pi}/seed{seed}.tsv"
    priority: 10
    threads: config["drying"]["threads"]
    resources:
        mem_mb=config["drying"]["mem_mb"],
        runtime=config["drying"]["runtime_run"],
    shell:
        "{params.cli} run {input.scene} --init {input.state} --out {output} --resume "
        "--threads {threads} {params.overrides} --set-file {input.speed} {params.study} "
        "> {log} 2>&1"


# Fracture-criterion sensitivity (rules drying_criterion*, config drying.criterion): the same
# initial states run with another material.fracture_stress_measure (open doubt 7 of the spec);
# results/drying/<scene>_C<measure>/ then goes through drying_fragments and drying_campaign.
ruleorder: drying_criterion_run > drying_run


rule drying_criterion_run:
    input:
        scene=DRYING_JOBS.scene_path,
        state="results/mass/{scene}/seed{seed}.nc",
    output:
        "results/drying/{scene}_C{measure}/run/seed{seed}.nc",
    wildcard_constraints:
        measure=drying_workflow.CRITERION_PATTERN,
    params:
        cli=CRAQUELURE,
        overrides=scene_overrides("drying"),
    log:
        "logs/drying_run/{scene}_C{measure}/seed{seed}.log",
    benchmark:
        "benchmarks/results/drying_run/{scene}_C{measure}/seed{seed}.tsv"
    priority: 10
    threads: config["drying"]["threads"]
    resources:
        mem_mb=config["drying"]["mem_mb"],
        runtime=config["drying"]["runtime_run"],
    shell:
        "{params.cli} run {input.scene} --init {input.state} --out {output} --resume "
        "--threads {threads} {params.overrides} "
        "--set material.fracture_stress_measure={wildcards.measure} > {log} 2>&1"
