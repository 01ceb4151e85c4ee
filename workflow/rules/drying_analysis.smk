# Drying paste analysis: fragments per seed, campaign aggregate over seeds, summary of the
# paper's claims (results/drying/summary.json) and the paper's figures 2-6; the thickness
# sweep; the error-versus-wall-time study.

DRYING_FIGURES = ("snapshots", "inverse_mean_area", "size_distribution", "scaled_distribution")
DRYING_CAMPAIGN = f"results/drying/{config['drying']['scene']}/campaign.nc"
# Run dataset of the first seed, drawn in the crack-pattern figure.
DRYING_SNAPSHOT_RUN = (
    f"results/drying/{config['drying']['scene']}/run/seed{config['drying']['first_seed']}.nc"
)
DRYING_PNG = {name: f"results/drying/figures/drying_{name}.png" for name in DRYING_FIGURES}
DRYING_PDF = [f"results/drying/figures/drying_{name}.pdf" for name in DRYING_FIGURES]


# Aggregation, figure and report rules: seconds each, run by the submitting Snakemake
# process instead of waiting in a cluster queue.
localrules:
    drying_campaign,
    drying_summary,
    drying_figures,
    drying_accuracy_figure,
    drying_thickness,
    drying_thickness_figure,
    drying_speed,
    drying_speed_figure,
    drying_criterion_summary,
    drying_validation,
    drying_transition,
    drying_transition_figure,
    drying_kappa_figure,


rule drying_fragments:
    input:
        "results/drying/{scene}/run/seed{seed}.nc",
    output:
        "results/drying/{scene}/fragments/seed{seed}.nc",
    params:
        cli=CRAQUELURE,
    log:
        "logs/drying_fragments/{scene}/seed{seed}.log",
    benchmark:
        "benchmarks/results/drying_fragments/{scene}/seed{seed}.tsv"
    # Above the runs (priority 10): a finished run is labelled at once, so that an ensemble
    # cut between sessions keeps every seed it ran ready to archive.
    priority: 15
    threads: config["drying"]["threads"]
    resources:
        mem_mb=config["drying"]["mem_mb"],
        runtime=config["drying"]["runtime_init"],
    shell:
        "{params.cli} fragments {input} --out {output} --threads {threads} > {log} 2>&1"


rule drying_campaign:
    input:
        DRYING_JOBS.campaign_fragments,
    output:
        periodic="results/drying/{scene}/campaign.nc",
        open="results/drying/{scene}/campaign_open.nc",
    params:
        cli=CRAQUELURE,
        window=config["drying"]["window"],
    log:
        "logs/drying_campaign/{scene}.log",
    threads: 1
    resources:
        mem_mb=config["drying"]["mem_mb"],
        runtime=config["drying"]["runtime_init"],
    # both fragment labellings (on the torus, and the open image): checks 14-16 judge each
    shell:
        "({params.cli} campaign {input} --out {output.periodic} --window {params.window} && "
        "{params.cli} campaign {input} --out {output.open} --window {params.window} "
        "--labelling open) > {log} 2>&1"


rule drying_summary:
    input:
        campaign=DRYING_CAMPAIGN,
        open=DRYING_CAMPAIGN.replace("campaign.nc", "campaign_open.nc"),
    output:
        "results/drying/summary.json",
    params:
        profile=config["profile"],
        scene=config["drying"]["scene"],
    log:
        "logs/drying_summary.log",
    threads: 1
    resources:
        mem_mb=config["drying"]["mem_mb"],
        runtime=config["drying"]["runtime_init"],
    script:
        "../scripts/drying_summary.py"


rule drying_figures:
    input:
        campaign=DRYING_CAMPAIGN,
        summary="results/drying/summary.json",
        run=DRYING_SNAPSHOT_RUN,
    output:
        snapshots=report(
            DRYING_PNG["snapshots"],
            caption="../report/drying_snapshots.rst",
            category="Drying paste",
            labels={"figure": "Fig. 2 crack patterns"},
        ),
        inverse_mean_area=report(
            DRYING_PNG["inverse_mean_area"],
            caption="../report/drying_inverse_mean_area.rst",
            category="Drying paste",
            labels={"figure": "Fig. 3 inverse mean area"},
        ),
        size_distribution=report(
            DRYING_PNG["size_distribution"],
            caption="../report/drying_size_distribution.rst",
            category="Drying paste",
            labels={"figure": "Fig. 4 size distribution"},
        ),
        scaled_distribution=report(
            DRYING_PNG["scaled_distribution"],
            caption="../report/drying_scaled_distribution.rst",
            category="Drying paste",
            labels={"figure": "Figs. 5-6 scaled distribution"},
        ),
        pdfs=DRYING_PDF,
    params:
        profile=config["profile"],
    log:
        "logs/drying_figures.log",
    threads: 1
    resources:
        mem_mb=config["drying"]["mem_mb"],
        runtime=config["drying"]["runtime_init"],
    script:
        "../scripts/drying_figures.py"


