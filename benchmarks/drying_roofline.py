"""Roofline of the drying pair kernel at the Table I scene's size and density (N = 4e4, L = 10,
h = 0.2, Verlet radius 1.1 h, cell-sorted RSA positions as ``craquelure init`` stores them),
in CPU time (so two threads' figures are per core):

- per rate evaluation (both pair passes), side by side in this process and alternated: the
  cluster-pair kernel (``drying/kernel_template.py``: clusters of LANES particles in SIMD
  lanes, each listed J broadcast, no gather) and the gather kernel it replaced (commit 4db0bf1,
  copied below: a CSR Verlet list, every neighbour's values loaded by index), on one and on two
  numba threads;
- pair visits counted per pass: *useful* = ordered pairs closer than h (the pairs whose terms
  are not 0), *masked* = the visits beyond h (the gather kernel's skin pairs; the cluster
  kernel's lanes farther from J than h, its skin included); both kernels compute the same
  useful pairs, so useful visits/s compares them directly;
- each pass of the cluster kernel alone, and what one lane visit costs against the core's
  roofs: an FMA loop, a loop of one square root and one division per element (the kernel's
  divider work per lane: 1/r shared with XSPH in pass 1, 1/r in pass 2), and the gather kernel's
  gather roof (a loop doing only pass 1's six gathers);
- the vector instructions of the generated code (numba ``inspect_asm`` of a fresh compilation).

``--write FILE`` writes the summary table as Markdown (benchmarks/tables/drying_kernel.md, included
by docs/performance.md and config/README.md).

    python benchmarks/drying_roofline.py [--n 40000] [--repeats 5] [--rounds 3]
        [--write benchmarks/tables/drying_kernel.md]
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
from craquelure.drying.effects.xsph import xsph_pair
from craquelure.periodic import minimum_image_inv
from craquelure.sph.kernels import kernel_w_g

sys.path.insert(0, str(Path(__file__).resolve().parent))
from sph_engine import EFFECT_SETS, scene_for  # noqa: E402

X, Y, VX, VY, RHO, SXX, SYY, SXY = 0, 1, 2, 3, 4, 5, 6, 7
NVAR = 8
P_LAMBDA, P_MU, P_ETA, P_VR, P_THICK, P_EPS, P_SUPPORT, P_BOX, P_DRYCAP = range(9)
# the gather kernel's flags: the drying scene's 7 effects
CONTINUITY = DRYING = ELASTICITY = SUBSTRATE = VISCOSITY = XSPH = True
GRADIENT_CORRECTION = False
KERNEL = 0
FASTMATH = {"reassoc", "contract", "nsz"}
GATHER_OPTIONS = dict(parallel=True, fastmath=FASTMATH, error_model="numpy")


# -- the gather kernel of commit 4db0bf1, the side-by-side reference --------------------------
@njit
def gather_rate(state, t, mass, alive, x0, y0, offsets, index, p, out, stress):
    """The drying rate of commit 4db0bf1 (all 7 effects, quintic): CSR Verlet list, every
    neighbour's values gathered by index, vectorised over each particle's list."""
    scaled = np.empty((3, state.shape[1]))
    gather_gradient_pass(state, t, mass, alive, offsets, index, p, out, stress, scaled)
    gather_momentum_pass(state, mass, alive, x0, y0, offsets, index, p, scaled, out)


@njit(**GATHER_OPTIONS)
def gather_gradient_pass(state, t, mass, alive, offsets, index, p, out, stress, scaled):
    """Pass 1: L, XSPH, the total stress (and sigma/rho^2 for pass 2) and every rate but the
    velocity's."""
    n = state.shape[1]
    s = p[P_SUPPORT]
    inv_s = 1.0 / s
    box = p[P_BOX]
    inv_box = 1.0 / box
    xs, ys, vxs, vys, rhos = state[X], state[Y], state[VX], state[VY], state[RHO]
    for i in prange(n):
        if not alive[i]:
            for v in range(NVAR):
                out[v, i] = 0.0
            stress[0, i] = 0.0
            stress[1, i] = 0.0
            stress[2, i] = 0.0
            scaled[0, i] = 0.0
            scaled[1, i] = 0.0
            scaled[2, i] = 0.0
            continue
        xi, yi = xs[i], ys[i]
        vxi, vyi = vxs[i], vys[i]
        rhoi = rhos[i]
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
        # branch-free pair loop (vectorised by LLVM): pairs beyond the support and coincident
        # particles have w = g = 0 and add exactly 0. An unsigned k makes index[k] a plain
        # load (a signed one gets numba's negative-index wraparound, which LLVM turns into a
        # gather of the index array: 8x slower)
        for k in range(np.uint64(offsets[i]), np.uint64(offsets[i + 1])):
            j = index[k]
            dx = minimum_image_inv(xi - xs[j], box, inv_box)
            dy = minimum_image_inv(yi - ys[j], box, inv_box)
            w, g = kernel_w_g(KERNEL, dx * dx + dy * dy, s, inv_s)
            dvx = vxs[j] - vxi
            dvy = vys[j] - vyi
            mj = mass[j]
            rhoj = rhos[j]
            if XSPH:
                # one division gives V_J = m_J/rho_J and 1/(rho_I + rho_J) for XSPH
                rsum = rhoi + rhoj
                dinv = 1.0 / (rhoj * rsum)
                vj = mj * (rsum * dinv)
                cx, cy = xsph_pair(mj, rhoj * dinv, dvx, dvy, w)
                hx += cx
                hy += cy
            else:
                vj = mj / rhoj
            f = vj * g
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
        inv2 = 1.0 / (rhoi * rhoi)
        scaled[0, i] = sxx * inv2
        scaled[1, i] = syy * inv2
        scaled[2, i] = sxy * inv2
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


