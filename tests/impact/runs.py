"""Impact runs for tests, through the runner without output files."""

from craquelure import runner
from craquelure.impact.api import ImpactRun


def simulate(scene, seed: int, progress: bool = True):
    """Run a scene; returns (specimen, engine, series dict, snapshots: lists of the times and
    of each field by name)."""
    model = ImpactRun(scene, seed)
    runner.run(model, scene, seed, progress=progress, **model.options())
    model.finish()
    return model.result()
