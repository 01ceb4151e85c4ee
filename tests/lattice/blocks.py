"""Geometry of the lattice scenes' blocks, as the tests measure it."""

from craquelure.lattice.geometry import ROW


def block_height(scene) -> float:
    """Height of the block between the bottom and top rows' centres."""
    return (scene.get("domain.ny") - 1) * ROW * scene.get("particles.spacing")
