"""The campaign aggregate over seeds (craquelure.drying.campaign; drying spec section 10) and
`craquelure campaign`, on synthetic fragment datasets."""

import numpy as np
import pytest

from craquelure.cli import main as cli_main
from craquelure.drying.campaign import build_campaign, pooled_mean
from craquelure.errors import CraquelureError
from craquelure.io import open_dataset, write_dataset

from .synthetic_run import TIMES, fragment_dataset


def law(t, b=0.05, t0=9.0):
    return 1.0 / (b * (t - t0 + 1.0))


def make(n_seeds=6, shape=2.0):
    mean = law(TIMES)
    frags = []
    for s in range(n_seeds):
        n = np.maximum(1, np.round(16.0 / mean)).astype(int)
        frags.append(fragment_dataset(100 + s, TIMES, mean, n, shape=shape,
                                      first_removal=8.0 + s))
    return frags


@pytest.fixture(scope="module")
def campaign():
    return build_campaign(make(), n_bins=20)


def test_dims_and_pooled_mean(campaign):
    frags = make()
    assert dict(campaign.sizes) == {"seed": 6, "time": TIMES.size, "bin": 20,
                                    "fragment": sum(f.sizes["fragment"] for f in frags)}
    total = sum(np.bincount(f["fragment_time_index"].values, f["fragment_area"].values,
                            minlength=TIMES.size) for f in frags)
    count = sum(f["n_fragments"].values for f in frags)
    np.testing.assert_allclose(campaign["mean_area"].values, total / count, rtol=1e-12)
    np.testing.assert_allclose(campaign["inverse_mean_area"].values, count / total, rtol=1e-12)
    assert campaign["n_fragments"].sel(seed=102).values.tolist() == \
        frags[2]["n_fragments"].values.tolist()
    assert campaign.attrs["t_star"] == pytest.approx(5e-3 / 2.2e-4)
    assert campaign["first_removal_time"].values.tolist() == [8, 9, 10, 11, 12, 13]


def test_scaled_sizes_have_unit_mean_and_densities_integrate(campaign):
    x = campaign["fragment_scaled_area"].values
    k = campaign["fragment_time_index"].values
    # Pooled <S>_t makes the pooled mean of X exactly 1 at every time.
    np.testing.assert_allclose(np.bincount(k, x) / np.bincount(k), 1.0, rtol=1e-12)
    width_s = (campaign["area_hi"] - campaign["area_lo"]).values
    width_x = (campaign["x_hi"] - campaign["x_lo"]).values
    integral_s = (campaign["size_density"] * width_s).sum("bin").values
    np.testing.assert_allclose(integral_s, campaign["size_in_range_fraction"].values,
                               rtol=1e-12)
    window = campaign["time"].values >= 18.0
    integral_x = (campaign["scaled_density"] * width_x).sum("bin").values
    np.testing.assert_allclose(integral_x[window], 1.0, rtol=1e-12)


def test_standard_error_matches_bootstrap_over_seeds():
    """The ratio-estimator SE of <S>_t agrees with the bootstrap spread over seeds (20 %: the
    bootstrap of 40 seeds estimates a standard deviation to about 1/sqrt(2 x 40) = 11 %)."""
    rng = np.random.default_rng(0)
    n_s, n_t = 40, 3
    count = rng.integers(5, 15, (n_s, n_t)).astype(float)
    total = count * rng.gamma(4.0, 0.25, (n_s, n_t))
    mean, se = pooled_mean(total, count)
    idx = rng.integers(0, n_s, (4000, n_s))
    boot = total[idx].sum(axis=1) / count[idx].sum(axis=1)
    np.testing.assert_allclose(se, boot.std(axis=0), rtol=0.2)
    np.testing.assert_allclose(mean, total.sum(0) / count.sum(0), rtol=1e-12)


def test_rejects_inconsistent_inputs():
    frags = make(2)
    with pytest.raises(CraquelureError, match="repeated seeds"):
        build_campaign([frags[0], frags[0]])
    other = frags[1].isel(time=slice(0, 5), fragment=frags[1]["fragment_time_index"] < 5)
    with pytest.raises(CraquelureError, match="snapshot times"):
        build_campaign([frags[0], other])
    with pytest.raises(CraquelureError, match="no fragment datasets"):
        build_campaign([])


def test_campaign_command(tmp_path):
    paths = []
    for ds in make(3):
        p = tmp_path / f"seed{ds.attrs['seed']}.nc"
        write_dataset(ds, p)
        paths.append(str(p))
    out = tmp_path / "campaign.nc"
    assert cli_main(["campaign", *paths, "--out", str(out), "--bins", "12"]) == 0
    ds = open_dataset(out)
    assert ds.sizes["seed"] == 3 and ds.sizes["bin"] == 12
    assert ds.attrs["seeds"] == "100,101,102"
    assert "git_commit" in ds.attrs and "scene" in ds.attrs
