"""Roofline of the drying pair kernel (issue 28, item 2) at N = 4e4 (drying density, h = 0.2,
the Verlet list within 1.1 h, cell-sorted RSA positions as ``craquelure init`` stores them),
one numba thread, CPU time:

- pair visits/s of one rate evaluation (both passes; a visit = one listed pair in one pass) for
  the kernel before this issue (the copy below, ``reference_rate``) and the current one, side by
  side in this process, with the largest difference of their outputs;
- each pass of the current kernel alone;
- flops and bytes per pair visit, counted from the kernel source (table ``COUNT``: FMA = 2
  flops, sqrt and divide 1 each, rint / max / selects 0; bytes: the streamed CSR index and the
  gathered per-particle values);
- the core's peak, measured by an FMA loop compiled with the kernel's numba options
  (fastmath, error model), and a gather roof: a loop doing only the kernel's gathers;
- the vector instructions in the generated code (zmm/ymm registers, vfmadd, vgather, packed
  sqrt/divide), from numba's ``inspect_asm`` of a fresh compilation.

    python benchmarks/drying_roofline.py [--n 40000] [--repeats 5]
"""

from __future__ import annotations

import argparse
import os
import re
import sys
import tempfile
import time
from pathlib import Path

import numba
import numpy as np
from numba import njit, prange

from craquelure.drying.effects.continuity import density_rate
from craquelure.drying.effects.drying import drying_stress
from craquelure.drying.effects.elasticity import jaumann_rate
from craquelure.drying.effects.gradient_correction import corrected_gradient
from craquelure.drying.effects.substrate import substrate_acceleration
from craquelure.drying.effects.viscosity import viscous_stress
from craquelure.periodic import minimum_image
from craquelure.sph.kernels import kernel_dwdr, kernel_w_dwdr

sys.path.insert(0, str(Path(__file__).resolve().parent))
from sph_engine import EFFECT_SETS, scene_for  # noqa: E402

X, Y, VX, VY, RHO, SXX, SYY, SXY = 0, 1, 2, 3, 4, 5, 6, 7
NVAR = 8
P_LAMBDA, P_MU, P_ETA, P_VR, P_THICK, P_EPS, P_SUPPORT, P_BOX, P_DRYCAP = range(9)
# the reference's flags: the drying scene's 7 effects
CONTINUITY = DRYING = ELASTICITY = SUBSTRATE = VISCOSITY = XSPH = True
GRADIENT_CORRECTION = False
KERNEL = 0
# Per pair visit, read off the current kernel (kernel_template.gradient_pass / momentum_pass, all
# 7 effects): (flops, streamed bytes, gathered bytes) of pass 1 and pass 2.
#  pass 1: minimum image 2 x 4, r^2 3, kernel_w_g 32 (sqrt, divide, x = r/s 2, 3x 1, three
#          clamps' subtractions 3, fourth powers 9, f 7, d 4, W 1, g 3), dv 2, the shared
#          divide for V_J and 1/(rho_I + rho_J) 6 (sum, product, divide, V_J 2, 1/sum 1), XSPH
#          8 (2 m_J, times 1/sum, times W, two components, two sums), V_J g and its two
#          components 3, L sums 4 FMA = 8: 70; index 8 B; gathers x, y, vx, vy, m, rho = 48 B
#  pass 2: minimum image 8, r^2 3, g only 24, m_J g and components 3, sigma sums 3,
#          accelerations 2 x 4 = 8 = 49; index 8 B; gathers x, y, m, sigma/rho^2 x 3 = 48 B
COUNT = {"pass 1": (70, 8, 48), "pass 2": (49, 8, 48)}


