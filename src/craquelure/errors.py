"""Exceptions with messages meant for the person who wrote the scene or ran the command."""


class CraquelureError(Exception):
    """Base class: the CLI prints the message and exits non-zero (no traceback)."""


class SceneError(CraquelureError):
    """A scene file or an override is invalid; the message names the key and allowed values."""


class SimulationDiverged(CraquelureError):
    """A run produced NaN/inf or a runaway energy; the message says when and what."""


class RunInterrupted(CraquelureError):
    """SIGTERM or SIGINT stopped a run; the message names the checkpoint it wrote. The CLI
    exits with :data:`INTERRUPTED_EXIT`, not 2, so a scheduler can tell "resume me" from
    "this run cannot work"."""


# exit status of a run stopped after writing its checkpoint (2: a clear error, 1: a traceback)
INTERRUPTED_EXIT = 3


class WriteError(CraquelureError):
    """A file could not be written (full disk, read-only or forbidden folder); the message
    names the file and the cause; what was there before is left intact."""
