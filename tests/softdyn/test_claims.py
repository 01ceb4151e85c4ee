"""Soft Dynamics claims for the validation report, on synthetic datasets with known answers."""

from __future__ import annotations

import math

import numpy as np
import xarray as xr

from craquelure.softdyn import analysis, claims


def sweep(exponent):
    """T = 10 (h0/h*)^exponent on a log grid of h0/h* from 0.02 to 30, one force."""
    ratio = np.geomspace(0.02, 30.0, 13)
    duration = 10.0 * ratio**exponent
    return xr.Dataset(
        {"duration": (("h0", "force"), duration[:, None]),
         "computed": (("h0", "force"), np.ones((13, 1))),
         "finished": (("h0", "force"), np.ones((13, 1))),
         "h0_over_h_star": (("h0", "force"), ratio[:, None])},
        coords={"h0": ratio * 1e-2, "force": [1e-3]})


def test_hertz_slope_and_trend():
    trend, hertz = claims.sweep_claims(analysis.sweep_numbers(sweep(-2.0)))
    # log10(30 / 0.02) = 3.18 decades of h0/h*, so 6.35 decades of T
    assert trend.verdict == "reproduced" and "span 6.35 decades" in trend.measured
    assert hertz.verdict == "reproduced" and "-2.00" in hertz.measured
    # 1.59 decades, too shallow
    trend, hertz = claims.sweep_claims(analysis.sweep_numbers(sweep(-0.5)))
    assert hertz.verdict == "not reproduced"
    assert trend.verdict == "partly" and trend.note == "fails: span >= 2 decades"


def phase(flip):
    fh = np.array([0.2, 0.5, 0.6, 0.8])
    predicted = (fh < 1 / math.sqrt(3)).astype(float)[:, None].repeat(2, axis=1)
    occurred = predicted.copy()
    occurred[flip] = 1 - occurred[flip]
    return xr.Dataset({"occurred": (("fh_over_fv", "force"), occurred),
                       "predicted": (("fh_over_fv", "force"), predicted)},
                      coords={"fh_over_fv": fh, "force": [1e-4, 1e-3]})


def test_phase_near_the_line_is_partly_far_from_it_not():
    # F_h/F_v = 0.6, within 0.05 of 1/sqrt3
    near = claims.phase_claim(analysis.phase_numbers(phase((2, 1))))
    assert near.verdict == "partly" and "F_h/F_v = 0.6 at F~ = 0.001" in near.measured
    far = claims.phase_claim(analysis.phase_numbers(phase((0, 0))))
    assert far.verdict == "not reproduced"
    n = analysis.phase_numbers(phase((slice(0, 0), 0)))
    assert claims.phase_claim(n).verdict == "reproduced"


def test_claims_read_only_the_summary(tmp_path):
    """The claims judge the numbers of summary.json; a dataset is not a source."""
    import json

    path = tmp_path / "summary.json"
    path.write_text(json.dumps({"sources": [
        {"source": "sweep.nc", **analysis.sweep_numbers(sweep(-2.0))},
        {"source": "phase.nc", **analysis.phase_numbers(phase((0, 0)))}]}))
    verdicts = [c.verdict for c in claims.claims([path])]
    assert verdicts == ["reproduced", "reproduced", "not reproduced"]