# -- the kernel before issue 28 (commit 58dba0d), the side-by-side reference -------------------
@njit(parallel=True)
def reference_rate(state, t, mass, alive, x0, y0, offsets, index, p, out, stress):
    """The drying rate before issue 28 (all 7 effects, quintic): piecewise quintic, per-pair
    store of dW/dr / r, signed loop index, divisions in the minimum image."""
    n = state.shape[1]
    s = p[P_SUPPORT]
    box = p[P_BOX]
    s2 = s * s
    # Per-particle factors hoisted out of the pair loops: V_J = m_J/rho_J (pass 1) and
    # sigma_J/rho_J^2 (pass 2).
    volume = np.empty(n)
    # dW/dr / r of every listed pair, written by pass 1 for every pair of a present particle
    # and reused by pass 2 (0 beyond the support and for coincident particles)
    gfac = np.empty(index.size)
    for i in prange(n):
        volume[i] = mass[i] / state[RHO, i] if alive[i] else 0.0
    for i in prange(n):
        if not alive[i]:
            for v in range(NVAR):
                out[v, i] = 0.0
            stress[0, i] = 0.0
            stress[1, i] = 0.0
            stress[2, i] = 0.0
            continue
        xi, yi = state[X, i], state[Y, i]
        vxi, vyi = state[VX, i], state[VY, i]
        rhoi = state[RHO, i]
        lxx = 0.0
        lxy = 0.0
        lyx = 0.0
        lyy = 0.0
        hx = 0.0
        hy = 0.0
        mxx = 0.0
        mxy = 0.0
        myx = 0.0
        myy = 0.0
        for k in range(offsets[i], offsets[i + 1]):
            j = index[k]
            dx = minimum_image(xi - state[X, j], box)
            dy = minimum_image(yi - state[Y, j], box)
            r2 = dx * dx + dy * dy
            if r2 >= s2:
                gfac[k] = 0.0
                continue
            r = np.sqrt(r2)
            dvx = state[VX, j] - vxi
            dvy = state[VY, j] - vyi
            if XSPH:
                w, dwdr = kernel_w_dwdr(KERNEL, r, s, 2)
            else:
                w, dwdr = 0.0, kernel_dwdr(KERNEL, r, s, 2)
            g = dwdr / r if r > 0.0 else 0.0
            gfac[k] = g
            if r > 0.0:
                f = volume[j] * g
                gx = f * dx
                gy = f * dy
                lxx += dvx * gx
                lxy += dvx * gy
                lyx += dvy * gx
                lyy += dvy * gy
                if GRADIENT_CORRECTION:
                    # r_J - r_I = -(dx, dy)
                    mxx -= dx * gx
                    mxy -= dx * gy
                    myx -= dy * gx
                    myy -= dy * gy
            if XSPH:
                f = mass[j] / (0.5 * (rhoi + state[RHO, j])) * w
                cx, cy = f * dvx, f * dvy
                hx += cx
                hy += cy
        if GRADIENT_CORRECTION:
            lxx, lxy, lyx, lyy = corrected_gradient(lxx, lxy, lyx, lyy, mxx, mxy, myx, myy)
        sxx = state[SXX, i]
        syy = state[SYY, i]
        sxy = state[SXY, i]
        if VISCOSITY:
            vxx, vyy, vxy = viscous_stress(lxx, lxy, lyx, lyy, p[P_ETA])
            sxx += vxx
            syy += vyy
            sxy += vxy
        if DRYING:
            dry = drying_stress(t, p[P_VR], p[P_DRYCAP])
            sxx += dry
            syy += dry
        stress[0, i] = sxx
        stress[1, i] = syy
        stress[2, i] = sxy
        if ELASTICITY:
            a, b, c = jaumann_rate(lxx, lxy, lyx, lyy, state[SXX, i], state[SYY, i],
                                   state[SXY, i], p[P_LAMBDA], p[P_MU])
            out[SXX, i] = a
            out[SYY, i] = b
            out[SXY, i] = c
        else:
            out[SXX, i] = 0.0
            out[SYY, i] = 0.0
            out[SXY, i] = 0.0
        if CONTINUITY:
            out[RHO, i] = density_rate(rhoi, lxx, lyy)
        else:
            out[RHO, i] = 0.0
        if XSPH:
            out[X, i] = vxi + p[P_EPS] * hx
            out[Y, i] = vyi + p[P_EPS] * hy
        else:
            out[X, i] = vxi
            out[Y, i] = vyi
    scaled = np.empty((3, n))
    for i in prange(n):
        inv2 = 1.0 / (state[RHO, i] * state[RHO, i])
        scaled[0, i] = stress[0, i] * inv2
        scaled[1, i] = stress[1, i] * inv2
        scaled[2, i] = stress[2, i] * inv2
    for i in prange(n):
        if not alive[i]:
            continue
        xi, yi = state[X, i], state[Y, i]
        rhoi = state[RHO, i]
        axx = scaled[0, i]
        ayy = scaled[1, i]
        axy = scaled[2, i]
        ax = 0.0
        ay = 0.0
        for k in range(offsets[i], offsets[i + 1]):
            g = gfac[k]
            if g == 0.0:
                continue
            j = index[k]
            dx = minimum_image(xi - state[X, j], box)
            dy = minimum_image(yi - state[Y, j], box)
            f = mass[j] * g
            gx = f * dx
            gy = f * dy
            txx = axx + scaled[0, j]
            tyy = ayy + scaled[1, j]
            txy = axy + scaled[2, j]
            ax += txx * gx + txy * gy
            ay += txy * gx + tyy * gy
        if SUBSTRATE:
            bx, by = substrate_acceleration(xi - x0[i], yi - y0[i], rhoi, p[P_MU], p[P_THICK])
            ax += bx
            ay += by
        out[VX, i] = ax
        out[VY, i] = ay


