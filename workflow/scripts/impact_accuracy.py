"""Impact accuracy versus cost: P-wave mode frequency error against the exact k c_p for each
kappa and particle spacing (config impact.accuracy), CPU time measured; JSON + report figure."""

import json
import sys
from pathlib import Path

import numba

from craquelure.impact.experiments import lattice_gradient_factor, p_wave_mode
from craquelure.impact.figures import figure_accuracy
from craquelure.io import write_text_atomic

if "snakemake" in globals():
    smk = snakemake  # noqa: F821
    numba.set_num_threads(smk.threads)
    sys.stderr = sys.stdout = open(smk.log[0], "w")  # noqa: SIM115
    spacings, kappas = smk.params.spacings, smk.params.kappas
    p_wave_mode(max(spacings), kappas[0])  # compile (or load the cache) before timing
    rows = []
    for kappa in kappas:
        for spacing in spacings:
            row = p_wave_mode(spacing, kappa)
            rows.append(row)
            print(f"kappa = {kappa:g}, Delta = {spacing * 1e3:g} mm: error {row['error']:.4g}, "
                  f"{row['steps']} steps, {row['cpu_seconds']:.3g} CPU s", flush=True)
    floors = {k: 1.0 - lattice_gradient_factor(k) for k in kappas}
    result = {"profile": smk.params.profile, "reference": "exact omega = k c_p, c_p = 3616 m/s",
              "runs": rows, "lattice_floor": {str(k): v for k, v in floors.items()}}
    write_text_atomic(Path(smk.output.json), json.dumps(result, indent=1))
    label = (f"profile {smk.params.profile}; 2D periodic strip 0.2 m, h = 1.2 kappa Delta, "
             f"elastic, cfl 0.3")
    figure_accuracy(rows, floors, Path(smk.output.png), label)
