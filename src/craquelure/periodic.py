"""The minimum-image convention, written once for every engine and helper.

A coordinate difference ``d`` along a periodic direction of length ``L`` is replaced by its
nearest image, ``d - L rint(d/L)`` (in (-L/2, L/2]). Numba inlines it into the kernels; called
from Python it also takes numpy arrays.
"""

import numpy as np
from numba import njit


@njit(inline="always", cache=True)
def minimum_image(d, length):
    """Nearest periodic image of the difference ``d`` along a direction of period ``length``."""
    return d - length * np.rint(d / length)


@njit(inline="always", cache=True)
def minimum_image_inv(d, length, inv_length):
    """:func:`minimum_image` with the reciprocal period given (no division in pair loops); the
    same value whenever d/length is not within round-off of a half-integer (never for pairs
    closer than length/2)."""
    return d - length * np.rint(d * inv_length)
