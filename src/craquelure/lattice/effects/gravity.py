r"""Gravity: :math:`F_y = -m g` on every particle, energy :math:`m g (y - y_{ref})` with the
initial positions as reference (lattice spec sections 5 and 10)."""

from numba import njit

from craquelure.registry import Effect

EFFECT = Effect(
    name="gravity",
    models=("lattice",),
    description="uniform gravity -m g along y",
    requires={"lattice": ("material.g",)},
)


@njit(inline="always", cache=True)
def gravity(m, g, y, y_ref):
    """(force y, energy relative to y_ref)."""
    return -m * g, m * g * (y - y_ref)
