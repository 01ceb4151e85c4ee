"""Symmetric 3x3 stresses as the effect fragments store them: components (xx, yy, xy, zz, xz,
yz), random stresses and rotations."""

import numpy as np


def matrix(s):
    xx, yy, xy, zz, xz, yz = s
    return np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])


def components(a):
    return (a[0, 0], a[1, 1], a[0, 1], a[2, 2], a[0, 2], a[1, 2])


def random_stress(rng, lo=-60e6, hi=10e6):
    return components(matrix(rng.uniform(lo, hi, 6)))


def rotate(s, q):
    return components(q @ matrix(s) @ q.T)
