"""Cost of the Soft Dynamics model: right-hand side and velocity solve versus N, one T1 per
integrator, and the integrators' error versus wall time on the T1 duration.

Prints

- per right-hand side (pair terms + velocity solve + rates) and per linear solve alone, for N
  spheres on a triangular patch (6 neighbours inside, every pair at gap h0 = 1e-2 R, zero-sum
  loads), dense LU (N d <= 512) and sparse SuperLU; time per pair per RHS (O(N) scaling of the
  pair terms; the sparse solve of a 2D patch grows like N^1.5 at worst);
- wall time, steps and right-hand sides of one T1 per integrator: the Poiseuille-side T1 of the
  accuracy scene (h0 = 0.1 R, F~ = 1e-2; LSODA/BDF/Radau at rtol 1e-8 and heun at dt 5e-3 tau)
  and the Fig. 4 Hertz T1 (h0 = 1e-3 R, F~ = 1e-3; adaptive integrators at rtol 1e-8);
- the error-versus-wall-time table of ``config/scenes/softdyn/t1_accuracy.yaml`` (the same study
  as the workflow rule ``softdyn_accuracy``; reference LSODA at rtol 1e-11).

Each timing is the best of several repetitions after a warm-up (compilation excluded). One
thread (the model is serial; run it with NUMBA_NUM_THREADS=1). Not a test:
``python benchmarks/softdyn_cost.py [--sizes 4 16 64 256 1024] [--no-accuracy]``.
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np

from craquelure.scene import load_scene
from craquelure.softdyn.accuracy import run_accuracy
from craquelure.softdyn.engine import Engine, Flags, run
from craquelure.softdyn.initial_state import build

H0 = 1e-2


def patch(n: int) -> tuple[np.ndarray, np.ndarray]:
    """About n centres on a triangular lattice (spacing 2R + h0) and their contact pairs."""
    side = max(2, int(round(math.sqrt(n))))
    d = 2.0 + H0
    pts = [((i + 0.5 * (j % 2)) * d, j * d * math.sqrt(3) / 2)
           for j in range(side) for i in range(side)][:n]
    x = np.array(pts)
    diff = x[:, None, :] - x[None, :, :]
    dist = np.sqrt((diff**2).sum(-1))
    i, j = np.nonzero(np.triu(dist < d * 1.001, 1))
    return x, np.stack([i, j], axis=1)


def system(n: int, solver: str) -> Engine:
    x, pairs = patch(n)
    rng = np.random.default_rng(1)
    F = rng.normal(size=x.shape) * 1e-3
    F -= F.mean(axis=0)
    return Engine(x0=x, pairs=pairs, F0=F, radius=1.0, viscosity=1.0, young=1.0, k_n=1.0,
                  k_t=1.0, c_n=1.5 * math.pi, c_t=math.pi, tau_baumgarte=1e-2,
                  ramp_time=0.0, linear_solver=solver,
                  flags=Flags(("lubrication_normal", "lubrication_tangential", "hertz")))


def best(fn, repeat: int, number: int) -> float:
    fn()
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        for _ in range(number):
            fn()
        times.append((time.perf_counter() - t0) / number)
    return min(times)


def bench_sizes(sizes) -> None:
    print("per right-hand side and per velocity solve (best of 5, one thread)")
    print(f"{'N':>6} {'pairs':>6} {'solver':>7} {'RHS [us]':>10} {'solve [us]':>11} "
          f"{'RHS/pair [us]':>14}")
    for n in sizes:
        for solver in ("dense", "sparse"):
            if solver == "dense" and 2 * n > 512:
                continue
            sysm = system(n, solver)
            rng = np.random.default_rng(2)
            y = sysm.initial_state()
            y[sysm.n * sysm.d: sysm.n * sysm.d + sysm.n_pairs] = rng.uniform(1e-4, 1e-3,
                                                                              sysm.n_pairs)
            x, s, q = sysm.unpack(y)
            terms = sysm.k.pair_terms(x, s, q, sysm.pi, sysm.pj, sysm.p)
            c, _ = sysm.k.particle_terms(1.0, sysm.pi, sysm.pj, sysm.F0, sysm.p, terms[6],
                                         terms[8])
            number = max(1, int(2000 / max(n, 1)))
            t_rhs = best(lambda sysm=sysm, y=y: sysm.rhs(1.0, y), 5, number)
            t_solve = best(lambda sysm=sysm, A=terms[7], c=c: sysm._solve(A, c), 5, number)
            print(f"{n:>6} {sysm.n_pairs:>6} {solver:>7} {t_rhs * 1e6:>10.1f} "
                  f"{t_solve * 1e6:>11.1f} {t_rhs * 1e6 / sysm.n_pairs:>14.3f}")


def bench_t1() -> None:
    print("\none T1 per integrator (wall time of the integration, kernels compiled)")
    print(f"{'case':>28} {'integrator':>10} {'T/tau':>10} {'wall [s]':>9} {'steps':>7} "
          f"{'RHS':>7} {'us/RHS':>7}")
    cases = (("h0=0.1 F~=1e-2 (Poiseuille)", "softdyn/t1_accuracy",
              ["LSODA", "BDF", "Radau", "heun"]),
             ("h0=1e-3 F~=1e-3 (Fig. 4)", "softdyn/t1_single", ["LSODA", "BDF", "Radau"]))
    for label, ref, methods in cases:
        for method in methods:
            extra = ["numerics.dt=0.005"] if method == "heun" else []
            sc = load_scene(ref, [f"numerics.integrator={method}", "numerics.rtol=1.0e-8",
                                  "outputs.run_past_stop=false", *extra])
            setup = build(sc)
            res = run(setup, sample_times_tau=np.array([]), desc=f"{method}")
            print(f"{label:>28} {method:>10} {res.t_stop / setup.tau:>10.4f} "
                  f"{res.wall_time_s:>9.3f} {res.n_steps:>7} {res.n_rhs:>7} "
                  f"{1e6 * res.wall_time_s / max(res.n_rhs, 1):>7.1f}")


def bench_accuracy() -> None:
    ds = run_accuracy(load_scene("softdyn/t1_accuracy"))
    print(f"\nerror versus wall time, T1 at h0 = {ds.attrs['h0']:g} R, F~ = "
          f"{ds.attrs['reduced_force']:g}; reference {ds.attrs['reference']}: T_ref = "
          f"{ds.attrs['reference_duration']:.8f} tau")
    print(f"{'integrator':>10} {'rtol/dt':>9} {'|T-T_ref|/tau':>14} {'state err/R':>12} "
          f"{'wall [s]':>9} {'RHS':>7}")
    for m, method in enumerate(ds.integrator.values):
        for k, rtol in enumerate(ds.rtol.values):
            print(f"{method:>10} {rtol:>9.0e} {ds.adaptive_error.values[m, k]:>14.3e} "
                  f"{ds.adaptive_state_error.values[m, k]:>12.3e} "
                  f"{ds.adaptive_wall_time_s.values[m, k]:>9.3f} "
                  f"{int(ds.adaptive_n_rhs.values[m, k]):>7}")
    for k, dt in enumerate(ds.dt.values):
        print(f"{'heun':>10} {dt:>9.4g} {ds.heun_error.values[k]:>14.3e} "
              f"{ds.heun_state_error.values[k]:>12.3e} {ds.heun_wall_time_s.values[k]:>9.3f} "
              f"{ds.heun_n_rhs.values[k]:>7.0f}")
    print(f"heun order (3 finest dt): duration {ds.attrs['heun_duration_order']:.2f}, "
          f"state {ds.attrs['heun_state_order']:.2f}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[4, 16, 64, 256, 1024])
    parser.add_argument("--no-accuracy", action="store_true")
    args = parser.parse_args()
    bench_sizes(args.sizes)
    bench_t1()
    if not args.no_accuracy:
        bench_accuracy()


if __name__ == "__main__":
    main()