TARGETS["drying_analysis"] = [
    DRYING_CAMPAIGN,
    "results/drying/summary.json",
    *DRYING_PNG.values(),
    *DRYING_PDF,
]


rule drying_accuracy:
    input:
        scene=scene_file("drying", config["drying"]["accuracy"]["scene"]),
    output:
        "results/drying/accuracy.nc",
    params:
        seed=config["drying"]["accuracy"]["seed"],
        time_steps=config["drying"]["accuracy"]["time_steps"],
    log:
        "logs/drying_accuracy.log",
    benchmark:
        "benchmarks/results/drying_accuracy.tsv"
    threads: config["drying"]["threads"]
    resources:
        mem_mb=config["drying"]["mem_mb"],
        runtime=config["drying"]["runtime_init"],
    script:
        "../scripts/drying_accuracy.py"


rule drying_accuracy_figure:
    input:
        "results/drying/accuracy.nc",
    output:
        png=report(
            "results/drying/figures/drying_accuracy.png",
            caption="../report/drying_accuracy.rst",
            category="Drying paste",
            labels={"figure": "accuracy: error vs wall time"},
        ),
        pdf="results/drying/figures/drying_accuracy.pdf",
    params:
        figure="accuracy",
        profile=config["profile"],
    log:
        "logs/drying_accuracy_figure.log",
    threads: 1
    resources:
        mem_mb=config["drying"]["mem_mb"],
        runtime=config["drying"]["runtime_init"],
    script:
        "../scripts/drying_dataset_figure.py"


TARGETS["drying_accuracy"] = [
    "results/drying/figures/drying_accuracy.png",
    "results/drying/figures/drying_accuracy.pdf",
]


rule drying_thickness:
    input:
        unpack(DRYING_JOBS.thickness_fragments),
    output:
        "results/drying/{scene}/thickness.nc",
    log:
        "logs/drying_thickness/{scene}.log",
    threads: 1
    resources:
        mem_mb=config["drying"]["mem_mb"],
        runtime=config["drying"]["runtime_init"],
    script:
        "../scripts/drying_thickness.py"


rule drying_thickness_figure:
    input:
        "results/drying/{scene}/thickness.nc",
    output:
        png=report(
            "results/drying/figures/{scene}_thickness.png",
            caption="../report/drying_thickness.rst",
            category="Drying paste",
            labels={"figure": "thickness sweep: <S> vs H"},
        ),
        pdf="results/drying/figures/{scene}_thickness.pdf",
    params:
        figure="thickness",
        profile=config["profile"],
    log:
        "logs/drying_thickness_figure/{scene}.log",
    threads: 1
    resources:
        mem_mb=config["drying"]["mem_mb"],
        runtime=config["drying"]["runtime_init"],
    script:
        "../scripts/drying_dataset_figure.py"


CLAIM_SOURCES["drying"] = ["results/drying/summary.json"]
if config["drying"]["thickness"]["n_seeds"] > 0:
    CLAIM_SOURCES["drying"].append(f"results/drying/{config['drying']['scene']}/thickness.nc")

TARGETS["drying_thickness"] = [
    f"results/drying/figures/{config['drying']['scene']}_thickness.{ext}"
    for ext in ("png", "pdf")
    if config["drying"]["thickness"]["n_seeds"] > 0
]

DATASETS["drying"] = [
    DRYING_CAMPAIGN,
    "results/drying/accuracy.nc",
    *expand(
        "results/drying/{scene}/fragments/seed{seed}.nc",
        scene=config["drying"]["scene"],
        seed=DRYING_JOBS.seeds(),
    ),
]


rule drying_speed:
    input:
        unpack(DRYING_JOBS.speed_fragments),
    output:
        "results/drying/{scene}/speed.nc",
    params:
        fixed=config["drying"]["speed"]["fixed_times_over_t_star"],
    log:
        "logs/drying_speed/{scene}.log",
    threads: 1
    resources:
        mem_mb=config["drying"]["mem_mb"],
        runtime=config["drying"]["runtime_init"],
    script:
        "../scripts/drying_speed.py"


