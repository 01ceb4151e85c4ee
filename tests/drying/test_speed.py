"""Drying-speed study on synthetic campaigns whose onset and 1/t law are known."""

from __future__ import annotations

import numpy as np
import pytest

from craquelure.drying.speed import speed_study

from .synthetic_run import fragment_dataset

SIGMA_Y, TAU = 5e-3, 5.0  # default scene: eta = 1, mu = 0.1


def speed_campaign(pi, onset_over_t_star, n_seeds=6, box_area=16.0):
    """Fragments of a campaign at Pi: snapshots at 0.2-2 t*, every sample broken from
    onset * t*, 1/<S> = b* (t - onset t*) after it (b* of the default scene)."""
    rate = pi * SIGMA_Y / TAU
    t_star = SIGMA_Y / rate
    times = np.round(np.arange(0.2, 2.01, 0.1) * t_star, 9)
    b_star = 0.1 * rate / (1.2 * 0.316**2 * SIGMA_Y)
    broken = times / t_star > onset_over_t_star - 1e-6
    mean = 1.0 / (b_star * np.maximum(times - onset_over_t_star * t_star, 0.05 * t_star))
    n = np.where(broken, np.maximum(2, np.round(box_area / mean)), 1).astype(int)
    mean = np.where(n == 1, box_area, mean)
    return [fragment_dataset(s, times, mean, n, shape=2.0, drying_rate=rate,
                             first_removal=0.9 * onset_over_t_star * t_star)
            for s in range(1, n_seeds + 1)]


@pytest.fixture(scope="module")
def study():
    groups = {pi * SIGMA_Y / TAU: speed_campaign(pi, onset)
              for pi, onset in ((0.66, 1.2), (0.2, 0.8), (0.05, 0.5), (0.022, 0.4))}
    return speed_study(groups, fixed_over_t_star=[1.5, 2.0], n_boot=200)


def test_speeds_are_sorted_by_pi_and_carry_the_paper(study):
    assert study["speed"].values == pytest.approx([0.022, 0.05, 0.2, 0.66])
    assert study.attrs["paper_pi"] == 0.022
    assert np.all(study["n_seeds"].values == 6)
    assert study["t_star"].values[0] == pytest.approx(227.27, rel=1e-4)


def test_onset_in_t_star_with_intervals(study):
    # Every sample breaks at the first snapshot >= onset t*.
    assert study["all_samples_broken"].values == pytest.approx([0.4, 0.5, 0.8, 1.2], abs=1e-6)
    assert study["first_sample_broken"].values == pytest.approx([0.4, 0.5, 0.8, 1.2], abs=1e-6)
    assert study["first_removal_median"].values == pytest.approx(
        0.9 * np.array([0.4, 0.5, 0.8, 1.2]))
    lo, hi = study["all_samples_broken_lo"].values, study["all_samples_broken_hi"].values
    assert np.all(lo <= study["all_samples_broken"].values + 1e-12)
    assert np.all(study["all_samples_broken"].values <= hi + 1e-12)


def test_inverse_area_law_recovered_in_units_of_t_star_and_b_star(study):
    # The synthetic law is 1/<S> = b* (t - onset t*) at every speed (its first snapshot is held
    # at t - onset t* = 0.05 t*, which pulls the fitted slope ~5 % low).
    assert study["t0_over_t_star"].values == pytest.approx([0.4, 0.5, 0.8, 1.2], abs=0.1)
    assert study["b_over_b_star"].values == pytest.approx(1.0, rel=0.15)
    b, lo, hi = (study[k].values for k in ("b_over_b_star", "b_over_b_star_lo",
                                            "b_over_b_star_hi"))
    assert np.all((lo < b) & (b < hi)) and np.all(hi - lo < 0.3)


def test_fragments_per_area_at_fixed_t_over_t_star(study):
    # At t = 2 t*: <S> = 1/(b* t* (2 - onset)), and b* t* = mu/((lambda + 2 mu) H^2) = 0.835.
    per_area = study["fragments_per_area"].sel(fixed_time=2.0).values
    expected = 0.835 * (2.0 - np.array([0.4, 0.5, 0.8, 1.2]))
    assert per_area == pytest.approx(np.round(16 * expected) / 16, rel=0.02)


def test_one_speed_is_rejected():
    from craquelure.errors import CraquelureError

    with pytest.raises(CraquelureError, match="at least two drying speeds"):
        speed_study({1e-3: speed_campaign(1.0, 1.0, n_seeds=2)}, [1.0])


def test_speed_figure_is_drawn_with_pi_in_the_caption(study, tmp_path):
    from matplotlib.image import imread

    from craquelure.drying.figures import fig_speed, save_figure

    fig = fig_speed(study, "test")
    assert any("Pi = 0.022, 0.05, 0.2, 0.66 (paper 0.022)" in t.get_text() for t in fig.texts)
    png, pdf = save_figure(fig, tmp_path / "speed.png")
    image = imread(png)
    assert image.shape[1] > 1000
    assert np.unique(image.reshape(-1, image.shape[-1]), axis=0).shape[0] > 20
    assert pdf.read_bytes().startswith(b"%PDF")


def test_speed_figure_says_which_speeds_have_no_fit_or_unbroken_samples(study):
    from craquelure.drying.figures import fig_speed

    blank = study.copy(deep=True)
    blank["t0_over_t_star"][:] = np.nan
    blank["all_samples_broken"][0] = np.nan
    fig = fig_speed(blank, "test")
    texts = [t.get_text() for ax in fig.axes for t in ax.texts]
    assert any("no fit at Pi = 0.022, 0.05, 0.2, 0.66" in t for t in texts)
    assert any("not all samples broken by the run's end at Pi = 0.022" in t for t in texts)
    # the fixture's every speed has a fit and all samples broken: nothing to say
    assert not [t for ax in fig_speed(study, "t").axes for t in ax.texts]