@njit(**GATHER_OPTIONS)
def gather_momentum_pass(state, mass, alive, x0, y0, offsets, index, p, scaled, out):
    """Pass 2: the velocity rate (pairwise antisymmetric momentum sum + substrate)."""
    n = state.shape[1]
    s = p[P_SUPPORT]
    inv_s = 1.0 / s
    box = p[P_BOX]
    inv_box = 1.0 / box
    xs, ys, rhos = state[X], state[Y], state[RHO]
    sxxs, syys, sxys = scaled[0], scaled[1], scaled[2]
    for i in prange(n):
        if not alive[i]:
            continue
        xi, yi = xs[i], ys[i]
        rhoi = rhos[i]
        axx = scaled[0, i]
        ayy = scaled[1, i]
        axy = scaled[2, i]
        ax = 0.0
        ay = 0.0
        for k in range(np.uint64(offsets[i]), np.uint64(offsets[i + 1])):
            j = index[k]
            dx = minimum_image_inv(xi - xs[j], box, inv_box)
            dy = minimum_image_inv(yi - ys[j], box, inv_box)
            # g recomputed, not stored by pass 1: a per-pair store stops the vectoriser (it
            # cannot rule out aliasing) and costs more memory traffic than the arithmetic
            _, g = kernel_w_g(KERNEL, dx * dx + dy * dy, s, inv_s)
            f = mass[j] * g
            gx = f * dx
            gy = f * dy
            txx = axx + sxxs[j]
            tyy = ayy + syys[j]
            txy = axy + sxys[j]
            ax += txx * gx + txy * gy
            ay += txy * gx + tyy * gy
        if SUBSTRATE:
            bx, by = substrate_acceleration(xi - x0[i], yi - y0[i], rhoi, p[P_MU], p[P_THICK])
            ax += bx
            ay += by
        out[VX, i] = ax
        out[VY, i] = ay


# -- machine roofs ---------------------------------------------------------------------------
@njit(fastmath=FASTMATH, error_model="numpy")
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


