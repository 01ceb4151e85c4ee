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
