"""The cost of every built-in scene, as `craquelure check` predicts it, one Markdown table per
model (``benchmarks/tables/cost_<model>.md``, included by the model pages).

Columns: particles, the work the throughput model counts (drying: rate evaluations; impact,
lattice: steps; softdyn: weighted integrations) and the predicted wall time on 1 and 2 threads
from the calibrated model (``src/craquelure/throughput.yaml``, written by
``benchmarks/predictions.py --calibrate``, which also measures how well the predictions hold).
Run after a calibration or a scene change:

    python benchmarks/cost_table.py
"""

from __future__ import annotations

from pathlib import Path

from craquelure import api
from craquelure.models import MODELS, model_api
from craquelure.throughput import cost_model, predicted_wall_time, table

OUT = Path(__file__).resolve().parent / "tables"


def duration(seconds: float) -> str:
    for unit, size in (("h", 3600.0), ("min", 60.0)):
        if seconds >= size:
            return f"{seconds / size:.3g} {unit}"
    return f"{seconds:.2g} s"


def cost_table(model: str) -> str:
    meta = table()
    rows = [f"| scene | particles | {cost_model(model).unit} | predicted wall time, "
            "1 / 2 threads |", "|---|---|---|---|"]
    for name in (n for n in api.scenes() if n.startswith(f"{model}/")):
        work = model_api(model).workload(api.load_scene(name))
        times = [duration(predicted_wall_time(model, work, t)) for t in (1, 2)]
        rows.append(f"| `{name}` | {work['particles']:.0f} | {work['units']:.3g} | "
                    f"{times[0]} / {times[1]} |")
    rows.append("")
    rows.append(f"Predicted by `craquelure check` from `src/craquelure/throughput.yaml` "
                f"(calibrated {meta['measured']}, {meta['machine']}); written by "
                "`benchmarks/cost_table.py`.")
    return "\n".join(rows) + "\n"


def main() -> None:
    OUT.mkdir(exist_ok=True)
    for model in MODELS:
        path = OUT / f"cost_{model}.md"
        path.write_text(cost_table(model))
        print(f"wrote {path}")


if __name__ == "__main__":
    main()
