r"""SPH smoothing kernels, written in terms of the **support radius** :math:`s` (``W = 0`` for
``r >= s``).

All kernels have the form :math:`W(r; s) = \frac{C_d}{s^d} f(x)`, :math:`x = r/s`, and
:math:`\partial W/\partial r = \frac{C_d}{s^{d+1}} f'(x)`; :math:`\nabla_I W_{IJ} =
(\partial W/\partial r)\, \mathbf r_{IJ}/|\mathbf r_{IJ}|`.

- ``quintic`` (drying spec section 5, support radius h):
  :math:`f = (3-3x)_+^5 - 6(2-3x)_+^5 + 15(1-3x)_+^5`, :math:`C_2 = 63/(478\pi)`,
  :math:`C_3 = 27/(120\pi)` (Morris' quintic with :math:`h' = s/3`).
- ``cubic`` (impact spec section 3, support 2h, so :math:`s = 2h`, :math:`q = r/h = 2x`):
  :math:`f = 1 - 1.5q^2 + 0.75q^3` (q < 1), :math:`0.25(2-q)^3` (1 <= q < 2);
  :math:`C_2 = 40/(7\pi)`, :math:`C_3 = 8/\pi`.
- ``wendland_c2``: :math:`f = (1-x)_+^4 (1+4x)`, :math:`C_2 = 7/\pi`, :math:`C_3 = 21/(2\pi)`.

Kernel kinds are small integers so that compiled code can take the kind as a compile-time
constant (the branch folds away) or as a run-time argument (utilities, tests).
"""

import math

import numpy as np
from numba import njit

QUINTIC, CUBIC, WENDLAND_C2 = 0, 1, 2
KERNEL_KINDS = {"quintic": QUINTIC, "cubic": CUBIC, "wendland_c2": WENDLAND_C2}

def kernel_kind(name: str) -> int:
    if name not in KERNEL_KINDS:
        raise ValueError(f"kernel: {name!r} is not allowed; allowed values: "
                         f"{', '.join(KERNEL_KINDS)}")
    return KERNEL_KINDS[name]


@njit(inline="always", cache=True)
def kernel_norm(kind, dim):
    if kind == QUINTIC:
        return 63.0 / (478.0 * math.pi) if dim == 2 else 27.0 / (120.0 * math.pi)
    if kind == CUBIC:
        return 40.0 / (7.0 * math.pi) if dim == 2 else 8.0 / math.pi
    return 7.0 / math.pi if dim == 2 else 21.0 / (2.0 * math.pi)


@njit(inline="always", cache=True)
def kernel_shape(kind, x):
    """f(x) for x = r/s >= 0."""
    if x >= 1.0:
        return 0.0
    if kind == QUINTIC:
        a = 3.0 - 3.0 * x
        f = a * a * a * a * a
        if x < 2.0 / 3.0:
            b = 2.0 - 3.0 * x
            f -= 6.0 * (b * b * b * b * b)
            if x < 1.0 / 3.0:
                c = 1.0 - 3.0 * x
                f += 15.0 * (c * c * c * c * c)
        return f
    if kind == CUBIC:
        q = 2.0 * x
        if q < 1.0:
            return 1.0 - 1.5 * q * q + 0.75 * q * q * q
        b = 2.0 - q
        return 0.25 * b * b * b
    a = 1.0 - x
    return a * a * a * a * (1.0 + 4.0 * x)


@njit(inline="always", cache=True)
def kernel_dshape(kind, x):
    """f'(x) = df/dx for x = r/s >= 0."""
    if x >= 1.0:
        return 0.0
    if kind == QUINTIC:
        a = 3.0 - 3.0 * x
        d = a * a * a * a
        if x < 2.0 / 3.0:
            b = 2.0 - 3.0 * x
            d -= 6.0 * (b * b * b * b)
            if x < 1.0 / 3.0:
                c = 1.0 - 3.0 * x
                d += 15.0 * (c * c * c * c)
        return -15.0 * d
    if kind == CUBIC:
        q = 2.0 * x
        if q < 1.0:
            return 2.0 * (-3.0 * q + 2.25 * q * q)
        b = 2.0 - q
        return 2.0 * (-0.75 * b * b)
    a = 1.0 - x
    return -20.0 * x * a * a * a


