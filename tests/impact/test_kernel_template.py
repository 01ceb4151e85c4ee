"""The impact kernels: no subnormal stalls. The kernels flush accelerations, stresses and pair
powers below ``Settings.flush_below`` (1e-100 SI) where they are produced, and the results do
not change."""

import dataclasses

import numpy as np
import pytest

from craquelure.impact import analysis, api
from craquelure.impact.api import initial_state, settings
from craquelure.impact.engine import Engine
from craquelure.impact.initial_state import build_specimen
from craquelure.scene import load_scene
from tests.impact.runs import simulate

# -- subnormals ----------------------------------------------------------------------------
# No subnormal stalls: the impact kernels flush accelerations, stresses and pair powers below
# ``Settings.flush_below`` (1e-100 SI) where they are produced, and the results do not change.
TINY = np.finfo(float).tiny


def subnormals(eng: Engine) -> int:
    st = eng.state
    arrays = (st.vx, st.vy, st.sig, st.nom, st.eint, st.eel, eng.ax, eng.ay, eng.pav, eng.pas)
    return sum(int(np.sum((a != 0) & (np.abs(a) < TINY))) for a in arrays)


def column_engine(flush: float) -> Engine:
    """A 4 x 300-cell column on the base: the precursor ahead of the compression wave crosses
    ~100 neighbour shells and goes subnormal after about 180 steps."""
    scene = load_scene("impact/ci", ["particles.shape=rectangle", "particles.diameter_cells=4",
                                     "particles.height_cells=300"])
    sp = build_specimen(scene, 0)
    return Engine(dataclasses.replace(settings(scene), flush_below=flush),
                  initial_state(scene, sp))


def test_flushing_removes_the_subnormals_and_changes_nothing_else():
    plain, flushed = column_engine(0.0), column_engine(1e-100)
    seen = 0
    for _ in range(240):
        plain.step()
        flushed.step()
        seen = max(seen, subnormals(plain))
        assert subnormals(flushed) == 0
    assert seen > 50  # the case does make subnormals without the flush
    for key, value in plain.energies().items():
        assert flushed.energies()[key] == pytest.approx(value, rel=1e-12, abs=1e-12), key
    for name in ("x", "y", "vx", "vy", "rho", "sig"):
        np.testing.assert_allclose(getattr(flushed.state, name), getattr(plain.state, name),
                                   rtol=1e-12, atol=1e-12 * np.abs(getattr(plain.state, name))
                                   .max())


def test_default_run_summary_equal_with_and_without_the_flush(monkeypatch):
    """The CI scene run end to end (its series and every run metric) with the default flush and
    with none: equal to round-off."""
    scene = load_scene("impact/ci")
    runs = {}
    for flush in (1e-100, 0.0):
        def patched(sc, flush=flush):
            return dataclasses.replace(settings(sc), flush_below=flush)

        monkeypatch.setattr(api, "settings", patched)
        sp, eng, series, snaps = simulate(scene, 0, progress=False)
        runs[flush] = api.run_dataset(scene, 0, sp, eng, series, snaps)
        # what write_run adds: the stored scene and the runner's step count
        runs[flush].attrs.update(scene=scene.text, run_steps=eng.step_count)
    a, b = runs[1e-100], runs[0.0]
    ma, mb = analysis.run_metrics(a), analysis.run_metrics(b)
    assert ma["steps"] == mb["steps"]
    assert a.attrs["run_dt_min"] == pytest.approx(b.attrs["run_dt_min"], rel=1e-10)
    for key, value in mb.items():
        if isinstance(value, float):
            assert ma[key] == pytest.approx(value, rel=1e-10, abs=1e-12), key
        else:
            assert ma[key] == value, key
    for name in b.data_vars:
        if name.startswith("series_"):
            np.testing.assert_allclose(a[name].values, b[name].values, rtol=1e-10,
                                       atol=1e-12 * float(np.abs(b[name].values).max() or 1))
