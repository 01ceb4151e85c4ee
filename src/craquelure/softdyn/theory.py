r"""Predicted T1 durations and crossover gap (spec sections 6-7), in units of R and tau.

* crossover gap (Eq. 30): :math:`h^* = R (\tilde F/k_n)^{2/3}` (Hertz deflection under F);
* Poiseuille (Eq. 33): :math:`T_P = c_n \tau \ln(h_1/h_0)`;
* Hertz (Eq. 34): :math:`T_H = (c_n/2)\tau (h^*/h_0)^2 [1 - (h_0/h_1)^2]`;
* general (quadrature): :math:`T_{sep} = \int_{h_0}^{h_1} c_n \eta a(h)^4/(F h^3)\, dh` with
  :math:`a^2 = R(h + \sigma)` and :math:`\sigma` solving :math:`k_n E a \sigma = F`, i.e. in reduced
  units :math:`k_n \sqrt{h + \sigma}\,\sigma = \tilde F`.
"""

import math

from scipy.integrate import quad
from scipy.optimize import brentq


def h_star(reduced_force: float, k_n: float) -> float:
    return (reduced_force / k_n) ** (2.0 / 3.0)


def t_poiseuille(h0: float, c_n: float, h1: float = 1.0) -> float:
    return c_n * math.log(h1 / h0)


def t_hertz(h0: float, reduced_force: float, k_n: float, c_n: float, h1: float = 1.0) -> float:
    hs = h_star(reduced_force, k_n)
    return 0.5 * c_n * (hs / h0) ** 2 * (1.0 - (h0 / h1) ** 2)


def steady_deflection(h: float, reduced_force: float, k_n: float) -> float:
    """|s| under a constant normal load: k_n sqrt(h + s) s = F~ (reduced units)."""
    fun = lambda s: k_n * math.sqrt(h + s) * s - reduced_force  # noqa: E731
    hi = max(h_star(reduced_force, k_n), reduced_force / (k_n * math.sqrt(h))) * 2.0 + 1e-300
    return brentq(fun, 0.0, hi, xtol=1e-16, rtol=1e-14)


def t_separation(h0: float, reduced_force: float, k_n: float, c_n: float, h1: float = 1.0) -> float:
    """Quadrature of the quasi-static opening time from h0 to h1 (units of tau). Raises
    ArithmeticError when the steady deflection under ``reduced_force`` cannot be solved (a
    force so large that k_n sqrt(h + s) s overflows), so callers report it as a number that
    cannot be computed."""
    def integrand(u):  # u = ln h
        h = math.exp(u)
        s = steady_deflection(h, reduced_force, k_n)
        return c_n * (h + s) ** 2 / h ** 2  # c_n a^4/h^3 dh with dh = h du
    try:
        value, _ = quad(integrand, math.log(h0), math.log(h1), epsabs=0.0, epsrel=1e-11, limit=400)
    except RuntimeError as exc:  # brentq: the deflection does not converge (|F~| overflows)
        raise ArithmeticError(f"T_sep quadrature at h0 = {h0:g} R, F~ = {reduced_force:g}: the "
                              f"steady deflection cannot be solved ({exc})") from exc
    return value


def regime(h0: float, reduced_force: float, k_n: float) -> str:
    """hertz (h0/h* <= 1/3), poiseuille (h0/h* >= 3) or crossover."""
    ratio = h0 / h_star(reduced_force, k_n)
    if ratio <= 1.0 / 3.0:
        return "hertz"
    return "poiseuille" if ratio >= 3.0 else "crossover"
