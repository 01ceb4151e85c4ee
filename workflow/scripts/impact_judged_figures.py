"""Pictures of the runs check 12 judges (3D when the profile runs 3D): the opening maps of every
seed per kappa, a time sequence of one seed per variant, the energy partition of the homogeneous
kappa = 1 disc and the fragment sizes per kappa."""

import sys
from collections import defaultdict
from pathlib import Path

from craquelure.impact import figures
from craquelure.impact.analysis import run_fact, run_metrics
from craquelure.io import open_dataset

if "snakemake" in globals():
    smk = snakemake  # noqa: F821
    sys.stderr = sys.stdout = open(smk.log[0], "w")  # noqa: SIM115
    ds = open_dataset(smk.input.energy)
    label = (f"profile {smk.params.profile}, scene impact/{ds.attrs['scene_name']} "
             f"({ds.attrs['material_model']}), "
             f"{int(run_fact(ds, 'n_particles'))} particles, "
             f"Delta = {1e3 * float(run_fact(ds, 'spacing')):g} mm")
    by_kappa = defaultdict(list)
    for run in smk.input.maps:
        by_kappa[float(run_metrics(open_dataset(run))["kappa"])].append(run)
    out = {k: Path(v) for k, v in smk.output.items()}
    figures.figure_opening_maps(by_kappa, out["opening_maps"], label)
    figures.figure_time_sequence(smk.input.sequence, out["time_sequence"], label)
    figures.figure_energy(Path(smk.input.energy), out["energy"], label)
    figures.figure_fragments(by_kappa, out["fragments"], label)
