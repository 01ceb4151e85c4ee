r"""Specimen: regular grid geometry, random particle masses, pre-crack layouts (spec sections 1, 4).

- Disc: a ``diameter_cells``² cell-centred square grid of spacing Δ keeping the centres within
  radius ``diameter_cells``·Δ/2 of the disc centre (40 cells → 1264 particles). Rectangle (tests):
  ``diameter_cells`` × ``height_cells`` cells. 3D (``domain.dim: 3``, spec section 1): that
  grid repeated in ``thickness_cells`` layers at z = (k − (n_z − 1)/2)Δ, the disc's axis along
  z (horizontal), so its rim strikes the base: 40 cells × 8 layers = 8 × 1264 = 10 112
  particles, the source's count. The lowest centre sits at
  :math:`y = y_{base} + r_c + \text{gap}\,\Delta`; every particle moves at
  :math:`(0, -v_{impact})`.
- Masses: total :math:`M = N\rho_0\Delta^d` (per metre in 2D) is fixed; :math:`\omega_i` i.i.d.
  with mean 1: ``uniform`` U(0, 2) [C]; ``normal`` N(1, sd²) with negatives redrawn [D];
  ``poisson`` :math:`\omega = k/\lambda_P`, :math:`k \sim` Poisson(λ_P) (exact zeros) [D];
  :math:`m_i = \omega_i M/\sum_j\omega_j`. ``homogeneous``: :math:`m_i = \rho_0\Delta^d`.
  :math:`\rho_i(0) = \rho_0` and :math:`h_i(0) = \kappa\,h_{factor}\Delta` for every particle, so
  the geometry stays the homogeneous grid and only the "virtual volume" :math:`m_i/\rho_0` varies.
- Pre-cracks: a layout is data in the scene (``precracks``: name → segments in units of R from
  the disc centre); a line one particle column wide gets m = 0 (spec check 12: "one particle
  column of zero mass"): for a segment steeper than 45° one particle per grid row, the one with
  −Δ/2 ≤ x − x_line(y) < Δ/2, over the rows the segment spans (one per column for flatter
  segments); in 3D the same (x, y) in every layer. The others keep their mass, not
  renormalised [C maps]; a pre-crack applies on top of the chosen mass distribution.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from craquelure.errors import SceneError
from craquelure.scene import Scene


@dataclass
class Specimen:
    x: np.ndarray
    y: np.ndarray
    mass: np.ndarray
    spacing: float
    radius: float        # disc radius (rectangle: half width)
    centre_y: float
    precrack: np.ndarray  # bool, particle on a pre-crack line
    vx: np.ndarray | None = None  # initial x velocity (rings); None: the disc's (0, -v_impact)
    z: np.ndarray | None = None   # 3D: position along the disc axis (None in 2D)

    @property
    def dim(self) -> int:
        return 2 if self.z is None else 3

    @property
    def n(self) -> int:
        return self.x.size


def grid(shape: str, cells: int, height_cells: int, spacing: float) -> tuple[np.ndarray, ...]:
    """Cell-centred grid points relative to the body centre."""
    rows = cells if shape == "disc" else height_cells
    cx = (np.arange(cells) - (cells - 1) / 2.0) * spacing
    cy = (np.arange(rows) - (rows - 1) / 2.0) * spacing
    gx, gy = np.meshgrid(cx, cy, indexing="xy")
    if shape == "disc":
        keep = gx**2 + gy**2 <= (cells * spacing / 2.0) ** 2 * (1 + 1e-12)
        return gx[keep], gy[keep]
    return gx.ravel(), gy.ravel()


def draw_weights(distribution: str, n: int, rng: np.random.Generator, normal_sd: float,
                 poisson_lambda: float) -> np.ndarray:
    """Relative masses omega_i with mean 1 (before the exact rescaling)."""
    if distribution == "homogeneous":
        return np.ones(n)
    if distribution == "uniform":
        return rng.uniform(0.0, 2.0, n)
    if distribution == "normal":
        w = rng.normal(1.0, normal_sd, n)
        while (bad := w < 0).any():
            w[bad] = rng.normal(1.0, normal_sd, int(bad.sum()))
        return w
    if distribution == "poisson":
        return rng.poisson(poisson_lambda, n) / poisson_lambda
    raise SceneError(f"particles.masses.distribution: {distribution!r} is not allowed")


def precrack_mask(x_rel, y_rel, segments, radius: float, spacing: float) -> np.ndarray:
    """Zero-mass line one particle column wide per segment (module docstring)."""
    mask = np.zeros(x_rel.size, bool)
    tol = 1e-9 * spacing
    for (x0, y0), (x1, y1) in segments:
        ax, ay, bx, by = x0 * radius, y0 * radius, x1 * radius, y1 * radius
        # across: the grid coordinate the line is one particle wide in; along: the other
        if abs(by - ay) >= abs(bx - ax):
            along, across, a0, a1, c0, c1 = y_rel, x_rel, ay, by, ax, bx
        else:
            along, across, a0, a1, c0, c1 = x_rel, y_rel, ax, bx, ay, by
        lo, hi = min(a0, a1), max(a0, a1)
        span = (along >= lo - tol) & (along <= hi + tol)
        line = c0 + (along - a0) * (c1 - c0) / (a1 - a0)
        offset = across - line
        mask |= span & (offset >= -0.5 * spacing - tol) & (offset < 0.5 * spacing - tol)
    return mask


def rings(inner: float, outer: float, half_distance: float, spacing: float):
    """Two rings on PySPH's ``solid_mech/rings`` grid: points (x, y) = (-r_o + iΔ, -r_o + jΔ)
    with r_i² ≤ x² + y² < r_o², copied to x ∓ half_distance; returns (x, y, side) with side
    -1 for the left ring and +1 for the right one."""
    # np.mgrid's own arithmetic (start + i step), so the points on r_i and r_o fall on the
    # same side as in PySPH: 17 592 particles at Δ = 5e-4 m, 70 320 at 2.5e-4 m
    gx, gy = np.mgrid[-outer:outer:spacing, -outer:outer:spacing]
    d = gx**2 + gy**2
    keep = (inner * inner <= d) & (d < outer * outer)
    x, y = gx[keep], gy[keep]
    side = np.concatenate([-np.ones(x.size), np.ones(x.size)])
    return (np.concatenate([x - half_distance, x + half_distance]), np.concatenate([y, y]),
            side)


def build_specimen(scene: Scene, seed: int) -> Specimen:
    dx = scene.get("particles.spacing")
    shape = scene.get("particles.shape")
    if shape == "rings":
        return _rings_specimen(scene, dx)
    cells = scene.get("particles.diameter_cells")
    x, y = grid(shape, cells, scene.get("particles.height_cells"), dx)
    z = None
    dim = scene.get("domain.dim")
    if dim == 3:
        layers = scene.get("particles.thickness_cells")
        zc = (np.arange(layers) - (layers - 1) / 2.0) * dx
        z = np.repeat(zc, x.size)
        x, y = np.tile(x, layers), np.tile(y, layers)
    radius = cells * dx / 2.0
    r_c = scene.get("numerics.contact_radius") * dx
    centre_y = scene.get("domain.base_y") + r_c + scene.get("particles.gap") * dx - y.min()
    n = x.size
    w = draw_weights(scene.get("particles.masses.distribution"), n, np.random.default_rng(seed),
                     scene.get("particles.masses.normal_sd"),
                     scene.get("particles.masses.poisson_lambda"))
    # rho0 Delta^d per particle
    total = n * scene.get("material.rho0") * dx * dx * (dx if dim == 3 else 1.0)
    if w.sum() <= 0:
        raise SceneError("particles.masses: every drawn weight is zero")
    mass = w * (total / w.sum())
    name = scene.get("particles.precrack")
    crack = np.zeros(n, bool)
    if name != "none":  # a layout under precracks (scene rules)
        crack = precrack_mask(x, y, scene.get("precracks")[name], radius, dx)
        mass[crack] = 0.0
    return Specimen(x=x, y=y + centre_y, mass=mass, spacing=dx, radius=radius,
                    centre_y=centre_y, precrack=crack, z=z)


def _rings_specimen(scene: Scene, dx: float) -> Specimen:
    """Homogeneous masses ρ0 Δ²; the rings' lowest point r_c + gap Δ above the base (only where they
    sit: no contact); each moves towards the other at ``particles.rings.speed``."""
    g = scene.get
    inner, outer = g("particles.rings.inner_radius"), g("particles.rings.outer_radius")
    x, y, side = rings(inner, outer, g("particles.rings.half_distance"), dx)
    r_c = g("numerics.contact_radius") * dx
    centre_y = g("domain.base_y") + r_c + g("particles.gap") * dx - y.min()
    mass = np.full(x.size, g("material.rho0") * dx * dx)
    return Specimen(x=x, y=y + centre_y, mass=mass, spacing=dx, radius=outer, centre_y=centre_y,
                    precrack=np.zeros(x.size, bool), vx=-side * g("particles.rings.speed"))


def initial_smoothing_length(scene: Scene) -> float:
    return (scene.get("numerics.kappa") * scene.get("numerics.h_factor")
            * scene.get("particles.spacing"))
