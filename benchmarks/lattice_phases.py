"""Where a lattice step's time goes, and how much of it is serial (thread scaling, issue 18).

On a beam block of ``--n`` particles (``craquelure.lattice.bench.block_engine``, ``--effects``):

1. one thread, CPU time per step of the kernel's two parallel phases called chunk by chunk
   (bond chunks: deformations, forces, energies; particle chunks: force sums and the update)
   and of a whole step of ``Engine.run``;
2. two threads, the parallel kernel: CPU time per step of each thread when the kernel is called
   once for ``--steps`` steps (as a run calls it, once per frame interval) and once per step:
   the main thread's excess over the worker is serial work (the step's glue: chunk reductions,
   energy sample; and per call the Python around the kernel), and 1-thread CPU over the busiest
   thread is the speed-up the work allows (Amdahl's bound with the threads' overhead), whatever
   the machine's load. Waiting for a core, or for a sleeping worker to wake, is not CPU time:
   only an idle machine's wall clock shows it (``benchmarks/threads.py``).

    python benchmarks/lattice_phases.py [--n 17600] [--steps 200] [--effects beams]

About 30 s on an idle 2-core machine with the kernels compiled.
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np

from craquelure.lattice.bench import block_engine
from craquelure.threads import set_threads, thread_cpu


def phase_cpu(n: int, effects: tuple[str, ...], steps: int) -> dict[str, float]:
    """CPU seconds per step of the bond phase, the particle phase and a whole step (1 thread)."""
    set_threads(1)
    probe = block_engine(n, effects)  # its state is stepped phase by phase, then discarded
    probe.run(2)
    k, s = probe.kernel, probe.system
    bpart = np.zeros((k.NCHUNK, k.N_BPART))
    ppart = np.zeros((k.NCHUNK, k.N_PPART))

    def bonds():
        for c in range(k.NCHUNK):
            k._bond_chunk(probe.cb[c], probe.cb[c + 1], probe.crange[0, c], probe.crange[1, c],
                          probe.q, probe.qm, s.bi, s.bj, probe.bref, probe.bk, s.state,
                          s.unbreakable, probe.bprev, probe.bforce, probe.benergy, probe.bratio,
                          probe.tbreak, probe.p, probe.seed, probe.step, probe.time,
                          probe.fn[c], bpart[c])

    def particles():
        for c in range(k.NCHUNK):
            k._particle_chunk(probe.cn[c], probe.cn[c + 1], probe.qm, probe.q, probe.qref,
                              probe.qbuild, s.mass, s.inertia, s.diameter, s.fix, s.drive,
                              s.load, probe.fn, probe.crange, probe.fc, probe.p, probe.time,
                              ppart[c])

    out = {}
    for name, phase in (("bond phase", bonds), ("particle phase", particles)):
        phase()
        c0 = time.process_time()
        for _ in range(steps):
            phase()
        out[name] = (time.process_time() - c0) / steps
    engine = block_engine(n, effects)
    engine.run(2)
    c0 = time.process_time()
    engine.run(steps)
    out["whole step"] = (time.process_time() - c0) / steps
    return out


def thread_split(n: int, effects: tuple[str, ...], steps: int, per_call: int) -> list[float]:
    """CPU seconds per step of each busy thread (largest first), 2 threads, parallel kernel,
    ``per_call`` steps per kernel call."""
    set_threads(2)
    engine = block_engine(n, effects, parallel=True)
    engine.run(2)
    s0 = thread_cpu()
    for _ in range(steps // per_call):
        engine.run(per_call)
    s1 = thread_cpu()
    used = sorted(((s1[t] - s0.get(t, 0)) * 1e-9 / steps for t in s1), reverse=True)
    return [u for u in used if u > 0.01 * used[0]]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=17600)
    parser.add_argument("--steps", type=int, default=200)
    parser.add_argument("--effects", nargs="+", default=["beams"])
    args = parser.parse_args()
    effects = tuple(args.effects)
    phases = phase_cpu(args.n, effects, args.steps)
    whole = phases["whole step"]
    probe = block_engine(args.n, effects)
    print(f"# {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}; {probe.system.n} particles, "
          f"{probe.system.bi.size} bonds, effects {'+'.join(effects)}; load average "
          f"{os.getloadavg()[0]:.1f}; CPU time per step")
    print("1 thread:")
    both = phases["bond phase"] + phases["particle phase"]
    for name in ("bond phase", "particle phase"):
        print(f"  {name:<15} {phases[name] * 1e3:8.3f} ms  ({phases[name] / both:6.1%} of the two)")
    print(f"  {'whole step':<15} {whole * 1e3:8.3f} ms  (the phases called one by one from "
          f"Python cost {both * 1e3:.3f} ms: dispatch and cache effects; the serial glue of a "
          f"step is the 2-thread main - worker below)")
    print("2 threads, parallel kernel:")
    for per_call, label in ((args.steps, f"{args.steps} steps per call (as a run)"),
                            (1, "1 step per call")):
        used = thread_split(args.n, effects, args.steps, per_call)
        serial = used[0] - (used[1] if len(used) > 1 else 0.0)
        print(f"  {label:<28} threads {', '.join(f'{u * 1e3:.3f}' for u in used)} ms; "
              f"serial (main - worker) {serial * 1e3:.3f} ms; CPU bound {whole / used[0]:.2f}x; "
              f"both threads {sum(used) / whole:.2f}x the 1-thread CPU")


if __name__ == "__main__":
    main()
