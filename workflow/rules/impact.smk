# Concrete impact (SPH): one run per variant (masses x kappa x pre-crack x seed), in 2D and,
# with 3 in impact.dims, in 3D (impact.three_d: the source's 10 112-particle disc), a summary of
# the source's findings (results/impact/summary.json) and the report figures.

from craquelure.impact import workflow as impact_workflow

IMPACT = config["impact"]
IMPACT_SCENE = IMPACT["scene"]
IMPACT_FIGURES = (
    "masses",
    "damage_homogeneous",
    "damage_heterogeneous_kappa1",
    "damage_heterogeneous_kappa_low_high",
    "precracks",
    "contact_force",
)
IMPACT_PNG = {name: f"results/impact/figures/impact_{name}.png" for name in IMPACT_FIGURES}
IMPACT_FIGURE_RUNS = impact_workflow.figure_runs(IMPACT)
IMPACT_CASE = impact_workflow.case_folder("{masses}", "{precrack}", "{kappa}")
# Pictures of the runs check 12 judges (3D when impact.dims has 3): one file each.
IMPACT_JUDGED = impact_workflow.judged_runs(IMPACT)
IMPACT_JUDGED_PNG = {
    name: f"results/impact/figures/impact_judged_{name}.png"
    for name in ("opening_maps", "time_sequence", "energy", "fragments")
}


# Aggregation, figure and report rules: seconds each, run by the submitting Snakemake
# process instead of waiting in a cluster queue.
localrules:
    impact_summary,
    impact_figures,
    impact_judged_figures,


wildcard_constraints:
    masses="homogeneous|uniform|normal|poisson",
    precrack="[a-z0-9]+",
    kappa="[0-9.]+",


rule impact_run:
    input:
        scene="config/scenes/impact/{scene}.yaml",
    output:
        f"results/impact/{{scene}}/{IMPACT_CASE}/seed{{seed}}.nc",
    params:
        cli=CRAQUELURE,
        variant=impact_workflow.variant_overrides(IMPACT),
        overrides=scene_overrides("impact"),
        three_d=impact_workflow.three_d_overrides(IMPACT),
    log:
        f"logs/impact_run/{{scene}}/{IMPACT_CASE}/seed{{seed}}.log",
    benchmark:
        f"benchmarks/results/impact_run/{{scene}}/{IMPACT_CASE}/seed{{seed}}.tsv"
    threads: impact_workflow.run_resource(IMPACT, "threads")
    resources:
        mem_mb=impact_workflow.run_resource(IMPACT, "mem_mb"),
        runtime=impact_workflow.run_resource(IMPACT, "runtime_run"),
    shell:
        "{params.cli} run {input.scene} --seed {wildcards.seed} --out {output} --resume "
        "--threads {threads} {params.variant} {params.overrides} {params.three_d} "
        "> {log} 2>&1"


rule impact_summary:
    input:
        impact_workflow.campaign_runs(IMPACT) + impact_workflow.campaign_runs_3d(IMPACT),
    output:
        "results/impact/summary.json",
    params:
        profile=config["profile"],
        scene=IMPACT_SCENE,
        distribution=IMPACT["distribution"],
        fixed_across_kappa=IMPACT.get("fixed_across_kappa", {}),
    log:
        "logs/impact_summary.log",
    threads: 1
    resources:
        mem_mb=IMPACT["mem_mb"],
        runtime=10,
    script:
        "../scripts/impact_summary.py"


