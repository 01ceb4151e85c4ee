"""Suite-wide settings.

Numba kernels run on one thread inside the test process: the checks are about numbers, not
speed, results do not depend on the thread count (all pair loops gather, none scatter), and a
parallel region on an oversubscribed machine (CI shares its 2 cores with Snakemake jobs in the
end-to-end test) can be ten times slower than a serial one. Subprocesses are unaffected.
"""

import numba
import pytest


@pytest.fixture(autouse=True, scope="session")
def _serial_numba():
    numba.set_num_threads(1)
    yield


# Property-based tests (hypothesis): the default profile is derandomised so CI is
# reproducible and sized for it (a few hundred examples); `pytest --hypothesis-profile
# thorough` draws ten times as many, at random.
from hypothesis import HealthCheck, settings  # noqa: E402

_QUIET = [HealthCheck.too_slow, HealthCheck.filter_too_much, HealthCheck.data_too_large]
settings.register_profile("ci", max_examples=400, derandomize=True, deadline=None,
                          database=None, suppress_health_check=_QUIET, print_blob=True)
settings.register_profile("thorough", max_examples=4000, deadline=None,
                          suppress_health_check=_QUIET, print_blob=True)
settings.load_profile("ci")


def pytest_addoption(parser):
    parser.addoption("--hard-cases", choices=("ci", "all"), default="ci",
                     help="hard-case suite: 'ci' runs the representative subset, 'all' also "
                          "the slow cases (marked hard_slow)")


def pytest_collection_modifyitems(config, items):
    if config.getoption("--hard-cases") == "all":
        return
    skip = pytest.mark.skip(reason="slow hard case: run with --hard-cases=all")
    for item in items:
        if "hard_slow" in item.keywords:
            item.add_marker(skip)
