"""Unbonded particles for the effect tests: one compiled kernel for the fluid effects."""

import math

import numpy as np

from craquelure.lattice.engine import LatticeState


def particles(x, y, vx=None):
    n = len(x)
    m = math.pi / 4
    return LatticeState(x=np.asarray(x, float), y=np.asarray(y, float), mass=np.full(n, m),
                  inertia=np.full(n, m / 8), diameter=np.ones(n), bi=np.zeros(0, np.int64),
                  bj=np.zeros(0, np.int64), kn=np.zeros(0), ka=np.zeros(0), kb=np.zeros(0))


# one compiled kernel for the bed, buoyancy, drag and gravity tests
FLUID = ("gravity", "buoyancy", "drag", "bed")