rule impact_figures:
    input:
        summary="results/impact/summary.json",
        specimen=IMPACT_FIGURE_RUNS["specimen"],
        homogeneous=IMPACT_FIGURE_RUNS["homogeneous"],
        hetero_kappa1=IMPACT_FIGURE_RUNS["hetero_kappa1"],
        hetero_low_high=IMPACT_FIGURE_RUNS["hetero_low_high"],
        precracks=IMPACT_FIGURE_RUNS["precracks"],
        contact=IMPACT_FIGURE_RUNS["contact"],
    output:
        masses=report(
            IMPACT_PNG["masses"],
            caption="../report/impact_masses.rst",
            category="Concrete impact",
            labels={"figure": "Figs. 5-6 masses"},
        ),
        damage_homogeneous=report(
            IMPACT_PNG["damage_homogeneous"],
            caption="../report/impact_damage_homogeneous.rst",
            category="Concrete impact",
            labels={"figure": "Fig. 7 homogeneous disc"},
        ),
        damage_heterogeneous_kappa1=report(
            IMPACT_PNG["damage_heterogeneous_kappa1"],
            caption="../report/impact_damage_heterogeneous.rst",
            category="Concrete impact",
            labels={"figure": "Fig. 8 heterogeneous, kappa = 1"},
        ),
        damage_heterogeneous_kappa_low_high=report(
            IMPACT_PNG["damage_heterogeneous_kappa_low_high"],
            caption="../report/impact_damage_kappa.rst",
            category="Concrete impact",
            labels={"figure": "Figs. 9-10 kappa = 1.5, 0.7"},
        ),
        precracks=report(
            IMPACT_PNG["precracks"],
            caption="../report/impact_precracks.rst",
            category="Concrete impact",
            labels={"figure": "Figs. 11-13 pre-cracks"},
        ),
        contact_force=report(
            IMPACT_PNG["contact_force"],
            caption="../report/impact_contact_force.rst",
            category="Concrete impact",
            labels={"figure": "contact force"},
        ),
    params:
        profile=config["profile"],
        scene=IMPACT_SCENE,
    log:
        "logs/impact_figures.log",
    threads: 1
    resources:
        mem_mb=IMPACT["mem_mb"],
        runtime=10,
    script:
        "../scripts/impact_figures.py"


rule impact_judged_figures:
    input:
        maps=IMPACT_JUDGED["maps"],
        sequence=IMPACT_JUDGED["sequence"],
        energy=IMPACT_JUDGED["energy"],
    output:
        opening_maps=report(
            IMPACT_JUDGED_PNG["opening_maps"],
            caption="../report/impact_judged_opening_maps.rst",
            category="Concrete impact",
            labels={"figure": "judged runs: opening maps, every seed"},
        ),
        time_sequence=report(
            IMPACT_JUDGED_PNG["time_sequence"],
            caption="../report/impact_judged_time_sequence.rst",
            category="Concrete impact",
            labels={"figure": "judged runs: time sequence per variant"},
        ),
        energy=report(
            IMPACT_JUDGED_PNG["energy"],
            caption="../report/impact_judged_energy.rst",
            category="Concrete impact",
            labels={"figure": "judged runs: energy partition"},
        ),
        fragments=report(
            IMPACT_JUDGED_PNG["fragments"],
            caption="../report/impact_judged_fragments.rst",
            category="Concrete impact",
            labels={"figure": "judged runs: fragment sizes per kappa"},
        ),
    params:
        profile=config["profile"],
    log:
        "logs/impact_judged_figures.log",
    threads: 1
    resources:
        mem_mb=IMPACT["mem_mb"],
        runtime=10,
    script:
        "../scripts/impact_judged_figures.py"


rule impact_accuracy:
    output:
        json="results/impact/accuracy.json",
        png=report(
            "results/impact/figures/impact_accuracy.png",
            caption="../report/impact_accuracy.rst",
            category="Concrete impact",
            labels={"figure": "accuracy: error vs CPU time"},
        ),
    params:
        profile=config["profile"],
        spacings=IMPACT["accuracy"]["spacings"],
        kappas=IMPACT["accuracy"]["kappas"],
    log:
        "logs/impact_accuracy.log",
    benchmark:
        "benchmarks/results/impact_accuracy.tsv"
    threads: 1
    resources:
        mem_mb=IMPACT["mem_mb"],
        runtime=10,
    script:
        "../scripts/impact_accuracy.py"


rule impact_regime_run:
    input:
        scene="config/scenes/impact/{scene}.yaml",
    output:
        "results/impact/{scene}/regime/ft{ft}_a{a}_v{v}.nc",
    wildcard_constraints:
        ft="[0-9.]+",
        a="[0-9.]+|auto",
        v="[0-9.]+",
    params:
        cli=CRAQUELURE,
        variant=impact_workflow.regime_overrides(IMPACT),
        overrides=scene_overrides("impact"),
    log:
        "logs/impact_regime_run/{scene}/ft{ft}_a{a}_v{v}.log",
    benchmark:
        "benchmarks/results/impact_regime_run/{scene}/ft{ft}_a{a}_v{v}.tsv"
    threads: impact_workflow.regime_resource(IMPACT, "threads")
    resources:
        mem_mb=impact_workflow.regime_resource(IMPACT, "mem_mb"),
        runtime=impact_workflow.regime_resource(IMPACT, "runtime_run"),
    shell:
        "{params.cli} run {input.scene} --seed 0 --out {output} --resume "
        "--threads {threads} {params.variant} {params.overrides} > {log} 2>&1"


