"""Static-strength sensitivity of the 3D disc (config impact.strength_sweep): measure each run,
write strength_sweep.json and the opening-map figure."""

import json
import sys
from pathlib import Path

from craquelure.impact.figures import figure_strength_sweep
from craquelure.impact.regime import strength_row
from craquelure.io import write_text_atomic
from craquelure.scene import load_scene

if "snakemake" in globals():
    smk = snakemake  # noqa: F821
    sys.stderr = sys.stdout = open(smk.log[0], "w")  # noqa: SIM115
    sweep = smk.config["impact"]["strength_sweep"]
    base = load_scene(f"impact/{sweep['scene']}").get("material.f_t")
    rows = sorted((strength_row(Path(p), base) for p in smk.input),
                  key=lambda r: (r["factor"], r["masses"] != "homogeneous", r["seed"]))
    write_text_atomic(Path(smk.output.json), json.dumps(
        {"profile": smk.params.profile, "kind": "sensitivity (not judged)", **sweep,
         "base_f_t": base, "runs": rows}, indent=2) + "\n")
    figure_strength_sweep(rows, Path(smk.output.png),
                          f"profile {smk.params.profile}, scene impact/{sweep['scene']}")
    for r in rows:
        print(f"f_t x{r['factor']:g} {r['masses']} seed {r['seed']}: {r['n_main_cracks']} main "
              f"(x = {r['main_runs_x_mm']} mm), F/F_s = {r['strength_to_load']:.2f}")
