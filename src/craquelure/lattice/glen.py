r"""Glen's-law melting-freezing test (lattice spec section 7, checks 8 and 9).

Set-up (scene ``lattice/glen``): block periodic in x, bottom row clamped, top row loaded by
:math:`\tau_{app}` along x and a confining :math:`p = 0.1\,\tau_{app}`. The top row's mean
displacement u(t) grows linearly after the transient; :math:`\dot\gamma = \dot u/H` (H: height
between bottom and top rows), :math:`D = \dot\gamma/2` and the spec's viscosity
:math:`\mu = t_D/D = 2\tau_{app}/\dot\gamma`. Glen (n = 3) predicts :math:`\mu\propto\tau^{-2}`.

Run length [D]: the melting rate is estimated before the run from the uniform-shear energy
per bond, :math:`U \approx (\tau^2/2\mu_L)(\sqrt3/2\,L^2)/3` (:math:`\mu_L` the lattice shear
modulus), :math:`\lambda \approx 2AE_b^2U/L^2` (or the frozen rate); the run lasts
``relaxations``/:math:`\lambda` and the rate is fitted over its last 3/5 (the first two
relaxation times are transient: the Maxwell time is ~0.7/:math:`\lambda` for this lattice).
"""

import math

import numpy as np

from craquelure.lattice import beam
from craquelure.lattice.initial_state import beam_constants
from craquelure.scene import Scene

RELAXATIONS = 5.0
FIT_FROM = 2.0 / 5.0


def melt_rate_estimate(scene: Scene, tau: float) -> float:
    if scene.get("melting.frozen_rate") > 0:
        return scene.get("melting.frozen_rate")
    c = beam_constants(scene)
    mu_lattice = beam.lattice_moduli(c.kn, c.ks)["mu"]
    u = tau**2 / (2 * mu_lattice) * beam.cell_area(c.L) / 3.0
    return 2.0 * scene.get("melting.rate_factor") * c.E_b**2 * u / c.L**2


def overrides(scene: Scene, tau: float, relaxations: float = RELAXATIONS) -> list[str]:
    """Scene overrides for one stress of the sweep (stress, confinement, run length)."""
    tau = float(tau)
    lam = melt_rate_estimate(scene, tau)
    t_end = float(relaxations / lam if lam > 0 else scene.get("outputs.t_end"))
    return [f"loads.top_shear_stress={tau!r}", f"loads.top_normal_stress={0.1 * tau!r}",
            f"outputs.t_end={t_end!r}", f"loads.ramp_time={min(0.05 * t_end, 20.0)!r}"]


def strain_rate(time: np.ndarray, ux: np.ndarray, height: float, fit_from: float = FIT_FROM
                ) -> dict[str, float]:
    """Shear rate from the top-row displacement series: fitted over t >= fit_from t_end;
    also the rates of the first and second halves of that window (steadiness)."""
    sel = time >= fit_from * time[-1]
    t, u = time[sel], ux[sel]
    rate = np.polyfit(t, u, 1)[0] / height
    half = t.size // 2
    r1 = np.polyfit(t[:half], u[:half], 1)[0] / height
    r2 = np.polyfit(t[half:], u[half:], 1)[0] / height
    return {"gamma_dot": float(rate), "gamma_dot_first": float(r1), "gamma_dot_second": float(r2)}


def viscosity(tau: float, gamma_dot: float) -> float:
    return 2.0 * tau / gamma_dot if gamma_dot > 0 else math.inf


def fit_power_law(x, y) -> tuple[float, float]:
    """(exponent b, prefactor a) of y = a x^b by least squares in log-log."""
    b, log_a = np.polyfit(np.log(x), np.log(y), 1)
    return float(b), float(np.exp(log_a))
