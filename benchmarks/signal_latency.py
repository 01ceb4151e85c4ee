"""How soon a run shows progress and how soon it stops at SIGTERM, per model.

For one scene of each model (a lattice run whose one frame lasts seconds, so the signal lands
inside a frame), ``craquelure run`` is started on one thread; the script prints

- the time from the process start to its first progress line (imports and kernel loading
  included: what a user waits for before the first line),
- the time from SIGTERM (sent as soon as that line is out) to the process's exit, in wall time
  and in CPU time of the process (checkpoint and interpreter exit included; the CPU time does
  not grow with the machine's load), the exit status (3) and the size of the checkpoint.

Wall times on whatever load the machine has (the figures say so with the load average). Not
a test: ``python benchmarks/signal_latency.py``.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

LATTICE = ["domain.nx=48", "domain.ny=12", "domain.water_level=7.0", "material.g=0.02",
           "fracture.start_time=30.0", "numerics.mass_damping_until=30.0",
           "outputs.t_end=2000.0", "outputs.frames=1"]
SCENES = {
    "drying": ["drying/ci", "--seed", "1"],
    "impact": ["impact/ci", "--seed", "1", "--set", "outputs.t_end=1.0e-3"],
    "lattice": ["lattice/calving", "--seed", "4", *[a for s in LATTICE for a in ("--set", s)]],
    "softdyn": ["softdyn/t1_sweep"],
}


def cpu_seconds(pid: int) -> float:
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def measure(args: list[str], folder: Path) -> tuple[float, float, float, int, int]:
    out, err = folder / "run.nc", folder / "run.err"
    env = {**os.environ, "NUMBA_NUM_THREADS": "1"}
    with open(err, "w") as fh:
        start = time.perf_counter()
        proc = subprocess.Popen([sys.executable, "-m", "craquelure", "run", *args, "--out",
                                 str(out), "--checkpoint-minutes", "0"], env=env,
                                stdout=subprocess.DEVNULL, stderr=fh)
        while "elapsed" not in err.read_text() and proc.poll() is None:
            time.sleep(0.01)
        first = time.perf_counter() - start
        cpu_before = cpu_seconds(proc.pid)
        sent = time.perf_counter()
        proc.send_signal(signal.SIGTERM)
        _, status, usage = os.wait4(proc.pid, 0)
        stop = time.perf_counter() - sent
        cpu = usage.ru_utime + usage.ru_stime - cpu_before
        proc.returncode = os.waitstatus_to_exitcode(status)
    ck = out.with_name(out.name + ".checkpoint.npz")
    return first, stop, cpu, proc.returncode, ck.stat().st_size if ck.exists() else 0


def main() -> None:
    print(f"load average {os.getloadavg()[0]:.1f}, {os.cpu_count()} cores")
    print(f"{'model':<8} {'first line [s]':>15} {'SIGTERM->exit [s]':>18} {'[CPU s]':>8} "
          f"{'exit':>5} {'checkpoint [kB]':>16}")
    for model, args in SCENES.items():
        with tempfile.TemporaryDirectory() as tmp:
            first, stop, cpu, code, size = measure(args, Path(tmp))
        print(f"{model:<8} {first:15.1f} {stop:18.2f} {cpu:8.2f} {code:5d} {size / 1e3:16.0f}")


if __name__ == "__main__":
    main()
