"""Time scales and statistics windows (craquelure.drying.time_scales; drying spec sections 10
and 13)."""

import numpy as np
import pytest

from craquelure.drying.summary import summarise
from craquelure.drying.time_scales import (
    campaign_window,
    collapse_times,
    paper_t_star,
)

from .synthetic_run import T_STAR, TIMES, campaign_of


def test_windows_scale_with_t_star():
    assert paper_t_star() == pytest.approx(227.2727, rel=1e-5)
    for tstar, window in ((paper_t_star(), (180.0, 300.0)), (T_STAR, (18.0, 30.0))):
        paper = campaign_window(np.array([1.0]), np.ones((1, 1)), tstar)
        assert (paper["start"], paper["end"]) == pytest.approx(window)
    paper_times = np.arange(90.0, 301.0, 10.0)
    assert collapse_times(paper_times, paper_t_star()).tolist() == list(range(180, 301, 20))
    assert collapse_times(TIMES, T_STAR).tolist() == list(range(18, 31, 2))
    # Snapshots taken a fraction of a step after the requested time still match.
    assert collapse_times(TIMES + 0.002, T_STAR).size == 7



def test_all_broken_window_starts_when_every_sample_is_broken():
    """Window mode all_broken: from the first snapshot from which on every sample has >= 2
    fragments (half the synthetic samples stay whole until t0 + 1) to the last snapshot, with
    7 collapse times spread over it; the summary reports the mode and the window."""

    t0 = 12.0
    campaign = campaign_of(b=0.05, t0=t0, n_seeds=6, window_mode="all_broken")
    counts = campaign["n_fragments"].values
    first_all = TIMES[np.all(counts >= 2, axis=0)][0]
    assert first_all >= t0 + 1  # the unbroken half delays it
    win = campaign_window(TIMES, counts, T_STAR, "all_broken")
    assert win["start"] == first_all and win["end"] == TIMES[-1]
    assert win["mask"].sum() == np.count_nonzero(TIMES >= first_all)
    assert win["collapse_times"].size == 7
    assert win["collapse_times"][0] == first_all and win["collapse_times"][-1] == TIMES[-1]
    # A sample that heals back to one fragment moves the start past that snapshot.
    healed = counts.copy()
    healed[0, -3] = 1
    assert campaign_window(TIMES, healed, T_STAR, "all_broken")["start"] == TIMES[-2]
    # Recorded in the campaign, read back by the summary.
    summary = summarise(campaign, profile="test", n_boot=50, n_power=200, n_power_collapse=10)
    assert summary["window_mode"] == "all_broken"
    assert summary["window"] == pytest.approx([first_all, TIMES[-1]])
    with pytest.raises(Exception, match="allowed values: paper, all_broken"):
        campaign_window(TIMES, counts, T_STAR, "fastest")