# -- machine roofs ---------------------------------------------------------------------------
@njit(fastmath={"reassoc", "contract", "nsz"}, error_model="numpy")
def fma_loop(y, m, c, repeats):
    """8 dependent FMAs per element on an L1-resident array (independent across elements, so
    the loop vectorises and the FMA pipes, not latency, set the rate): 16 flops per element."""
    for _ in range(repeats):
        for k in range(y.size):
            v = y[k]
            v = v * m + c
            v = v * m + c
            v = v * m + c
            v = v * m + c
            v = v * m + c
            v = v * m + c
            v = v * m + c
            v = v * m + c
            y[k] = v


@njit(parallel=True, fastmath={"reassoc", "contract", "nsz"}, error_model="numpy")
def gather_loop(offsets, index, a, b, c, d, e, f):
    """Only the gathers of pass 1 (six per-particle arrays through the CSR index) and a sum."""
    total = 0.0
    for i in prange(offsets.size - 1):
        acc = 0.0
        for k in range(np.uint64(offsets[i]), np.uint64(offsets[i + 1])):
            j = index[k]
            acc += a[j] + b[j] + c[j] + d[j] + e[j] + f[j]
        total += acc
    return total


def cpu_time(fn, repeats: int) -> float:
    """Best of 5 rounds of ``repeats`` calls, CPU seconds per call."""
    fn()
    best = float("inf")
    for _ in range(5):
        start = time.process_time()
        for _ in range(repeats):
            fn()
        best = min(best, (time.process_time() - start) / repeats)
    return best