# The regime map in 2D (impact.regime) and, with impact.regime.three_d, in 3D: one figure with
# a row of panels per dimension, regime.json with both.
rule impact_regime:
    input:
        impact_workflow.regime_runs(IMPACT) + impact_workflow.regime_runs_3d(IMPACT),
    output:
        json="results/impact/regime.json",
        png=report(
            "results/impact/figures/impact_regime_map.png",
            caption="../report/impact_regime_map.rst",
            category="Concrete impact",
            labels={"figure": "regime map: splits once or fans out"},
        ),
    params:
        profile=config["profile"],
    log:
        "logs/impact_regime.log",
    threads: 1
    resources:
        mem_mb=IMPACT["mem_mb"],
        runtime=10,
    script:
        "../scripts/impact_regime.py"


# Check 12 again with CSCM's rate effects (config impact.rate: the campaign with the rate
# scenes): its own summary and judged-run pictures; report rows "with rate effects".
IMPACT_RATE = impact_workflow.with_rate_effects(IMPACT)
IMPACT_RATE_RUNS = (
    impact_workflow.campaign_runs(IMPACT_RATE) + impact_workflow.campaign_runs_3d(IMPACT_RATE)
    if IMPACT_RATE
    else []
)
IMPACT_RATE_PNG = {
    name: f"results/impact/figures/impact_judged_rate_{name}.png"
    for name in ("opening_maps", "time_sequence", "energy", "fragments")
}
# The report figures (2D runs) again for the campaign with rate effects.
IMPACT_RATE_FIGURE_PNG = {
    name: f"results/impact/figures/impact_rate_{name}.png" for name in IMPACT_FIGURES
}

if IMPACT_RATE:
    IMPACT_RATE_JUDGED = impact_workflow.judged_runs(IMPACT_RATE)

    rule impact_summary_rate:
        input:
            IMPACT_RATE_RUNS,
        output:
            "results/impact/summary_rate.json",
        params:
            profile=config["profile"],
            scene=IMPACT_RATE["scene"],
            distribution=IMPACT["distribution"],
            fixed_across_kappa=IMPACT.get("fixed_across_kappa", {}),
        log:
            "logs/impact_summary_rate.log",
        threads: 1
        resources:
            mem_mb=IMPACT["mem_mb"],
            runtime=10,
        script:
            "../scripts/impact_summary.py"

    rule impact_figures_rate:
        input:
            **impact_workflow.figure_runs(IMPACT_RATE),
            summary="results/impact/summary_rate.json",
        output:
            **{
                name: report(
                    path,
                    caption="../report/impact_figures_rate.rst",
                    category="Concrete impact",
                    labels={"figure": f"2D runs with rate effects: {name}"},
                )
                for name, path in IMPACT_RATE_FIGURE_PNG.items()
            },
        params:
            profile=config["profile"],
            scene=IMPACT_RATE["scene"],
        log:
            "logs/impact_figures_rate.log",
        threads: 1
        resources:
            mem_mb=IMPACT["mem_mb"],
            runtime=10,
        script:
            "../scripts/impact_figures.py"

    rule impact_judged_figures_rate:
        input:
            maps=IMPACT_RATE_JUDGED["maps"],
            sequence=IMPACT_RATE_JUDGED["sequence"],
            energy=IMPACT_RATE_JUDGED["energy"],
        output:
            **{
                name: report(
                    path,
                    caption="../report/impact_judged_rate.rst",
                    category="Concrete impact",
                    labels={"figure": f"judged runs with rate effects: {name}"},
                )
                for name, path in IMPACT_RATE_PNG.items()
            },
        params:
            profile=config["profile"],
        log:
            "logs/impact_judged_figures_rate.log",
        threads: 1
        resources:
            mem_mb=IMPACT["mem_mb"],
            runtime=10,
        script:
            "../scripts/impact_judged_figures.py"

    # results/published/impact-check12/: both summaries (every run's measurements per case),
    # check 12's rows with and without rate effects, the report and judged-run pictures, the
    # static-strength sensitivity, the runs' commits and CPU time, and a SHA-256 manifest
    # (craquelure.impact.published; craquelure verify results/published/impact-check12).
    IMPACT_CHECK12_RUNS = (
        impact_workflow.campaign_runs(IMPACT)
        + impact_workflow.campaign_runs_3d(IMPACT)
        + IMPACT_RATE_RUNS
    )

    rule impact_publish_check12:
        input:
            summaries=["results/impact/summary.json", "results/impact/summary_rate.json"],
            figures=[
                *IMPACT_PNG.values(),
                *IMPACT_JUDGED_PNG.values(),
                *IMPACT_RATE_PNG.values(),
                *IMPACT_RATE_FIGURE_PNG.values(),
                *(
                    ["results/impact/figures/impact_strength_sweep.png"]
                    if impact_workflow.strength_runs(IMPACT)
                    else []
                ),
            ],
            extra=(
                ["results/impact/strength_sweep.json"]
                if impact_workflow.strength_runs(IMPACT)
                else []
            ),
            runs=IMPACT_CHECK12_RUNS,
        output:
            directory("results/published/impact-check12"),
        params:
            profile=config["profile"],
            distribution=IMPACT["distribution"],
            scenes=[IMPACT_SCENE, IMPACT_RATE["scene"]]
            + sorted(impact_workflow.three_d_scenes(IMPACT)),
            benchmarks=[
                run.replace("results/impact/", "benchmarks/results/impact_run/", 1)[:-3] + ".tsv"
                for run in IMPACT_CHECK12_RUNS
            ],
        log:
            "logs/impact_publish_check12.log",
        threads: 1
        resources:
            mem_mb=1000,
            runtime=5,
        script:
            "../scripts/impact_publish_check12.py"


