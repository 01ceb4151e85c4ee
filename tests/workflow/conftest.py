"""The uninterrupted end-to-end run of ``rule all`` on the CI profile, once per session: the
end-to-end checks of test_snakemake and the reference datasets of test_faults."""

from __future__ import annotations

import subprocess
from pathlib import Path

import pytest

from tests.workflow.test_snakemake import snakemake, workflow_copy


@pytest.fixture(scope="session")
def ci_run(tmp_path_factory) -> tuple[Path, subprocess.CompletedProcess]:
    work = workflow_copy(tmp_path_factory.mktemp("e2e"))
    proc = snakemake(work, "--cores", "2", "--configfile", "config/ci.yaml", timeout=1500)
    return work, proc