def vector_instructions(functions) -> dict[str, int]:
    asm = "\n".join("\n".join(f.inspect_asm().values()) for f in functions)
    patterns = {"zmm": r"%zmm", "ymm": r"%ymm", "vfmadd/vfnmadd": r"\bvfn?m(add|sub)\w*pd",
                "vgather": r"\bvgather\w+", "vsqrtpd": r"\bvsqrtpd", "vdivpd": r"\bvdivpd",
                "scalar vsqrtsd": r"\bvsqrtsd", "scalar vdivsd": r"\bvdivsd"}
    return {k: len(re.findall(p, asm)) for k, p in patterns.items()}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=40000)
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    # a fresh cache folder: the generated kernel is compiled here, so its assembly can be read
    os.environ["CRAQUELURE_CACHE"] = tempfile.mkdtemp(prefix="craquelure-roofline-")
    numba.set_num_threads(1)
    from craquelure.drying.engine import DryingEngine
    from craquelure.drying.positions import random_sequential_addition
    from craquelure.sph.neighbours import Box, cell_order

    n = args.n
    length = float(np.sqrt(n) / 20.0)
    rng = np.random.default_rng(0)
    x, y = random_sequential_addition(n, length, 0.8 * length / np.sqrt(n), rng)
    order = cell_order(x, y, 0.2, Box.square(length))
    x, y = x[order], y[order]
    mass = length**2 / n * rng.uniform(0.5, 1.5, n)
    stress0 = rng.uniform(-5e-5, 5e-5, (3, n))
    engine = DryingEngine(scene_for(n, EFFECT_SETS["drying (all 7)"]), x, y, mass,
                          rng.uniform(0.99, 1.01, n), stress0)
    engine.state[VX:VY + 1] = rng.uniform(-1e-4, 1e-4, (2, n))
    engine.state[X:Y + 1] += rng.uniform(-1e-3, 1e-3, (2, n))
    st, p, pairs = engine.state, engine.params, engine.index.size
    args_rate = (st, 50.0, engine.mass, engine.alive, engine.x0, engine.y0, engine.offsets,
                 engine.index, p)
    mod = engine.rate_module
    out_new, s_new = np.empty_like(st), np.empty((3, n))
    out_ref, s_ref = np.empty_like(st), np.empty((3, n))
    t_ref = cpu_time(lambda: reference_rate(*args_rate, out_ref, s_ref), args.repeats)
    t_new = cpu_time(lambda: mod.rate(*args_rate, out_new, s_new), args.repeats)
    scaled = np.empty((3, n))
    t_p1 = cpu_time(lambda: mod.gradient_pass(st, 50.0, engine.mass, engine.alive,
                                              engine.offsets, engine.index, p,
                                              out_new, s_new, scaled), args.repeats)
    t_p2 = cpu_time(lambda: mod.momentum_pass(st, engine.mass, engine.alive, engine.x0,
                                              engine.y0, engine.offsets, engine.index, p,
                                              scaled, out_new), args.repeats)
    mod.rate(*args_rate, out_new, s_new)
    rows = ["x", "y", "vx", "vy", "rho", "sxx", "syy", "sxy"]
    diff = {r: float(np.abs(out_new[k] - out_ref[k]).max() / np.abs(out_ref[k]).max())
            for k, r in enumerate(rows)}
    diff["stress"] = float(np.abs(s_new - s_ref).max() / np.abs(s_ref).max())
    print(f"# N = {n}, listed pairs per pass {pairs} ({pairs / n:.1f} per particle), "
          f"numba {numba.__version__}, 1 thread, CPU time, best of 5 x {args.repeats}")
    print(f"{'kernel':<34} {'ms/eval':>8} {'pair visits/s':>14}")
    print(f"{'before (reference_rate)':<34} {1e3 * t_ref:>8.2f} {2 * pairs / t_ref:>14.3e}")
    print(f"{'current (kernel_template.rate)':<34} {1e3 * t_new:>8.2f} {2 * pairs / t_new:>14.3e}"
          f"   {t_ref / t_new:.2f}x")
    print(f"{'  pass 1 (L, XSPH, stress, rates)':<34} {1e3 * t_p1:>8.2f} {pairs / t_p1:>14.3e}")
    print(f"{'  pass 2 (momentum, substrate)':<34} {1e3 * t_p2:>8.2f} {pairs / t_p2:>14.3e}")
    print("largest |current - before| / max|before| per rate row: "
          + ", ".join(f"{k} {v:.1e}" for k, v in diff.items()))
    # peak: 1024 doubles (8 KB, L1), 16 flops per element per repeat
    yv = np.ones(1024)
    reps = 20000
    t_fma = cpu_time(lambda: fma_loop(yv, 0.999999, 1e-6, reps), 1)
    peak = 16 * yv.size * reps / t_fma
    cols = [st[X], st[Y], st[VX], st[VY], engine.mass, st[RHO]]
    t_gather = cpu_time(lambda: gather_loop(engine.offsets, engine.index, *cols), args.repeats)
    print(f"measured FMA peak (numba, same options): {peak / 1e9:.1f} Gflop/s; gather roof "
          f"(pass 1's 6 gathers only): {pairs / t_gather:.3e} pair visits/s")
    for label, t, (flops, streamed, gathered) in (("pass 1", t_p1, COUNT["pass 1"]),
                                                 ("pass 2", t_p2, COUNT["pass 2"])):
        rate = pairs / t
        print(f"{label}: {flops} flops, {streamed} B streamed + {gathered} B gathered per visit;"
              f" intensity {flops / streamed:.1f} flop/B streamed, "
              f"{flops / (streamed + gathered):.2f} flop/B loaded; attained "
              f"{flops * rate / 1e9:.1f} Gflop/s = {100 * flops * rate / peak:.0f} % of peak")
    total_flops = sum(c[0] for c in COUNT.values())
    print(f"whole evaluation: {total_flops * pairs / t_new / 1e9:.1f} Gflop/s = "
          f"{100 * total_flops * pairs / t_new / peak:.0f} % of peak")
    print("vector instructions, current kernel:",
          vector_instructions([mod.gradient_pass, mod.momentum_pass]))
    print("vector instructions, before:", vector_instructions([reference_rate]))


if __name__ == "__main__":
    main()
