"""Snakemake script of rule impact_publish_check12: check 12's archive
(craquelure.impact.published): both summaries, their rows, the judged-run pictures, the
static-strength sensitivity, the runs' commits and measured cost, and a SHA-256 manifest
(``craquelure verify results/published/impact-check12``)."""

import sys

from craquelure.impact.published import cpu_seconds, publish
from craquelure.io import open_dataset
from craquelure.provenance import git_commit

if "snakemake" in globals():
    smk = snakemake  # noqa: F821
    sys.stderr = sys.stdout = open(smk.log[0], "w")  # noqa: SIM115
    commits, dims = set(), {}
    for path in smk.input.runs:
        with open_dataset(path) as ds:
            commits.add(str(ds.attrs.get("git_commit", "")))
            dim = f"{int(ds.attrs.get('dim', 2))}D"
            dims[dim] = dims.get(dim, 0) + 1
    seconds = cpu_seconds(smk.params.benchmarks)
    provenance = {"profile": smk.params.profile, "distribution": smk.params.distribution,
                  "scenes": smk.params.scenes, "git_commit": git_commit(),
                  "run_git_commits": sorted(commits), "n_runs": len(smk.input.runs),
                  "n_runs_by_dim": dims, "cpu_seconds": seconds,
                  "cpu_hours_total": seconds / 3600.0}
    dest = publish(smk.input.summaries, [*smk.input.figures], provenance, smk.output[0],
                   smk.input.extra)
    print(f"published {dest}: {len(smk.input.runs)} runs, {seconds / 3600:.2f} CPU-hours")
