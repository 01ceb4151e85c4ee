"""Thickness sweep (issue part 6): the exponent of <S> against H is recovered from synthetic
fragment datasets whose law is known, and box-limited snapshots are excluded."""

import numpy as np
import pytest

from craquelure.drying.thickness import thickness_sweep
from craquelure.errors import CraquelureError

from .synthetic_run import fragment_dataset

TIMES = np.arange(10.0, 41.0, 2.0)
THICKNESSES = (0.2, 0.25, 0.316)


def sweep_of(exponent, n_seeds=8, unbroken_until=14.0):
    sets = {}
    for h in THICKNESSES:
        mean = 2.0 * (h / 0.316) ** exponent * 30.0 / TIMES
        frags = []
        for s in range(n_seeds):
            n = np.maximum(2, np.round(16.0 / mean)).astype(int)
            n[TIMES < unbroken_until] = 1
            frags.append(fragment_dataset(100 * s + 1, TIMES, mean, n))
        sets[h] = frags
    return thickness_sweep(sets)


def test_recovers_h_squared():
    # ~10-40 fragments per sample x 8 seeds of gamma(2) sizes: <S> to ~3-5 %, so over a
    # log-H span of 0.46 the slope is good to ~0.2.
    sweep = sweep_of(2.0)
    assert sweep.attrs["exponent_late_mean"] == pytest.approx(2.0, abs=0.2)
    assert sweep.attrs["n_late_times"] >= 4
    # Snapshots where the samples are still one fragment (area = box) are not used.
    assert not sweep["usable"].values[TIMES < 14.0].any()
    assert np.isnan(sweep["exponent"].values[TIMES < 14.0]).all()


def test_thickness_independent_sizes_give_zero_exponent():
    sweep = sweep_of(0.0)
    assert sweep.attrs["exponent_late_mean"] == pytest.approx(0.0, abs=0.2)


def test_needs_two_thicknesses():
    with pytest.raises(CraquelureError, match="at least two thicknesses"):
        thickness_sweep({0.3: [fragment_dataset(1, TIMES, np.ones(TIMES.size),
                                                np.full(TIMES.size, 4))]})
