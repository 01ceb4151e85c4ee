"""Mesh fields (Shepard field) against a direct sum over all particles; the block-classified
image against the field summed at every mesh point as up to commit 4db0bf1, bit for bit."""

from __future__ import annotations

import numpy as np
import pytest

from craquelure.drying.field import mesh_field, mesh_image, mesh_spacing
from craquelure.drying.positions import square_lattice
from craquelure.sph.kernels import w

from .field_reference import mesh_field as reference_field


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


L2, H2 = 2.0, 0.2


def _paste(kind: str, seed: int = 4):
    """Particles at the paper's density (h = 4 spacings, N = 1600 in L = 2) with cracks:
    (x, y, volume, alive). ``lines``: removed bands along a line that wraps across both
    periodic edges, one along the edge x = 0 and one along y = L; ``holes``: 15 % removed at
    random, so that the field hovers near phi0 in many places; ``random``: uniform random
    positions (no lattice), a few lines removed."""
    rng = np.random.default_rng(seed)
    if kind == "random":
        x, y = rng.uniform(0, L2, 1600), rng.uniform(0, L2, 1600)
    else:
        x, y = square_lattice(40, L2)
        x = x + rng.uniform(-0.01, 0.01, x.size)
        y = y + rng.uniform(-0.01, 0.01, y.size)
    volume = (L2 / 40) ** 2 * rng.uniform(0.95, 1.05, x.size)
    alive = np.ones(x.size, bool)
    if kind == "holes":
        alive = rng.random(x.size) > 0.15
    else:
        alive &= np.abs(np.mod(y - 0.7 * x - 0.3, L2) - 1.0) > 0.06  # wraps across both edges
        alive &= np.minimum(x, L2 - x) > 0.05
        alive &= np.abs(y - L2) > 0.04
    return x, y, volume, alive


@pytest.mark.parametrize("kind", ["intact", "lines", "holes", "random"])
@pytest.mark.parametrize(("spacing_h", "phi0"), [(0.01, 0.8), (0.013, 0.8), (0.01, 0.55),
                                                 (0.02, 0.95), (0.05, 0.8)])
def test_mesh_image_equals_the_field_summed_everywhere(kind, spacing_h, phi0):
    """The same image bit for bit as thresholding the field summed at every mesh point:
    0.01 h the source's spacing (blocks of 5 x 5 points), 0.013 h blocks that do not tile the
    mesh, 0.02 h blocks of 3, 0.05 h no blocks; thresholds from near the edge value 1/2 to near
    the interior value 1."""
    x, y, volume, alive = _paste(kind)
    if kind == "intact":
        alive[:] = True
    spacing = spacing_h * H2
    expected = reference_field(x, y, np.where(alive, volume, 0.0), L2, H2, spacing,
                               active=alive) >= phi0
    image = mesh_image(x, y, np.where(alive, volume, 0.0), L2, H2, spacing, "quintic", phi0,
                       active=alive)
    assert image.dtype == np.bool_ and image.shape == expected.shape
    assert 0.0 < expected.mean() and (kind == "intact" or not expected.all())
    np.testing.assert_array_equal(image, expected)


def test_mesh_field_equals_the_reference_bit_for_bit():
    x, y, volume, alive = _paste("lines")
    for spacing in (0.002, 0.0026):
        np.testing.assert_array_equal(mesh_field(x, y, volume, L2, H2, spacing, active=alive),
                                      reference_field(x, y, volume, L2, H2, spacing,
                                                      active=alive))


def test_mesh_image_of_a_cracked_run_equals_the_field_summed_everywhere(tmp_path, make_scene):
    """The same on the snapshots of a real run: an RSA paste of L = 1 dried until it cracks
    (removals from t = 2.5), every snapshot at the scene's threshold and spacings 0.01 h and
    0.02 h."""
    from craquelure.drying.api import run
    from craquelure.drying.initial_state import build_initial_state
    from craquelure.io import open_dataset, write_dataset

    scene = make_scene(particles={"placement": "rsa"}, material={"drying_rate": 2e-3},
                       outputs={"t_end": 3.2, "times": [2.0, 2.8, 3.2]})
    write_dataset(build_initial_state(scene, 4), tmp_path / "state.nc")
    ds = open_dataset(run(scene, tmp_path / "run.nc", init=tmp_path / "state.nc"))
    length, h = float(ds.attrs["box_length"]), float(ds.attrs["h"])
    assert int((ds["alive"].values[-1] == 0).sum()) > 0  # cracked
    for k in range(ds.sizes["time"]):
        snap = ds.isel(time=k)
        alive = snap["alive"].values.astype(bool)
        volume = np.where(alive, snap["mass"].values / snap["rho"].values, 0.0)
        for spacing_h in (0.01, 0.02):
            args = (snap["x"].values, snap["y"].values, volume, length, h, spacing_h * h)
            expected = reference_field(*args, active=alive) >= 0.8
            np.testing.assert_array_equal(mesh_image(*args, "quintic", 0.8, active=alive),
                                          expected)
    assert not expected.all()  # the cracks show in the last image
