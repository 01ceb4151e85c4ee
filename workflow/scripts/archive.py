"""Rule archive: pack the workflow's outputs and configuration with a SHA-256 manifest."""

import yaml

from craquelure.archive import build_archive

sm = snakemake  # noqa: F821 (injected by Snakemake)
texts = {
    # The configuration as Snakemake resolved it (config/config.yaml merged with --configfile
    # and --config), and which files made it.
    "resolved-config.yaml": yaml.safe_dump(
        {"configfiles": list(sm.params.configfiles), "config": dict(sm.config)}, sort_keys=False
    ),
}
with open(sm.log[0], "w") as log:
    files = [*sm.input.outputs, *sm.input.reports, *sm.input.configs]
    out = build_archive(sm.output.archive, files, texts)
    n = len(files) + len(texts)
    print(f"wrote {out}: {n} files and MANIFEST.sha256", file=log)