# Static-strength sensitivity (config impact.strength_sweep): the 3D disc with f_t x factor.
IMPACT_STRENGTH_RUNS = impact_workflow.strength_runs(IMPACT)

if IMPACT_STRENGTH_RUNS:
    IMPACT_SWEEP = IMPACT["strength_sweep"]

    rule impact_strength_run:
        input:
            scene="config/scenes/impact/{scene}.yaml",
        output:
            "results/impact/strength/{scene}/x{factor}/{masses}/seed{seed}.nc",
        wildcard_constraints:
            factor="[0-9.]+",
        params:
            cli=CRAQUELURE,
            variant=impact_workflow.strength_overrides(IMPACT),
            overrides=scene_overrides("impact"),
        log:
            "logs/impact_strength_run/{scene}/x{factor}/{masses}/seed{seed}.log",
        benchmark:
            "benchmarks/results/impact_strength_run/{scene}/x{factor}/{masses}/seed{seed}.tsv"
        threads: IMPACT_SWEEP["threads"]
        resources:
            mem_mb=IMPACT_SWEEP["mem_mb"],
            runtime=IMPACT_SWEEP["runtime_run"],
        shell:
            "{params.cli} run {input.scene} --seed {wildcards.seed} --out {output} --resume "
            "--threads {threads} {params.variant} {params.overrides} > {log} 2>&1"

    rule impact_strength_sweep:
        input:
            IMPACT_STRENGTH_RUNS,
        output:
            json="results/impact/strength_sweep.json",
            png=report(
                "results/impact/figures/impact_strength_sweep.png",
                caption="../report/impact_strength_sweep.rst",
                category="Concrete impact",
                labels={"figure": "sensitivity: static f_t x 1-3 (3D)"},
            ),
        params:
            profile=config["profile"],
        log:
            "logs/impact_strength_sweep.log",
        threads: 1
        resources:
            mem_mb=IMPACT["mem_mb"],
            runtime=10,
        script:
            "../scripts/impact_strength_sweep.py"


CLAIM_SOURCES["impact"] = ["results/impact/summary.json"] + (
    ["results/impact/summary_rate.json"] if IMPACT_RATE else []
)
# The 3D disc (config impact.three_d, scene with domain.dim 3): its runs are datasets of the
# campaign with attrs dim = 3, under results/impact/<3D scene>/.
IMPACT_RUNS_3D = impact_workflow.campaign_runs_3d(IMPACT)
TARGETS["impact"] = [
    "results/impact/summary.json",
    *IMPACT_RUNS_3D,
    *IMPACT_PNG.values(),
    *IMPACT_JUDGED_PNG.values(),
    "results/impact/figures/impact_accuracy.png",
    "results/impact/figures/impact_regime_map.png",
]
if IMPACT_RATE:
    TARGETS["impact"] += [
        "results/impact/summary_rate.json",
        *IMPACT_RATE_PNG.values(),
        *IMPACT_RATE_FIGURE_PNG.values(),
    ]
if IMPACT_STRENGTH_RUNS:
    TARGETS["impact"] += [
        "results/impact/strength_sweep.json",
        "results/impact/figures/impact_strength_sweep.png",
    ]
DATASETS["impact"] = (
    impact_workflow.campaign_runs(IMPACT)
    + IMPACT_RUNS_3D
    + IMPACT_RATE_RUNS
    + IMPACT_STRENGTH_RUNS
    + impact_workflow.regime_runs(IMPACT)
    + impact_workflow.regime_runs_3d(IMPACT)
)
