"""Regime map of the homogeneous disc in 2D and, if configured, 3D: classify each short run,
write regime.json (both dimensions) and the figure."""

import json
import sys
from pathlib import Path

from craquelure.impact.regime import figure_regime, regime_maps, regime_row
from craquelure.io import write_text_atomic

if "snakemake" in globals():
    smk = snakemake  # noqa: F821
    sys.stderr = sys.stdout = open(smk.log[0], "w")  # noqa: SIM115
    rows = [regime_row(Path(p)) for p in smk.input]
    maps = regime_maps(rows)
    label = f"profile {smk.params.profile}, " + ", ".join(
        f"{dim}: scene impact/{'/'.join(m['scene'])}, {m['n_runs']} runs"
        for dim, m in maps.items())
    write_text_atomic(Path(smk.output.json), json.dumps(
        {"profile": smk.params.profile, "dims": list(maps), "maps": maps, "runs": rows},
        indent=2) + "\n")
    figure_regime(rows, Path(smk.output.png), label)
    for r in rows:
        print(f"{r['dim']} f_t {r['f_t'] / 1e6:.3g} MPa, a {r['contact_a']:.3g}, "
              f"v {r['impact_velocity']:g} m/s: {r['class']} ({r['n_main_cracks']} main, "
              f"{r['n_main_cracks_softening']} by softening; this class from "
              f"{1e6 * (r['class_settled_from'] or r['t_end']):.0f} us of {1e6 * r['t_end']:.0f})")
