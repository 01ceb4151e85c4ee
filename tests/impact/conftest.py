import numba
import pytest


@pytest.fixture(autouse=True, scope="session")
def _one_numba_thread():
    """The impact kernels are small (hundreds of particles): one thread avoids barrier costs on
    the shared 2-core machine."""
    old = numba.get_num_threads()
    numba.set_num_threads(1)
    yield
    numba.set_num_threads(old)
