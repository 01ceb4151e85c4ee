"""Figures from analysis datasets (synthetic campaign and run): files exist, are valid PNG/PDF
with drawn content, and the captions carry the profile, sizes and fitted numbers."""

import numpy as np
import pytest
from matplotlib.image import imread

from craquelure.drying.campaign import build_campaign
from craquelure.drying.figures import (
    COMPARISON,
    FIGURES,
    comparison_series,
    fig_inverse_mean_area,
    fit_line,
    make_comparison,
    make_figures,
    setup_line,
)
from craquelure.drying.summary import summarise
from craquelure.drying.time_scales import window_of

from .synthetic_run import fragment_dataset, lattice_run

TIMES = np.arange(9.0, 31.0)


@pytest.fixture(scope="module")
def data():
    mean = 1.0 / (0.05 * np.maximum(TIMES - 9.0, 0.5))
    frags = [fragment_dataset(s, TIMES, mean, np.maximum(1, np.round(16 / mean)).astype(int))
             for s in range(1, 9)]
    campaign = build_campaign(frags, n_bins=15)
    summary = summarise(campaign, profile="test", n_boot=100, n_power=100, n_power_collapse=5)
    bands = [[]] * 12 + [[("y", 1.0, 1.3)]] * 5 + [[("y", 1.0, 1.3), ("x", 0.5, 0.8)]] * 5
    run = lattice_run(40, 2.0, bands_per_time=bands, times=TIMES, scene="drying/default")
    return campaign, summary, run


def test_captions_state_profile_sizes_and_fit(data):
    campaign, summary, _ = data
    setup = setup_line(campaign, "test")
    assert "profile test" in setup and "N = 6400" in setup and "8 seeds" in setup
    assert "10x faster than the paper" in setup
    # tau = eta/(2 mu) = 5, t* = 22.7: Pi = 0.22 (paper 0.022).
    assert "Pi = tau/t* = 0.22 with tau = eta/(2 mu) = 5 (paper 0.022)" in setup
    fit = fit_line(summary)
    assert f"alpha = {summary['fit']['alpha']:.3g}" in fit
    c14 = summary["checks"]["check14_inverse_mean_area_linear"]
    assert f"reduced chi^2 = {c14['reduced_chi2']:.3g}" in fit
    lo, hi = summary["fit"]["alpha_ci95"]
    assert f"{lo:.3g}-{hi:.3g}" in fit
    fig = fig_inverse_mean_area(campaign, summary, "test")
    texts = [t.get_text() for t in fig.texts]
    assert any("alpha" in t and "profile test" in t for t in texts)


def test_ccdf_bands_bracket_the_curve_and_shrink_with_more_samples():
    from craquelure.drying.summary import ccdf_bands

    mean = np.full(TIMES.size, 1.0)

    def bands(n_seeds):
        frags = [fragment_dataset(s, TIMES, mean, np.full(TIMES.size, 20), shape=1.0)
                 for s in range(1, n_seeds + 1)]
        c = build_campaign(frags, n_bins=10)
        return ccdf_bands(c, 5, np.linspace(0.0, 4.0, 41), scaled=True, n_boot=200)

    few, many = bands(3), bands(24)
    for b in (few, many):
        assert b["ccdf"][0] == 1.0 and np.all(np.diff(b["ccdf"]) <= 0)
        assert np.all(b["lo"] <= b["ccdf"] + 1e-12) and np.all(b["ccdf"] <= b["hi"] + 1e-12)
    # Exponential X: P(X > 1) = e^-1 within the band of 24 x 20 fragments.
    assert many["lo"][10] < np.exp(-1.0) < many["hi"][10]
    width = lambda b: np.mean(b["hi"] - b["lo"])  # noqa: E731
    assert width(many) < 0.6 * width(few)  # ~ sqrt(3/24) = 0.35


@pytest.mark.slow
def test_all_figures_written_as_png_and_pdf(data, tmp_path):
    campaign, summary, run = data
    outputs = {name: tmp_path / f"{name}.png" for name in FIGURES}
    written = make_figures(campaign, summary, run, outputs, "test")
    assert len(written) == 2 * len(FIGURES)
    for name in FIGURES:
        png = imread(outputs[name])
        assert png.shape[0] > 300 and png.shape[1] > 500
        # Not blank: many distinct colours are drawn.
        assert np.unique(png.reshape(-1, png.shape[-1]), axis=0).shape[0] > 20
        pdf = (tmp_path / f"{name}.pdf").read_bytes()
        assert pdf.startswith(b"%PDF") and len(pdf) > 5000


def test_comparison_draws_each_ensembles_series(data, tmp_path):
    """The comparison of ensembles plots, per ensemble, its campaign's 1/<S>_t against t/t*,
    check 14's fitted line at the window's ends, and the CCDF of X = S/<S>_t over the
    window's fragments (what the counts give directly); both figures are drawn."""
    campaign, summary, _ = data
    summary = {**summary, "box_length": 2.0}
    series = [comparison_series(name, summary, {"periodic": campaign})
              for name in ("one", "other")]
    d = series[0]["labellings"]["periodic"]
    tstar = float(campaign.attrs["t_star"])
    np.testing.assert_allclose(d["t_over_t_star"], TIMES / tstar)
    np.testing.assert_allclose(np.array(d["inverse_mean_area"], float),
                               1 / campaign["mean_area"].values)
    c14 = summary["checks"]["check14_inverse_mean_area_linear"]
    lo, hi = summary["window"]
    np.testing.assert_allclose(d["fit_inverse_mean_area"],
                               [c14["intercept_a"] + c14["slope_b"] * t for t in (lo, hi)])
    in_window = window_of(campaign)["mask"][campaign["fragment_time_index"].values]
    x = campaign["fragment_scaled_area"].values[in_window]
    assert d["n_fragments"] == x.size > 50
    for g, p in zip(d["x"], d["ccdf"], strict=True):
        assert p == pytest.approx(np.mean(x > g), abs=1e-12)
    assert "N = " in series[0]["setting"] and "8 seeds" in series[0]["setting"]
    outputs = {name: tmp_path / f"{name}.png" for name in COMPARISON}
    assert len(make_comparison(series, outputs)) == 2 * len(COMPARISON)
    for name in COMPARISON:
        png = imread(outputs[name])
        assert np.unique(png.reshape(-1, png.shape[-1]), axis=0).shape[0] > 20