rule drying_speed_figure:
    input:
        "results/drying/{scene}/speed.nc",
    output:
        png=report(
            "results/drying/figures/{scene}_speed.png",
            caption="../report/drying_speed.rst",
            category="Drying paste",
            labels={"figure": "drying speed: onset and 1/t law against Pi"},
        ),
        pdf="results/drying/figures/{scene}_speed.pdf",
    params:
        figure="speed",
        profile=config["profile"],
    log:
        "logs/drying_speed_figure/{scene}.log",
    threads: 1
    resources:
        mem_mb=config["drying"]["mem_mb"],
        runtime=config["drying"]["runtime_init"],
    script:
        "../scripts/drying_dataset_figure.py"


DRYING_SPEED = [
    f"results/drying/{config['drying']['scene']}/speed.nc",
    *(f"results/drying/figures/{config['drying']['scene']}_speed.{ext}" for ext in ("png", "pdf")),
]


# One target for the whole study: `snakemake drying_speed_study`.
rule drying_speed_study:
    localrule: True
    input:
        DRYING_SPEED,


TARGETS["drying_speed"] = DRYING_SPEED if config["drying"]["speed"]["n_seeds"] > 0 else []
DATASETS["drying"] += DRYING_SPEED[:1] if config["drying"]["speed"]["n_seeds"] > 0 else []


# Fracture-criterion sensitivity (config drying.criterion): a summary per criterion, with its
# checks 14-16 in the validation report (every row says the criterion departs from the source).
rule drying_criterion_summary:
    input:
        campaign="results/drying/{scene}_C{measure}/campaign.nc",
        open="results/drying/{scene}_C{measure}/campaign_open.nc",
    output:
        "results/drying/{scene}_C{measure}/summary.json",
    wildcard_constraints:
        measure=drying_workflow.CRITERION_PATTERN,
    params:
        profile=config["profile"],
        scene=DRYING_JOBS.criterion_scene,
    log:
        "logs/drying_summary/{scene}_C{measure}.log",
    threads: 1
    resources:
        mem_mb=config["drying"]["mem_mb"],
        runtime=config["drying"]["runtime_init"],
    script:
        "../scripts/drying_summary.py"


DRYING_CRITERION = [
    f"results/drying/{folder}/summary.json" for folder in DRYING_JOBS.criterion_folders()
]
CLAIM_SOURCES["drying"] += DRYING_CRITERION
TARGETS["drying_criterion"] = DRYING_CRITERION


# The drying rows of the validation report from the drying claim sources alone (a drying
# campaign's rows without the other models' runs).
rule drying_validation:
    input:
        drying_claim_sources,
    output:
        "results/drying/validation.json",
    params:
        profile=config["profile"],
    log:
        "logs/drying_validation.log",
    threads: 1
    resources:
        mem_mb=config["drying"]["mem_mb"],
        runtime=config["drying"]["runtime_init"],
    script:
        "../scripts/drying_validation.py"


# One target for the criterion study: the source criterion's summary beside each other
# criterion's, and their rows of the validation report.
rule drying_criterion_study:
    localrule: True
    input:
        "results/drying/summary.json",
        DRYING_CRITERION,
        "results/drying/validation.json",


# Damage-to-fragmentation transition (beyond the source; config drying.transition): m_max, its
# sample-to-sample fluctuation and the mean fragment area against damage d per box size, d_c by
# finite-size scaling, exponents with bootstrap intervals (craquelure.drying.transition).
rule drying_transition:
    input:
        unpack(DRYING_JOBS.transition_fragments),
    output:
        "results/drying/transition.nc",
    params:
        variant=config["drying"]["transition"]["variant"],
    log:
        "logs/drying_transition.log",
    threads: 1
    resources:
        mem_mb=config["drying"]["mem_mb"],
        runtime=config["drying"]["runtime_init"],
    script:
        "../scripts/drying_transition.py"


