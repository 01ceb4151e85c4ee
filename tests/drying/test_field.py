"""Mesh fields (Shepard field) against a direct sum over all particles."""

from __future__ import annotations

import numpy as np
import pytest

from craquelure.drying.field import mesh_field, mesh_spacing
from craquelure.drying.positions import square_lattice
from craquelure.sph.kernels import w


@pytest.mark.parametrize("kernel", ["quintic", "wendland_c2"])
def test_mesh_field_equals_direct_sum(kernel):
    rng = np.random.default_rng(8)
    length, s = 1.5, 0.3
    x, y = rng.uniform(0, length, 300), rng.uniform(0, length, 300)
    x[:5] = 0.0
    y[5:10] = length
    value = rng.uniform(0.5, 2.0, 300)
    phi = mesh_field(x, y, value, length, s, 0.05, kernel)
    spacing = mesh_spacing(length, 0.05)
    n_mesh = phi.shape[0]
    assert phi.shape == (n_mesh, n_mesh) and n_mesh * spacing == pytest.approx(length)
    g = np.arange(n_mesh) * spacing
    px, py = np.meshgrid(g, g)  # [j, i] indexing: row = y
    dx = px.ravel()[:, None] - x[None, :]
    dy = py.ravel()[:, None] - y[None, :]
    dx -= length * np.rint(dx / length)
    dy -= length * np.rint(dy / length)
    ref = (w(kernel, np.hypot(dx, dy), s) * value[None, :]).sum(axis=1).reshape(n_mesh, n_mesh)
    np.testing.assert_allclose(phi, ref, rtol=1e-12, atol=1e-12 * ref.max())


def test_shepard_field_of_a_lattice_is_one_and_drops_in_a_gap():
    length, n_side, h = 2.0, 40, 0.2
    x, y = square_lattice(n_side, length)
    vol = np.full(x.size, (length / n_side) ** 2)
    phi = mesh_field(x, y, vol, length, h, 0.01)
    assert np.abs(phi - 1).max() < 1e-4
    # Remove a band of width 4 h: the field vanishes in its middle, about 1/2 on its edges.
    keep = ~((x > 0.6) & (x < 1.4))
    phi = mesh_field(x[keep], y[keep], vol[keep], length, h, 0.01)
    assert phi[:, 100].max() < 1e-12
    edge = phi[:, int(round(0.6 / 0.01))]
    assert np.all((edge > 0.4) & (edge < 0.6))