@njit(fastmath=FASTMATH, error_model="numpy")
def divider_loop(a, out, repeats):
    """One square root and one division per element (vectorised): the divider's work per lane
    visit of either pass."""
    for _ in range(repeats):
        for k in range(a.size):
            out[k] = 1.0 / np.sqrt(a[k])


@njit(parallel=True, fastmath=FASTMATH, error_model="numpy")
def gather_loop(offsets, index, a, b, c, d, e, f):
    """Only the gathers of the gather kernel's pass 1 (six per-particle arrays through the CSR
    index) and a sum."""
    total = 0.0
    for i in prange(offsets.size - 1):
        acc = 0.0
        for k in range(np.uint64(offsets[i]), np.uint64(offsets[i + 1])):
            j = index[k]
            acc += a[j] + b[j] + c[j] + d[j] + e[j] + f[j]
        total += acc
    return total


def cpu_time(fn, repeats: int, rounds: int = 5) -> float:
    """Best of ``rounds`` rounds of ``repeats`` calls, CPU seconds (all threads) per call."""
    fn()
    best = float("inf")
    for _ in range(rounds):
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
    parser.add_argument("--rounds", type=int, default=3,
                        help="alternations of the two kernels (best of all rounds)")
    parser.add_argument("--write", type=Path, help="write the summary table (Markdown)")
    args = parser.parse_args()
    # a fresh cache folder: the generated kernel is compiled here, so its assembly can be read
    os.environ["CRAQUELURE_CACHE"] = tempfile.mkdtemp(prefix="craquelure-roofline-")
    from craquelure.drying.engine import DryingEngine
    from craquelure.drying.kernel_template import LANES
    from craquelure.drying.positions import random_sequential_addition
    from craquelure.sph.neighbours import Box, cell_order, neighbour_list

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
    engine.rebuild()
    st, p, h = engine.state, engine.params, engine.h
    offsets, index = neighbour_list(st[X], st[Y], h + engine.skin, engine.box)
    useful = neighbour_list(st[X], st[Y], h, engine.box)[1].size  # ordered pairs within h
    listed = index.size
    lanes = LANES * engine.pairs.jlist.size
    common = (st, 50.0, engine.mass, engine.alive, engine.x0, engine.y0)
    mod = engine.rate_module
    out_c, s_c = np.empty_like(st), np.empty((3, n))
    out_g, s_g = np.empty_like(st), np.empty((3, n))
    cluster = lambda: mod.rate(*common, engine.pairs, p, out_c, s_c)  # noqa: E731
    gather = lambda: gather_rate(*common, offsets, index, p, out_g, s_g)  # noqa: E731
    times = {}
    for threads in (1, 2):
        numba.set_num_threads(threads)
        for _ in range(args.rounds):
            for name, fn in (("gather", gather), ("cluster", cluster)):
                t = cpu_time(fn, args.repeats, rounds=2)
                times[name, threads] = min(times.get((name, threads), np.inf), t)
    numba.set_num_threads(1)
    perm, start, jlist, _ = engine.pairs
    c = np.empty((mod.NC, perm.size))
    scaled = np.empty((3, perm.size))
    mod.to_clusters(st, engine.mass, perm, c)
    t_p1 = cpu_time(lambda: mod.gradient_pass(c, st, 50.0, engine.alive, perm, start, jlist,
                                              p, out_c, s_c, scaled), args.repeats)
    t_p2 = cpu_time(lambda: mod.momentum_pass(c, st, engine.alive, engine.x0, engine.y0, perm,
                                              start, jlist, p, scaled, out_c), args.repeats)
    cluster()
    gather()
    rows = ["x", "y", "vx", "vy", "rho", "sxx", "syy", "sxy"]
    diff = {r: float(np.abs(out_c[k] - out_g[k]).max() / np.abs(out_g[k]).max())
            for k, r in enumerate(rows)}
    diff["stress"] = float(np.abs(s_c - s_g).max() / np.abs(s_g).max())

    print(f"# N = {n}, L = {length:g}, h = {h:g}, Verlet radius {h + engine.skin:g}; numba "
          f"{numba.__version__}; CPU time (per core), best of {args.rounds} alternations x 2 "
          f"rounds x {args.repeats} evaluations; a shared machine: ratios are what compares")
    print(f"# per pass: useful visits (ordered pairs < h) {useful}; gather kernel {listed} "
          f"listed; cluster kernel {lanes} lane visits ({LANES} lanes x {jlist.size} listed "
          f"J, {perm.size // LANES} clusters)")
    table = [("kernel", "threads", "ms/eval (CPU)", "useful visits/s/core",
              "masked visits/s/core", "useful share of visits", "speed-up")]
    for threads in (1, 2):
        for name, visits in (("gather (4db0bf1)", listed), (f"cluster ({LANES} lanes)", lanes)):
            t = times[name.split()[0], threads]
            ratio = times["gather", threads] / t
            table.append((name, str(threads), f"{1e3 * t:.2f}", f"{2 * useful / t:.3e}",
                          f"{2 * (visits - useful) / t:.3e}", f"{useful / visits:.2f}",
                          f"{ratio:.2f}x"))
    width = [max(len(r[k]) for r in table) for k in range(len(table[0]))]
    for r in table:
        print("  ".join(v.rjust(w) for v, w in zip(r, width, strict=True)))
    print(f"cluster kernel, 1 thread: pass 1 (L, XSPH, stress, rates) {1e3 * t_p1:.2f} ms = "
          f"{1e9 * t_p1 / lanes:.2f} ns per lane visit; pass 2 (momentum, substrate) "
          f"{1e3 * t_p2:.2f} ms = {1e9 * t_p2 / lanes:.2f} ns per lane visit")
    print("largest |cluster - gather| / max|gather| per rate row: "
          + ", ".join(f"{k} {v:.1e}" for k, v in diff.items()))
    yv = np.ones(1024)
    reps = 20000
    t_fma = cpu_time(lambda: fma_loop(yv, 0.999999, 1e-6, reps), 1)
    peak = 16 * yv.size * reps / t_fma
    av = np.linspace(1.0, 2.0, 1024)
    t_div = cpu_time(lambda: divider_loop(av, yv, reps), 1) / (yv.size * reps)
    cols = [st[X], st[Y], st[VX], st[VY], engine.mass, st[RHO]]
    t_gather = cpu_time(lambda: gather_loop(offsets, index, *cols), args.repeats)
    print(f"roofs: FMA peak {peak / 1e9:.1f} Gflop/s = {1e9 * 2 / peak:.3f} ns per FMA lane; "
          f"one sqrt + one division {1e9 * t_div:.3f} ns per lane; gather roof (6 gathers "
          f"only) {listed / t_gather:.3e} listed visits/s")
    print("vector instructions, cluster kernel:",
          vector_instructions([mod.gradient_pass, mod.momentum_pass]))
    print("vector instructions, gather kernel:",
          vector_instructions([gather_gradient_pass, gather_momentum_pass]))
    if args.write:
        lines = ["| " + " | ".join(table[0]) + " |", "|" + "---|" * len(table[0])]
        lines += ["| " + " | ".join(r) + " |" for r in table[1:]]
        lines.append("")
        lines.append(f"N = {n}, L = {length:g}, h = {h:g}: {useful} useful visits per pass "
                     f"(ordered pairs closer than h); the gather kernel visits {listed} "
                     f"listed pairs, the cluster kernel {lanes} lanes. Cluster kernel on one "
                     f"thread: pass 1 {1e9 * t_p1 / lanes:.2f} ns and pass 2 "
                     f"{1e9 * t_p2 / lanes:.2f} ns per lane visit; roofs of the core: "
                     f"{1e9 * t_div:.3f} ns per lane for one square root and one division, "
                     f"{1e9 * 2 / peak:.3f} ns per FMA lane ({peak / 1e9:.1f} Gflop/s). "
                     f"Written by `benchmarks/drying_roofline.py`.")
        args.write.parent.mkdir(parents=True, exist_ok=True)
        args.write.write_text("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
