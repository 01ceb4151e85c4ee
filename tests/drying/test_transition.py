"""The damage-to-fragmentation analysis (issue 32, item 6) on a synthetic ensemble with a known
critical point: sample s of size L breaks at d_s = d_c + L^(-1/nu) xi_s (xi_s standard normal),
so P_L(d) = Phi((d - d_c) L^(1/nu) / 0.06) crosses at d_c with slope phi(0) L^(1/nu) / 0.06 (the
transition at L = 8 is 0.0075 wide, about two bins: a slope narrower than a bin would be
underestimated); m_max is
L^(-beta/nu) before the break and 0.4 L^(-beta/nu) after it, so its mean at d_c scales as
L^(-beta/nu); the fragments besides the largest have area A = 0.01 L^(gamma/nu), so
m_2 L^2 = A scales as L^(gamma/nu)."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from craquelure.drying import transition as tr
from craquelure.drying.claims import transition_claims
from craquelure.io import write_dataset
from craquelure.scene import load_scene

D_C, ONE_OVER_NU, BETA_OVER_NU, GAMMA_OVER_NU = 0.08, 1.0, 0.125, 1.75


def synthetic(length: float, seed: int, damage: np.ndarray, rng) -> xr.Dataset:
    sc = load_scene("drying/ci", [f"domain.box_length={length}"])
    d_s = D_C + length ** (-ONE_OVER_NU) * 0.06 * rng.standard_normal()
    areas, index = [], []
    for k, d in enumerate(damage):
        m_max = length ** (-BETA_OVER_NU) * (1.0 if d < d_s else 0.4)
        small = 0.01 * length**GAMMA_OVER_NU
        n_small = int((1.0 - m_max) * length**2 * 0.8 / small)
        a = np.r_[m_max * length**2, np.full(n_small, small)]
        areas.append(a)
        index.append(np.full(a.size, k))
    return xr.Dataset(
        {"fragment_area": ("fragment", np.concatenate(areas)),
         "fragment_time_index": ("fragment", np.concatenate(index)),
         "damage": ("time", damage)},
        coords={"time": ("time", np.arange(damage.size, dtype=float))},
        attrs={"box_length": length, "scene": sc.text, "scene_name": sc.name, "seed": seed})


@pytest.fixture(scope="module")
def ensemble():
    rng = np.random.default_rng(5)
    damage = np.linspace(0.0, 0.16, 81)
    return {f"L{length:g}": [synthetic(length, s, damage, rng) for s in range(200)]
            for length in (2.0, 4.0, 8.0)}


def test_recovers_the_critical_point_and_exponents(ensemble):
    ds = tr.transition(ensemble, n_bins=40, n_boot=30)
    a = ds.attrs
    assert a["d_c"] == pytest.approx(D_C, abs=0.004)
    assert a["beta_over_nu"] == pytest.approx(BETA_OVER_NU, abs=0.03)
    assert a["gamma_over_nu"] == pytest.approx(GAMMA_OVER_NU, abs=0.05)
    assert a["one_over_nu"] == pytest.approx(ONE_OVER_NU, abs=0.15)
    lo, hi = a["d_c_ci95"]
    assert lo <= a["d_c"] <= hi
    # the damage phase: m_max stays near L^(-beta/nu) >= 0.5 at low d; fluctuation peaks near d_c
    assert np.all(ds["m_max"].values[:, 0] >= 0.5)
    peak = ds["damage"].values[-1, np.nanargmax(ds["m_max_sigma"].values[-1])]
    assert peak == pytest.approx(D_C, abs=0.01)


def test_rows_say_inconclusive_below_three_sizes(ensemble, tmp_path):
    two = {key: ensemble[key] for key in ("L2", "L4")}
    path = write_dataset(tr.transition(two, n_bins=40, n_boot=20), tmp_path / "transition.nc")
    phases, scaling = transition_claims(path)
    assert phases.verdict == "reproduced"  # cracked and one piece, then fragmented
    assert scaling.verdict == "inconclusive" and "3 box sizes" in scaling.note
    three = write_dataset(tr.transition(ensemble, n_bins=40, n_boot=30),
                          tmp_path / "three" / "transition.nc")
    assert transition_claims(three)[1].verdict in ("reproduced", "partly", "not reproduced")


def test_exponent_row_decides_only_what_its_intervals_can(ensemble, tmp_path):
    """Ising inside an interval narrower than its gap to percolation: reproduced; intervals
    wider than every gap: inconclusive, even when a percolation value falls just outside one
    (the named alternative cannot be told apart); Ising outside: not reproduced."""
    ds = tr.transition(ensemble, n_bins=40, n_boot=20)

    def verdict(intervals, name):
        out = ds.copy()
        out.attrs.update({f"{k}_ci95": np.array(v) for k, v in intervals.items()})
        return transition_claims(write_dataset(out, tmp_path / name / "transition.nc"))[1]

    narrow = {"beta_over_nu": [0.12, 0.13], "gamma_over_nu": [1.7, 1.8], "one_over_nu": [0.9, 1.1]}
    wide = {"beta_over_nu": [0.05, 0.5], "gamma_over_nu": [1.0, 3.0], "one_over_nu": [0.3, 4.0]}
    off = {**narrow, "gamma_over_nu": [2.0, 2.4]}
    assert verdict(narrow, "narrow").verdict == "reproduced"
    wide_row = verdict(wide, "wide")
    assert wide_row.verdict == "inconclusive" and "percolation" in wide_row.note
    # the campaign of 2026-12-03: percolation's beta/nu 0.104 just below a 0.64-wide interval
    edge = {"beta_over_nu": [0.109, 0.748], "gamma_over_nu": [0.855, 3.01],
            "one_over_nu": [0.237, 4.87]}
    assert verdict(edge, "edge").verdict == "inconclusive"
    assert verdict(off, "off").verdict == "not reproduced"


def test_sample_records_of_a_fragment_dataset():
    rng = np.random.default_rng(1)
    ds = synthetic(4.0, 1, np.array([0.0, 0.5]), rng)
    rec = tr.sample_records(ds)
    assert rec["m_max"][0] == pytest.approx(4.0 ** (-BETA_OVER_NU))
    assert rec["m_2"][0] == pytest.approx(0.01 * 4.0**GAMMA_OVER_NU / 16.0)
