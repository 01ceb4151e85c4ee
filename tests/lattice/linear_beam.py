"""The linear beam model of lattice spec section 3, the reference the tests check the lattice
kernel against: the 6x6 Euler-Bernoulli matrix written out, the general local matrix
:math:`B^T D B` of the beam energy of :mod:`craquelure.lattice.beam`, its rotation to global
axes, a network's global stiffness and a static solve."""

import math

import numpy as np

from craquelure.periodic import minimum_image


def euler_bernoulli_matrix(E_b: float, A: float, I: float, L: float) -> np.ndarray:  # noqa: N803
    """The 6x6 local stiffness matrix of a 2D Euler-Bernoulli beam, written out (section 3)."""
    a, c = E_b * A / L, E_b * I
    return np.array([
        [a, 0, 0, -a, 0, 0],
        [0, 12 * c / L**3, 6 * c / L**2, 0, -12 * c / L**3, 6 * c / L**2],
        [0, 6 * c / L**2, 4 * c / L, 0, -6 * c / L**2, 2 * c / L],
        [-a, 0, 0, a, 0, 0],
        [0, -12 * c / L**3, -6 * c / L**2, 0, 12 * c / L**3, -6 * c / L**2],
        [0, 6 * c / L**2, 2 * c / L, 0, -6 * c / L**2, 4 * c / L],
    ], dtype=np.float64)


def deformation_matrix(L: float) -> np.ndarray:  # noqa: N803
    """B with (e, phi1', phi2') = B q for small local displacements q."""
    return np.array([
        [-1.0, 0.0, 0.0, 1.0, 0.0, 0.0],
        [0.0, 1.0 / L, 1.0, 0.0, -1.0 / L, 0.0],
        [0.0, 1.0 / L, 0.0, 0.0, -1.0 / L, 1.0],
    ])


def local_matrix(kn: float, a: float, b: float, L: float) -> np.ndarray:  # noqa: N803
    """Local 6x6 stiffness B^T D B of the general beam energy (both bond models)."""
    B = deformation_matrix(L)  # noqa: N806
    D = np.array([[kn, 0.0, 0.0], [0.0, a, b], [0.0, b, a]])  # noqa: N806
    return B.T @ D @ B


def rotation_matrix(alpha: float) -> np.ndarray:
    """T = blockdiag(T1, T1), T1 = [[c, s, 0], [-s, c, 0], [0, 0, 1]] (global -> local)."""
    c, s = math.cos(alpha), math.sin(alpha)
    t1 = np.array([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]])
    t = np.zeros((6, 6))
    t[:3, :3] = t1
    t[3:, 3:] = t1
    return t


def global_matrix(k_local: np.ndarray, alpha: float) -> np.ndarray:
    """K_glob = T^T k T for a beam at angle alpha."""
    t = rotation_matrix(alpha)
    return t.T @ k_local @ t


def assemble_global(x, y, bi, bj, kn, a, b, L0=None, period_x: float = 0.0):  # noqa: N803
    """Global linear stiffness (3n x 3n, scipy CSR, dofs x, y, theta per node) of a bond
    network in configuration (x, y): sum over bonds of T^T k T (used by the static checks
    and the eigen-solve of the critical step)."""
    from scipy.sparse import coo_matrix

    n = x.size
    dx = x[bj] - x[bi]
    if period_x > 0:
        dx = minimum_image(dx, period_x)
    dy = y[bj] - y[bi]
    length = np.hypot(dx, dy) if L0 is None else np.broadcast_to(L0, dx.shape)
    alpha = np.arctan2(dy, dx)
    kn, a, b = (np.broadcast_to(v, dx.shape) for v in (kn, a, b))
    rows, cols, vals = [], [], []
    for k in range(bi.size):
        kg = global_matrix(local_matrix(kn[k], a[k], b[k], length[k]), alpha[k])
        dofs = np.r_[3 * bi[k]:3 * bi[k] + 3, 3 * bj[k]:3 * bj[k] + 3]
        rows.append(np.repeat(dofs, 6))
        cols.append(np.tile(dofs, 6))
        vals.append(kg.ravel())
    return coo_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                      shape=(3 * n, 3 * n)).tocsr()


def solve_static(K, f: np.ndarray, fixed: np.ndarray) -> np.ndarray:  # noqa: N803
    """Displacements u with K u = f on the free dofs and u = 0 on the fixed ones."""
    from scipy.sparse.linalg import spsolve

    free = np.flatnonzero(~fixed)
    u = np.zeros(f.size)
    u[free] = spsolve(K[free][:, free].tocsc(), f[free])
    return u
