# craquelure: scene files -> datasets -> figures -> report, for four particle models.
from snakemake.utils import min_version

min_version("9.0")


configfile: "config/config.yaml"


report: "workflow/report/workflow.rst"


include: "workflow/rules/common.smk"
include: "workflow/rules/drying.smk"
include: "workflow/rules/lattice.smk"
include: "workflow/rules/drying_analysis.smk"
include: "workflow/rules/published.smk"
include: "workflow/rules/impact.smk"
include: "workflow/rules/softdyn.smk"
include: "workflow/rules/validation.smk"
include: "workflow/rules/archive.smk"


rule all:
    default_target: True
    input:
        all_targets(),
