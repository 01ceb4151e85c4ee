# Archive (last stage, not part of `rule all`; `make run` calls it after the report): final
# datasets, figures, the validation report and the Snakemake report (results/report.html, when
# it was built first), the resolved configuration, the config and scene files and the
# profiles, with a SHA-256 manifest, in results/archive/craquelure-<profile>-<date>.tar.gz.
# `craquelure verify <archive or unpacked folder>` checks it later.
from datetime import UTC, datetime

ARCHIVE = f"results/archive/craquelure-{config['profile']}-{datetime.now(UTC):%Y-%m-%d}.tar.gz"


localrules:
    all,
    archive,


rule archive:
    input:
        outputs=archive_outputs(),
        reports=archive_reports(),
        configs=archive_configs(),
    output:
        archive=ARCHIVE,
        checksum=f"{ARCHIVE}.sha256",
    params:
        configfiles=[str(path) for path in workflow.configfiles],
    log:
        "logs/archive.log",
    threads: 1
    resources:
        mem_mb=1000,
        runtime=30,
    script:
        "../scripts/archive.py"
