"""Snakemake script of rule drying_published_companions: an archived ensemble beside the
companion ensembles it names, Fig. 3 and Figs. 4-6 drawn for all of them
(craquelure.drying.figures.make_comparison) from their rebuilt campaigns, with the plotted
series in figures/drying_companions.json.

Outside Snakemake: ``python workflow/scripts/drying_published_companions.py OUTDIR REBUILT_DIR ...``
(the headline's results/drying_published/<name>/ first).
"""

import json
import sys
from pathlib import Path

from craquelure.drying.campaign import LABELLINGS
from craquelure.drying.figures import COMPARISON, comparison_series, make_comparison
from craquelure.io import open_dataset, write_text_atomic


def main(outdir: str, *rebuilt: str) -> None:
    figures = Path(outdir) / "figures"
    series = [comparison_series(Path(folder).name,
                                json.loads((Path(folder) / "summary.json").read_text()),
                                {name: open_dataset(Path(folder) / f"campaign_{name}.nc")
                                 for name in LABELLINGS}) for folder in rebuilt]
    write_text_atomic(figures / "drying_companions.json",
                      json.dumps({"ensembles": series}, indent=1) + "\n")
    make_comparison(series, {name: figures / f"drying_companions_{name}.png"
                             for name in COMPARISON})
    print(f"compared {', '.join(s['name'] for s in series)}")


if "snakemake" in globals():
    with open(snakemake.log[0], "w") as log:  # noqa: F821
        sys.stdout = sys.stderr = log
        main(snakemake.params.outdir, *snakemake.params.rebuilt)  # noqa: F821
elif __name__ == "__main__":
    main(*sys.argv[1:])
