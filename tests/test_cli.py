"""The console entry point in a new process (``python -m craquelure``): a bad scene exits
non-zero with the message on stderr and no traceback; ``scenes`` lists the built-in scenes."""

from __future__ import annotations

import subprocess
import sys

from tests.commands.test_check import write_scene
from tests.test_scene import ci_text


def test_cli_subprocess_exit_code_and_stderr(tmp_path):
    path = write_scene(tmp_path, ci_text(("  h: 0.2\n", "  h: -0.2\n")))
    proc = subprocess.run([sys.executable, "-m", "craquelure", "check", str(path)],
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode != 0
    assert "numerics.h: -0.2 is not allowed; must be > 0" in proc.stderr
    assert "Traceback" not in proc.stderr
    proc = subprocess.run([sys.executable, "-m", "craquelure", "scenes"],
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0 and "drying/ci" in proc.stdout
