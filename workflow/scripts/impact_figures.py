"""Report figures of the impact campaign (masses, damage maps, pre-cracks, contact force)."""

import sys
from collections import defaultdict
from pathlib import Path

from craquelure.impact import figures
from craquelure.impact.analysis import run_fact, run_metrics
from craquelure.io import open_dataset

if "snakemake" in globals():
    smk = snakemake  # noqa: F821
    sys.stderr = sys.stdout = open(smk.log[0], "w")  # noqa: SIM115
    ds = open_dataset(smk.input.specimen)
    size = (f"{int(run_fact(ds, 'n_particles'))} particles, "
            f"Delta = {1e3 * float(run_fact(ds, 'spacing')):g} mm")
    label = f"profile {smk.params.profile}, scene impact/{smk.params.scene}, {size}, 2D"
    out = {k: Path(v) for k, v in smk.output.items()}
    figures.figure_masses(Path(smk.input.specimen), out["masses"], label)
    figures.figure_damage_grid(smk.input.homogeneous, out["damage_homogeneous"],
                              "homogeneous disc at the end time (Fig. 7; black cracked, "
                              "dark grey crushed)", label)
    figures.figure_damage_grid(smk.input.hetero_kappa1, out["damage_heterogeneous_kappa1"],
                              "heterogeneous specimens, kappa = 1 (Fig. 8)", label)
    figures.figure_damage_grid(smk.input.hetero_low_high,
                              out["damage_heterogeneous_kappa_low_high"],
                              "heterogeneous specimens, kappa = 0.7 and 1.5 (Figs. 9-10)", label)
    figures.figure_precracks(smk.input.precracks, out["precracks"], label)
    by_kappa = defaultdict(list)
    for run in smk.input.contact:
        by_kappa[float(run_metrics(open_dataset(run))["kappa"])].append(run)
    figures.figure_contact(by_kappa, out["contact_force"], f"contact force; {label}")