rule drying_transition_figure:
    input:
        "results/drying/transition.nc",
    output:
        png=report(
            "results/drying/figures/drying_transition.png",
            caption="../report/drying_transition.rst",
            category="Drying paste",
            labels={"figure": "damage-to-fragmentation transition"},
        ),
        pdf="results/drying/figures/drying_transition.pdf",
    params:
        figure="transition",
        profile=config["profile"],
    log:
        "logs/drying_transition_figure.log",
    threads: 1
    resources:
        mem_mb=config["drying"]["mem_mb"],
        runtime=config["drying"]["runtime_init"],
    script:
        "../scripts/drying_dataset_figure.py"


DRYING_TRANSITION = [
    "results/drying/transition.nc",
    "results/drying/figures/drying_transition.png",
    "results/drying/figures/drying_transition.pdf",
]


# One target for the transition study: `snakemake drying_transition_study`.
rule drying_transition_study:
    localrule: True
    input:
        DRYING_TRANSITION,


if DRYING_JOBS.transition_fragments():
    TARGETS["drying_transition"] = DRYING_TRANSITION
    DATASETS["drying"].append(DRYING_TRANSITION[0])
    CLAIM_SOURCES["drying"].append(DRYING_TRANSITION[0])


# Onset study (config drying.kappa, issue 32 item 1): kappa_max at fixed F, fracture off, against
# the minimum gap and h/Delta of the initial particles; one run per point and seed.
KAPPA_JOBS = drying_workflow.KappaJobs(config["drying"])


rule drying_kappa_init:
    input:
        scene=drying_workflow.KAPPA_SCENE,
    output:
        "results/mass/kappa/{point}/seed{seed}.nc",
    wildcard_constraints:
        point=drying_workflow.KAPPA_PATTERN.replace("?P<gap>", "")
        .replace("?P<hd>", "")
        .replace("?P<method>", ""),
    params:
        cli=CRAQUELURE,
        overrides=KAPPA_JOBS.point_overrides,
    log:
        "logs/drying_kappa_init/{point}/seed{seed}.log",
    threads: 1
    resources:
        mem_mb=config["drying"]["mem_mb"],
        runtime=config["drying"]["runtime_init"],
    shell:
        "{params.cli} init {input.scene} --seed {wildcards.seed} --out {output} --threads 1 "
        "{params.overrides} > {log} 2>&1"


rule drying_kappa_run:
    input:
        scene=drying_workflow.KAPPA_SCENE,
        state="results/mass/kappa/{point}/seed{seed}.nc",
    output:
        "results/drying/kappa/{point}/seed{seed}.nc",
    params:
        cli=CRAQUELURE,
        overrides=KAPPA_JOBS.point_overrides,
    log:
        "logs/drying_kappa_run/{point}/seed{seed}.log",
    benchmark:
        "benchmarks/results/drying_kappa_run/{point}/seed{seed}.tsv"
    threads: 1
    resources:
        mem_mb=config["drying"]["mem_mb"],
        runtime=config["drying"]["runtime_run"],
    shell:
        "{params.cli} run {input.scene} --init {input.state} --out {output} --threads 1 "
        "{params.overrides} > {log} 2>&1"


rule drying_kappa:
    input:
        KAPPA_JOBS.runs(),
    output:
        "results/drying/kappa.nc",
    log:
        "logs/drying_kappa.log",
    threads: 1
    resources:
        mem_mb=config["drying"]["mem_mb"],
        runtime=config["drying"]["runtime_init"],
    script:
        "../scripts/drying_kappa.py"


rule drying_kappa_figure:
    input:
        "results/drying/kappa.nc",
    output:
        png=report(
            "results/drying/figures/drying_kappa.png",
            caption="../report/drying_kappa.rst",
            category="Drying paste",
            labels={"figure": "onset: kappa_max against the disorder"},
        ),
        pdf="results/drying/figures/drying_kappa.pdf",
    params:
        figure="kappa",
        profile=config["profile"],
    log:
        "logs/drying_kappa_figure.log",
    threads: 1
    resources:
        mem_mb=config["drying"]["mem_mb"],
        runtime=config["drying"]["runtime_init"],
    script:
        "../scripts/drying_dataset_figure.py"


DRYING_KAPPA = [
    "results/drying/kappa.nc",
    "results/drying/figures/drying_kappa.png",
    "results/drying/figures/drying_kappa.pdf",
]


# One target for the onset study: `snakemake drying_onset_study`.
rule drying_onset_study:
    localrule: True
    input:
        DRYING_KAPPA,


if KAPPA_JOBS.labels():
    TARGETS["drying_kappa"] = DRYING_KAPPA
    DATASETS["drying"].append(DRYING_KAPPA[0])