@njit(inline="always", cache=True)
def kernel_w(kind, r, s, dim):
    """W(r; s) in ``dim`` dimensions."""
    inv = 1.0 / s
    scale = inv * inv if dim == 2 else inv * inv * inv
    return kernel_norm(kind, dim) * scale * kernel_shape(kind, r * inv)


@njit(inline="always", cache=True)
def kernel_dwdr(kind, r, s, dim):
    """dW/dr (r; s) in ``dim`` dimensions (<= 0)."""
    inv = 1.0 / s
    scale = inv * inv * inv if dim == 2 else inv * inv * inv * inv
    return kernel_norm(kind, dim) * scale * kernel_dshape(kind, r * inv)


@njit(inline="always", cache=True)
def quintic_w_g(r2, inv_s):
    """Branch-free quintic (2D) from the squared distance: ``(W, (dW/dr)/r)`` with ``inv_s`` =
    1/s. The clamps max(k - 3x, 0) are the spec's (k - 3x)_+, so one formula covers every piece
    and x >= 1 (all three terms vanish: W = 0, g = 0, exactly as the piecewise form). At r = 0,
    f'(0) = -15 (3^4 - 6 2^4 + 15) = 0 exactly, so g = 0 there (r2 is floored at 1e-300 only to
    keep 1/r finite). One square root and one division per pair."""
    # conditional expressions (selects), not max(): numba's max() keeps a branch that stops
    # the loop vectoriser
    inv_r = 1.0 / np.sqrt(r2 if r2 > 1e-300 else 1e-300)
    return quintic_w_g_r(r2 * inv_r, inv_r, inv_s)


@njit(inline="always", cache=True)
def quintic_w_g_r(r, inv_r, inv_s):
    """:func:`quintic_w_g` from r and 1/r (a caller that shares the division with another
    quotient, as the drying kernel's XSPH 1/(rho_I + rho_J))."""
    x3 = 3.0 * (r * inv_s)
    a = 3.0 - x3
    b = 2.0 - x3
    c = 1.0 - x3
    a = a if a > 0.0 else 0.0
    b = b if b > 0.0 else 0.0
    c = c if c > 0.0 else 0.0
    a4 = a * a * a * a
    b4 = b * b * b * b
    c4 = c * c * c * c
    f = a4 * a - 6.0 * (b4 * b) + 15.0 * (c4 * c)
    d = a4 - 6.0 * b4 + 15.0 * c4
    norm = 63.0 / (478.0 * math.pi) * inv_s * inv_s
    return norm * f, (norm * inv_s) * (-15.0 * d) * inv_r


@njit(inline="always", cache=True)
def kernel_w_g(kind, r2, s, inv_s):
    """(W, (dW/dr)/r) in 2D from the squared distance r2 (both 0 for r >= s; g = 0 at r = 0):
    the branch-free quintic, the piecewise forms of the other kernels."""
    if kind == QUINTIC:
        return quintic_w_g(r2, inv_s)
    if r2 >= s * s or r2 <= 0.0:
        w0 = kernel_w(kind, 0.0, s, 2) if r2 <= 0.0 else 0.0
        return w0, 0.0
    r = np.sqrt(r2)
    w, dwdr = kernel_w(kind, r, s, 2), kernel_dwdr(kind, r, s, 2)
    return w, dwdr / r


@njit(cache=True)
def kernel_w_array(kind, r, s, dim):
    out = np.empty_like(r)
    for i in range(r.size):
        out.flat[i] = kernel_w(kind, r.flat[i], s, dim)
    return out


@njit(cache=True)
def kernel_dwdr_array(kind, r, s, dim):
    out = np.empty_like(r)
    for i in range(r.size):
        out.flat[i] = kernel_dwdr(kind, r.flat[i], s, dim)
    return out


def w(name: str, r, s: float, dim: int = 2) -> np.ndarray:
    """Vectorised W for Python callers (tests, analysis)."""
    return kernel_w_array(kernel_kind(name), np.asarray(r, dtype=np.float64), float(s), dim)


def dwdr(name: str, r, s: float, dim: int = 2) -> np.ndarray:
    return kernel_dwdr_array(kernel_kind(name), np.asarray(r, dtype=np.float64), float(s), dim)
