"""Check 7 (crack band in SPH) at any resolution and kappa, with its CPU time: the notched
200 mm bar of :func:`craquelure.impact.experiments.crack_band_bar` pulled at +-0.05 m/s; prints the
dissipation per crack area over G_F, the band width in columns and l_c.

    .venv/bin/python benchmarks/impact_crack_band.py 0.004 10 1.0  # spacing [m], rows, kappa
"""

import sys

import numba

from craquelure.impact.experiments import crack_band_bar


def main(spacing: float, rows: int, kappa: float) -> None:
    numba.set_num_threads(1)
    out = crack_band_bar(spacing, rows, kappa)
    print(f"Delta = {spacing * 1e3:g} mm, {rows} rows ({out['particles']} particles), "
          f"kappa = {kappa}: dissipation / (G_F A) = {out['ratio']:.3f} (check 7: 1 +- 0.2); "
          f"band {out['band_columns']} columns, l_c = {out['band_width'] * 1e3:g} mm; "
          f"{out['steps']} steps in {out['cpu_seconds']:.1f} CPU s")


if __name__ == "__main__":
    args = sys.argv[1:]
    main(float(args[0]) if args else 0.004, int(args[1]) if len(args) > 1 else 10,
         float(args[2]) if len(args) > 2 else 1.0)
