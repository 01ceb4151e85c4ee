"""The one minimum-image function: nearest image, scalars in kernels and arrays in Python."""

import numpy as np
from numba import njit

from craquelure.periodic import minimum_image


def test_minimum_image_is_the_nearest_image():
    rng = np.random.default_rng(3)
    length = 2.7
    d = rng.uniform(-5 * length, 5 * length, 1000)
    wrapped = minimum_image(d, length)
    assert np.all(np.abs(wrapped) <= 0.5 * length + 1e-12)
    assert np.allclose(np.rint((d - wrapped) / length) * length, d - wrapped, atol=1e-12)
    # small differences are returned bit for bit, one period off is taken back exactly
    small = d[np.abs(d) < 0.5 * length]
    assert np.array_equal(minimum_image(small, length), small)
    assert np.array_equal(minimum_image(small + length, length), (small + length) - length)


def test_minimum_image_inlines_into_a_kernel():
    @njit
    def pair(dx, length):
        return minimum_image(dx, length)

    assert pair(0.9, 1.0) == 0.9 - 1.0
    assert pair(-0.2, 1.0) == -0.2
