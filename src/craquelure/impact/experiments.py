"""Numerical experiments of the impact spec's checks that the tests, benchmarks and workflow
share (spec section 10).

:func:`crack_band_bar` is check 7: a 2D plane-strain bar (length ``length``, ``height_cells``
rows of spacing Δ) pulled at ±``speed`` by its two end columns on each side (velocity
prescribed, v_y = 0 there), started with the matching linear velocity profile so that the bar is
loaded quasi-statically from the first step. The "one weakened row" of the spec is a notch: the
top and bottom particles of the middle column get zero mass (they carry nothing), so the net
section is (n_y − 2)Δ and the crack localises there, not at the gripped ends. It runs until
the crack can be fully open: 1.3 × (w_c + 1.5 κ0 L)/(2 v), w_c = 2G_F/f_t. The dissipation is
Σ m (e_int − e_el − w_p): the stress work minus the (secant) elastic energy still stored and the
plastic work; kinetic energy and artificial viscosity are outside e_int by construction.
"""

from __future__ import annotations

import time

import numpy as np

from craquelure.impact.api import initial_state, settings, softening
from craquelure.impact.engine import Engine
from craquelure.impact.initial_state import build_specimen
from craquelure.scene import load_scene

BAR_EFFECTS = "[elasticity, plasticity, damage, artificial_viscosity, variable_smoothing_length]"


def crack_band_bar(spacing: float, height_cells: int, kappa: float = 1.0, speed: float = 0.05,
                   length: float = 0.2, overrides: tuple[str, ...] = ()) -> dict[str, float]:
    """Run the notched bar; returns dissipation / (G_F × net section) and diagnostics."""
    nx = int(round(length / spacing))
    scene = load_scene("impact/default", [
        "particles.shape=rectangle", f"particles.spacing={spacing}",
        f"particles.diameter_cells={nx}", f"particles.height_cells={height_cells}",
        "particles.impact_velocity=0.0", f"numerics.kappa={kappa}", f"effects={BAR_EFFECTS}",
        *overrides])
    sp = build_specimen(scene, 0)
    st = initial_state(scene, sp)
    x, y = sp.x, sp.y
    left, right = x < x.min() + 1.5 * spacing, x > x.max() - 1.5 * spacing
    ends = left | right
    col = np.rint(x / spacing - 0.5 * (nx % 2 == 0)).astype(int)  # middle column is 0
    notch = (col == 0) & ((y > y.max() - 0.01 * spacing) | (y < y.min() + 0.01 * spacing))
    st.m[notch] = 0.0
    eng = Engine(settings(scene), st)
    mat = eng.s.material
    st.vx[:] = speed * x / x.max()

    def drive():
        st.vx[left], st.vx[right], st.vy[ends] = -speed, speed, 0.0
        eng.ax[ends] = eng.ay[ends] = 0.0

    drive()
    t_end = 1.3 * (2 * mat.G_F / mat.f_t + 1.5 * mat.eps_0 * length) / (2 * speed)
    t0 = time.process_time()
    while eng.t < t_end:
        eng.step()
        drive()
        if eng.step_count % 500 == 0:
            eng.check_health()
    eng.check_health()
    cpu = time.process_time() - t0
    net = (height_cells - 2) * spacing
    e = eng.energies()
    s = softening(st.eps_max, mat)
    cols = np.unique(col)
    s_col = np.array([s[(col == c) & (st.m > 0)].mean() for c in cols])
    band = cols[s_col > 0.5]
    return {"ratio": e["damage"] / (mat.G_F * net), "band_width": mat.band,
            "band_columns": int(band.size), "band_first": int(band.min()) if band.size else 0,
            "band_last": int(band.max()) if band.size else 0,
            "max_softening_outside": float(s_col[np.abs(cols) > 3].max()),
            "elastic_left": e["elastic"] / (mat.G_F * net), "steps": eng.step_count,
            "particles": int(x.size), "cpu_seconds": cpu}


