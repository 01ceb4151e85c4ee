"""Exceptions with messages meant for the person who wrote the scene or ran the command."""


class CraquelureError(Exception):
    """Base class: the CLI prints the message and exits non-zero (no traceback)."""


class SceneError(CraquelureError):
    """A scene file or an override is invalid; the message names the key and allowed values."""


class SimulationDiverged(CraquelureError):
    """A run produced NaN/inf or a runaway energy; the message says when and what."""
