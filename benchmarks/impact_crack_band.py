"""Check 7 (crack band in SPH) as a measurement, not a unit test (minutes at 2 mm): a
200 x 40 mm bar pulled at +-0.05 m/s at its end columns, with one slightly pre-damaged column
(kappa = 1.02 kappa0) to localise the crack; prints the damage dissipation per crack area over
G_F and the band width while the crack opens.

    .venv/bin/python benchmarks/impact_crack_band.py 0.004   # spacing [m]; then 0.002
"""

import sys
import time

import numba
import numpy as np

from craquelure.impact.api import initial_state, settings, softening
from craquelure.impact.engine import Engine
from craquelure.impact.specimen import build_specimen
from craquelure.scene import load_scene


def main(dx: float, speed: float = 0.05) -> None:
    numba.set_num_threads(1)
    nx, ny = int(round(0.2 / dx)), int(round(0.04 / dx))
    scene = load_scene("impact/default", [
        "particles.shape=rectangle", f"particles.spacing={dx}", f"particles.diameter_cells={nx}",
        f"particles.height_cells={ny}", "particles.impact_velocity=0.0",
        "effects=[elasticity, plasticity, damage, artificial_viscosity, "
        "variable_smoothing_length]"])
    sp = build_specimen(scene, 0)
    st = initial_state(scene, sp)
    x = sp.x
    left, right = x < x.min() + 1.5 * dx, x > x.max() - 1.5 * dx
    ends = left | right
    eng = Engine(settings(scene), st)
    mat = eng.s.material
    st.kap[np.abs(x - 0.5 * dx) < 0.01 * dx] = 1.02 * mat.kappa0
    st.vx[:] = speed * x / x.max()
    height = ny * dx

    def drive():
        st.vx[left], st.vx[right], st.vy[ends] = -speed, speed, 0.0
        eng.ax[ends] = 0.0
        eng.ay[ends] = 0.0

    drive()
    t_end = 1.3 * (2 * mat.G_F / mat.f_t + mat.kappa0 * 0.2 * 1.5) / (2 * speed)
    t0 = time.perf_counter()
    while eng.t < t_end:
        eng.step()
        drive()
        if eng.step_count % 2000 == 0:
            e = eng.energies()
            band = np.sum(softening(st.kap, mat) > 0.5) / ny
            print(f"t = {eng.t * 1e6:7.1f} us: damage dissipation / (G_F H) = "
                  f"{e['damage'] / height / mat.G_F:.3f}, elastic {e['elastic']:.3g} J/m, "
                  f"band {band:.1f} columns", flush=True)
    e = eng.energies()
    print(f"dx = {dx}: {eng.step_count} steps in {time.perf_counter() - t0:.0f} s; "
          f"dissipation / (G_F H) = {e['damage'] / height / mat.G_F:.3f} (check 7: 1 +- 0.2)")


if __name__ == "__main__":
    main(float(sys.argv[1]) if len(sys.argv) > 1 else 0.004)
