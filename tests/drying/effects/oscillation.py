"""Time of the first zero crossing of a mode's projection, for the oscillation checks."""

from __future__ import annotations


def quarter_period(engine, projection, t_max):
    """Time of the first zero crossing of ``projection(engine)`` (linear interpolation)."""
    prev_t, prev = engine.t, projection(engine)
    while engine.t < t_max:
        engine.step()
        now = projection(engine)
        if prev > 0 >= now:
            return prev_t + (engine.t - prev_t) * prev / (prev - now)
        prev_t, prev = engine.t, now
    raise AssertionError("no zero crossing")
