"""Concrete-impact scene rules a schema cannot state (each refusal names the key and the allowed
values) and the memory estimate, whose particle count is the specimen's."""

import re

import numpy as np
import pytest

from craquelure import cli
from craquelure.errors import SceneError
from craquelure.impact import rules
from craquelure.impact.initial_state import build_specimen
from craquelure.scene import list_scenes, load_scene


@pytest.mark.parametrize("scene, overrides, message", [
    ("impact/default", ["numerics.h_min=2.0", "numerics.h_max=1.5"],
     r"numerics\.h_min: 2\.0 must be below numerics\.h_max = 1\.5"),
    ("impact/disc3d", ["domain.plane=stress"],
     r"domain\.plane: 'stress' is not allowed with domain\.dim = 3; allowed values: strain"),
    ("impact/disc3d", ["particles.shape=rings"],
     r"particles\.shape: 'rings' is not allowed with domain\.dim = 3; allowed values: disc"),
    ("impact/default", ["particles.precrack=pf9"],
     r"particles\.precrack: 'pf9' is not allowed; allowed values: none, pf1"),
    ("impact/default", ["outputs.series_dt=1e-30"], r"outputs\.series_dt: 1e-30 gives"),
])
def test_cross_field_problems_name_the_key(scene, overrides, message):
    with pytest.raises(SceneError, match=message):
        load_scene(scene, overrides)


def test_the_rules_accept_the_built_in_scenes():
    for name in ("default", "ci", "ci3d", "cscm", "disc3d", "plane_stress", "rings"):
        assert rules.scene_problems(load_scene(f"impact/{name}").data) == []


@pytest.mark.parametrize("scene, overrides", [
    ("impact/default", []),
    ("impact/default", ["particles.diameter_cells=30"]),
    ("impact/default", ["particles.shape=rectangle", "particles.diameter_cells=12",
                        "particles.height_cells=40"]),
    ("impact/disc3d", ["particles.diameter_cells=16", "particles.thickness_cells=3"]),
])
def test_memory_estimate_counts_the_specimens_particles(scene, overrides):
    """The estimate's particle count (pi/4 d^2 for a disc, d x height for a rectangle, times
    the layers in 3D) is the built specimen's to within the boundary cells, 2/d (the cells the
    perimeter pi d cuts, half of them inside, over the area pi d^2/4: 1264 against 1257 at
    d = 40); each particle added costs at least its 80 state doubles."""
    sc = load_scene(scene, overrides)
    d = sc.get("particles.diameter_cells")
    need, what = rules.memory_estimate(sc.data)
    counted = float(re.match(r"([\d.e+]+) particles", what).group(1))
    built = build_specimen(sc, 0).x.size
    assert counted == pytest.approx(built, rel=2 / d)
    bigger = load_scene(scene, [*overrides, f"particles.diameter_cells={2 * d}"])
    more = build_specimen(bigger, 0).x.size
    assert rules.memory_estimate(bigger.data)[0] - need >= (more - built) * 8 * 80


@pytest.mark.parametrize("case", range(4))
def test_fuzzed_scene_with_a_snapshot_after_the_end_is_refused(case, capsys):
    """Four fuzzed impact scenes (scene, end time, snapshot times drawn from seed 39 + case),
    one snapshot time after outputs.t_end: `craquelure check` refuses each with one line
    naming outputs.snapshot_times and the allowed range [0, t_end]; the same scene with that
    time moved to t_end passes."""
    rng = np.random.default_rng(39 + case)
    names = sorted(n for n, _ in list_scenes() if n.startswith("impact/"))
    name = names[rng.integers(len(names))]
    t_end = float(rng.uniform(5e-5, 1e-3))
    late = t_end * float(rng.uniform(1.01, 3.0))
    early = sorted(float(v) for v in rng.uniform(0.0, t_end, size=rng.integers(0, 3)))
    times = [*early, late]
    sets = ["--set", f"outputs.t_end={t_end!r}"]
    assert cli.main(["check", name, *sets, "--set",
                     f"outputs.snapshot_times=[{', '.join(map(repr, times))}]"]) != 0
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    assert f"outputs.snapshot_times: {late!r} is after outputs.t_end = {t_end!r}" in err[0]
    assert "[0, t_end]" in err[0]
    ok = [*early, t_end]
    assert cli.main(["check", name, *sets, "--set",
                     f"outputs.snapshot_times=[{', '.join(map(repr, ok))}]"]) == 0