def lattice_gradient_factor(kappa: float, h_factor: float = 1.2, dim: int = 2) -> float:
    """g = −Σ_j V_j x_ij ∂W/∂x_i on the unit square (``dim`` 2) or cubic (3) lattice (exact
    value 1): the SPH gradient of a linear field at fixed h/Δ = κ h_factor. A long P wave then
    travels at g c_p: g − 1 is the resolution-independent floor of :func:`p_wave_mode`'s error."""
    from craquelure.sph.kernels import CUBIC, kernel_dwdr

    support = 2.0 * kappa * h_factor
    n = int(np.ceil(support))
    axis = np.arange(-n, n + 1, dtype=float)
    grid = np.meshgrid(*([axis] * dim), indexing="ij")
    r = np.sqrt(sum(g * g for g in grid)).ravel()
    xi = grid[0].ravel()
    inside = (r > 0.0) & (r < support)
    return -float(sum(x * x * kernel_dwdr(CUBIC, q, support, dim) / q
                      for x, q in zip(xi[inside], r[inside], strict=True)))


def p_wave_mode(spacing: float, kappa: float = 1.0, length: float = 0.2, cfl: float = 0.3,
                effects: tuple[str, ...] = ("elasticity",)) -> dict[str, float]:
    """Accuracy-versus-cost probe: the fundamental plane-strain P-wave mode of a strip
    ``length`` long and a few Δ high, h = 1.2 κ Δ, periodic both ways (a pure P wave), started
    with v_x = v0 sin(kx), k = 2π/length. ω is read from the first two zero crossings of the
    modal amplitude a(t) = Σ m v_x sin(kx) / Σ m sin²(kx) and compared with the exact k c_p.
    Returns the relative frequency error, the steps and the CPU seconds of the stepping loop.
    The error is (1 − g) + O((kΔ)²) with g of :func:`lattice_gradient_factor`: at fixed h/Δ SPH
    does not converge to the exact speed."""
    from craquelure.impact.api import probe_settings
    from craquelure.impact.engine import State
    from craquelure.impact.material import standard_concrete

    nx = int(round(length / spacing))
    rows = max(6, int(np.ceil(4.8 * kappa)) + 1)
    ix, iy = np.meshgrid(np.arange(nx), np.arange(rows), indexing="xy")
    x = (ix.ravel() + 0.5) * spacing
    y = (iy.ravel() + 0.5) * spacing
    rho0, v0 = 2400.0, 0.01
    k = 2.0 * np.pi / length
    st = State.grid(x, y, v0 * np.sin(k * x), 0.0, np.full(x.size, rho0 * spacing**2), rho0,
                    1.2 * kappa * spacing)
    s = probe_settings(material=standard_concrete(), rho0=rho0, spacing=spacing, effects=effects,
                       av_alpha=1.0, av_beta=2.0, as_epsilon=0.3, cfl=cfl,  # the spec's constants
                       periodic_box=(nx * spacing, rows * spacing))
    eng = Engine(s, st)
    omega = k * s.wave_speed
    weight = st.m * np.sin(k * x)
    norm = float(np.dot(weight, np.sin(k * x)))
    crossings = []
    prev_t, prev_a = 0.0, v0
    t0 = time.process_time()
    while len(crossings) < 2:
        eng.step()
        a = float(np.dot(weight, st.vx)) / norm
        if (a < 0.0) != (prev_a < 0.0):
            crossings.append(prev_t + (eng.t - prev_t) * prev_a / (prev_a - a))
        prev_t, prev_a = eng.t, a
        if eng.t > 4.0 * np.pi / omega:
            raise RuntimeError("no oscillation of the P-wave mode within two periods")
    cpu = time.process_time() - t0
    eng.check_health()
    measured = np.pi / (crossings[1] - crossings[0])
    return {"spacing": spacing, "kappa": kappa, "particles": int(x.size), "steps": eng.step_count,
            "omega_exact": omega, "omega": measured,
            "error": abs(measured / omega - 1.0), "cpu_seconds": cpu}
