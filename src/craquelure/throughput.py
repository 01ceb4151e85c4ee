"""Measured throughput model of each engine: the wall time `craquelure check` predicts
(docs/performance.md, "What a run will cost").

A run is ``units`` repetitions of the engine's unit of work over ``particles`` particles with
``neighbours`` neighbours (or bonds, or pairs) each:

    T(threads) = T_0 + units (c_unit + particles (c_particle + sum_e c_e + neighbours c_pair))
                 / S(threads)

c_e is the extra per-particle cost of effect e where the calibration probe lacks it, S(2) is
measured and Amdahl's law gives S beyond. The numbers are in ``throughput.yaml`` beside this
file, written by ``benchmarks/predictions.py --calibrate``.
"""

from dataclasses import dataclass, field
from functools import cache
from pathlib import Path

import yaml

TABLE = Path(__file__).with_name("throughput.yaml")


@dataclass(frozen=True)
class CostModel:
    unit: str
    overhead_s: float
    per_unit_s: float
    per_particle_s: float
    per_pair_s: float
    speedup_2: float
    per_particle_effect_s: dict = field(default_factory=dict)

    def speedup(self, threads: int) -> float:
        """Measured S(2); Amdahl's law with the same parallel fraction for other counts."""
        threads = max(1, int(threads))
        if threads == 1:
            return 1.0
        fraction = min(1.0, max(0.0, 2.0 * (1.0 - 1.0 / self.speedup_2)))
        return 1.0 / ((1.0 - fraction) + fraction / threads)

    def compute_seconds(self, units: float, particles: float, neighbours: float,
                        threads: int = 1, effects: tuple[str, ...] = ()) -> float:
        extra = sum(self.per_particle_effect_s.get(name, 0.0) for name in effects)
        per_unit = (self.per_unit_s
                    + particles * (self.per_particle_s + extra + neighbours * self.per_pair_s))
        return units * per_unit / self.speedup(threads)

    def seconds(self, units: float, particles: float, neighbours: float,
                threads: int = 1, effects: tuple[str, ...] = ()) -> float:
        return self.overhead_s + self.compute_seconds(units, particles, neighbours, threads,
                                                      effects)


@cache
def table() -> dict:
    return yaml.safe_load(TABLE.read_text())


def cost_model(engine: str) -> CostModel:
    entry = table()["engines"][engine]
    return CostModel(**{k: entry[k] for k in CostModel.__dataclass_fields__ if k in entry})


def predicted_parts(engine: str, workload: dict, threads: int = 1) -> tuple[float, float]:
    """(fixed cost T_0, compute part) in seconds of ``craquelure run`` for a workload dict
    (units, particles, neighbours; optional: ``effects``, the scene's effects, and ``serial:
    True`` when the engine runs its serial kernels whatever the thread count)."""
    if workload.get("serial"):
        threads = 1
    model = cost_model(engine)
    return model.overhead_s, model.compute_seconds(workload["units"], workload["particles"],
                                                   workload["neighbours"], threads,
                                                   tuple(workload.get("effects", ())))


def predicted_wall_time(engine: str, workload: dict, threads: int = 1) -> float:
    """Seconds of ``craquelure run`` for a workload dict (see :func:`predicted_parts`)."""
    return sum(predicted_parts(engine, workload, threads))


def prediction_lines(engine: str, workload: dict) -> dict[str, object]:
    """Entries for `craquelure check`'s derived numbers."""
    meta = table()
    model = cost_model(engine)
    return {
        f"work: {model.unit}, particles, neighbours": (
            round(workload["units"], 1), workload["particles"],
            round(float(workload["neighbours"]), 2)),
        "predicted wall time [s], 1 / 2 threads": (
            round(predicted_wall_time(engine, workload, 1), 1),
            round(predicted_wall_time(engine, workload, 2), 1)),
        "throughput model": f"{TABLE.name}, measured {meta['measured']} ({meta['machine']})",
    }


# `craquelure check` and `craquelure run` warn above this predicted wall time (s)
LONG_RUN_S = 3600.0


def long_run_warning(engine: str, workload: dict, threads: int = 1) -> str | None:
    """A one-line warning when the predicted wall time of a run exceeds :data:`LONG_RUN_S`:
    the figure, the workload it was predicted from and the throughput model; else None."""
    seconds = predicted_wall_time(engine, workload, threads)
    if not seconds > LONG_RUN_S:
        return None
    model, meta = cost_model(engine), table()
    threads = 1 if workload.get("serial") else max(1, int(threads))
    return (f"warning: predicted wall time {seconds / 3600:.3g} h ({seconds:.3g} s) with "
            f"{threads} thread(s) exceeds an hour; predicted from {workload['units']:.4g} "
            f"{model.unit} x {workload['particles']:.4g} particles x "
            f"{float(workload['neighbours']):.3g} neighbours by the throughput model "
            f"T = T_0 + units (c_unit + particles (c_particle + neighbours c_pair)) / S(threads) "
            f"of {TABLE.name} (measured {meta['measured']}, {meta['machine']})")
