r"""Accuracy versus cost of the lattice (error-versus-wall-time curve of the workflow).

Problem: the fundamental longitudinal mode of a column of fixed height H = 1, clamped at the
bottom, free at the top, periodic in x (so the strain is uniaxial and the long-wave speed is
the P-wave speed :math:`c_P = \sqrt{M/\rho_2}`, M = lambda + 2 mu of the lattice, spec
section 4). Reference solution [D]: the continuum period :math:`T = 4H/c_P` (exact for the
continuum the lattice approximates). The column is resolved with N free rows (spacing
:math:`h = H/(N + 1/2)`, the effective height of :mod:`craquelure.lattice.settlement`,
particle spacing :math:`L = h/(\sqrt3/2)`), with k_n, k_s and the disc density fixed, so M,
rho_2 and c_P do not depend on N. Started from rest in the continuum mode shape
:math:`u_y = u_0 \sin(\pi y/2H)`, the top row's mean displacement oscillates with the discrete
period; the period is measured from the upward zero crossings (linear interpolation) over
``periods`` periods. A discrete fixed-free chain has
:math:`\omega = 2\sqrt{k/m}\,\sin(\pi/(2(2N + 1)))`, so the relative period error falls as
:math:`(\pi/(2(2N+1)))^2/6 \propto N^{-2}` (lattice dispersion); the central-difference error
:math:`(\omega\,\Delta t)^2/24` of this slow mode is far smaller at dt = 0.2 dt_crit. Cost:
particles ~ N, steps ~ N, so the wall time grows as N^2 while the error falls as N^-2: error
~ 1/wall time. Wall and process-CPU times of the runs (compilation excluded) are measured.
"""

import math
import time

import numpy as np

from craquelure.lattice import beam
from craquelure.lattice.engine import lattice_system, stable_step_estimate
from craquelure.lattice.geometry import ROW, triangular_block
from craquelure.lattice.initial_state import probe_engine


def column_period(n_free_rows: int, nx: int = 4, ks_over_kn: float = 0.2,
                  dt_factor: float = 0.2, periods: int = 2, u0: float = 1e-4) -> dict:
    """One column run: measured and reference period, relative error, wall/CPU time."""
    height = 1.0
    spacing = height / ((n_free_rows + 0.5) * ROW)
    x, y, row = triangular_block(nx, n_free_rows + 1, L=spacing)
    c = beam.shear_beam(1.0, ks_over_kn, L=spacing)
    s = lattice_system(x, y, L=spacing, kn=c.kn, ka=c.a, kb=c.b, period_x=nx * spacing)
    s.fix[:, row == 0] = 1
    s.fix[0, :] = 1  # periodic column: no lateral motion (uniaxial strain by symmetry)
    moduli = beam.lattice_moduli(c.kn, c.ks)
    rho2 = float(s.mass[0]) / beam.cell_area(spacing)
    c_p = math.sqrt(moduli["M"] / rho2)
    t_ref = 4.0 * height / c_p
    dt = dt_factor * stable_step_estimate(s)
    eng = probe_engine(s, ("beams",), dict(dt=dt), series_every=10**9, parallel=False)
    y0 = s.y - s.y.min()
    shape = np.sin(0.5 * math.pi * y0 / height)
    eng.q[1] = s.y + u0 * shape
    eng.set_velocity(0.0, 0.0, 0.0)  # at rest: x(t - dt) = x
    eng.run(1)  # compile / load the cached kernel outside the timing
    eng.q[1] = s.y + u0 * shape
    eng.set_velocity(0.0, 0.0, 0.0)
    eng.step = 0
    top = row == row.max()
    # sample the top displacement ~256 times per period (kernel calls of `chunk` steps);
    # near a zero crossing the sine is linear to third order, so interpolation is exact to
    # far below the dispersion error
    chunk = max(1, int(round(t_ref / dt / 256)))
    n_samples = int(math.ceil((periods + 0.75) * t_ref / (dt * chunk)))
    n_steps = n_samples * chunk
    u = np.empty(n_samples + 1)
    u[0] = u0 * shape[top].mean()
    w0, c0 = time.perf_counter(), time.process_time()
    for k in range(n_samples):
        eng.run(chunk)
        u[k + 1] = eng.q[1][top].mean() - s.y[top].mean()
    wall, cpu = time.perf_counter() - w0, time.process_time() - c0
    dt_s = dt * chunk
    t = dt_s * np.arange(n_samples + 1)
    up = np.nonzero((u[:-1] < 0.0) & (u[1:] >= 0.0))[0]
    if up.size < 2:
        raise RuntimeError(f"column with {n_free_rows} rows: fewer than two zero crossings")
    crossings = t[up] - u[up] * dt_s / (u[up + 1] - u[up])
    period = float(np.mean(np.diff(crossings)))
    return {"rows": n_free_rows, "particles": s.n, "bonds": int(s.bi.size), "dt": dt,
            "steps": n_steps, "period": period, "reference_period": t_ref,
            "relative_error": abs(period / t_ref - 1.0), "wall_s": wall, "cpu_s": cpu,
            "chain_prediction": chain_error(n_free_rows)}


def chain_error(n_free_rows: int) -> float:
    """Relative period error of the fixed-free chain with N masses (sin x / x - 1)."""
    x = math.pi / (2.0 * (2 * n_free_rows + 1))
    return abs(x / math.sin(x) - 1.0)


def study(rows, **kwargs) -> list[dict]:
    return [column_period(int(n), **kwargs) for n in rows]


def convergence_order(results: list[dict]) -> float:
    """Log-log slope of the error versus the number of rows (expected -2)."""
    n = np.array([r["rows"] for r in results], float)
    e = np.array([r["relative_error"] for r in results])
    return float(np.polyfit(np.log(n), np.log(e), 1)[0])
