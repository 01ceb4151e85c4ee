"""Progress lines: the first after a few seconds, then one per interval."""

from __future__ import annotations


def test_progress_first_line_after_seconds_then_at_its_interval(monkeypatch):
    """Plain log lines (not a terminal): the first once ``first_line_s`` (2 s) have passed,
    with the simulated time, the rate and the ETA; then one per ``log_every_s``."""
    import io

    from craquelure import progress

    now = [100.0]
    monkeypatch.setattr(progress.time, "perf_counter", lambda: now[0])
    out = io.StringIO()
    bar = progress.Progress(10.0, "demo", unit="t", stream=out)
    for t, value in ((101.0, 0.5), (102.5, 1.25), (110.0, 4.0), (133.0, 5.0)):
        now[0] = t
        bar.update_to(value, "42 particle-steps/s")
    lines = out.getvalue().splitlines()
    assert len(lines) == 2
    # at 2.5 s: 1.25 of 10 done at 0.5 t/s, so 17.5 s to go
    assert lines[0] == ("[demo] 1.25/10 t ( 12.5 %) elapsed     2.5 s, eta    17.5 s "
                        "42 particle-steps/s")
    assert lines[1].startswith("[demo] 5/10 t ( 50.0 %) elapsed    33.0 s")
