r"""Why rkc2's step cap dt_max = 0.2 stays (issue 28, item 3). Prints the two properties a
drying run needs at a step dt above the cap, for rkc2 and for a splitting that takes the
substrate spring -(mu/H^2) u out of the Chebyshev stages:

1. **Undamped grid-scale modes** (velocity patterns the kernel gradient does not see: a
   particle's own oscillator u'' = -omega0^2 u, omega0 = 1.0007) sit at z = i y,
   y = omega0 dt. A scheme must keep |R(i y)| <= 1 there, at the stage count s the viscous
   spectrum asks for at that dt (s = 1 + floor(sqrt(1 + 1.54 dt rho)), rho = 1.2 x 168).
   rkc2 (:mod:`craquelure.drying.integrators`) has |R_s(i y)| = 1 + 0.035 y^4: such a mode
   grows at ln|R_s(i y)|/dt per time unit (printed).
2. **The quasi-static balance** grad.sigma = (mu/H^2) u of a viscously overdamped mode: the
   linear model u' = v, v' = -gamma v - omega0^2 u + a t (gamma = 200: viscous rate; a t: the
   slowly growing drying load), integrated to t = 50 with Strang splitting (exact spring
   half-steps around an rkc2 step of the rest) and with rkc2 on the whole; relative error of u
   against a Radau solution at rtol 1e-11.

    python benchmarks/drying_spring_schemes.py
"""

from __future__ import annotations

import math

import numpy as np
from scipy.integrate import solve_ivp
from scipy.linalg import expm

from craquelure.drying.integrators import rkc2_step, rkc_stability, rkc_stages

OMEGA0 = 1.0007
RHO = 1.2 * 168.0  # safety-scaled viscous spectral radius of the paste (spec section 8)


def overdamped_errors(dt: float, gamma: float = 200.0, load: float = 1e-3, t_end: float = 50.0):
    spring = np.array([[0.0, 1.0], [-OMEGA0**2, 0.0]])

    def rest(y, t):
        return np.array([0.0, -gamma * y[1] + load * t])

    def whole(y, t):
        return spring @ y + rest(y, t)

    ref = solve_ivp(lambda t, y: whole(y, t), (0, t_end), [0.0, 0.0], method="Radau",
                    rtol=1e-11, atol=1e-14).y[0, -1]
    steps, s = int(round(t_end / dt)), rkc_stages(dt, 1.2 * gamma)
    half = expm(spring * dt / 2)
    plain, split, t = np.zeros(2), np.zeros(2), 0.0
    for _ in range(steps):
        plain = rkc2_step(plain, whole(plain, t), t, dt, whole, s)
        split = half @ split
        split = half @ rkc2_step(split, rest(split, t), t, dt, rest, s)
        t += dt
    return abs(plain[0] - ref) / ref, abs(split[0] - ref) / ref


def main() -> None:
    print("1. |R(i y)| on the undamped grid-scale modes, y = omega0 dt, s from the viscous "
          "spectrum at dt")
    print(f"{'dt':>5} {'s':>3} {'evals/time':>10} {'rkc2':>8} {'growth/time':>11}")
    for dt in (0.2, 0.3, 0.5, 0.8, 1.0, 2.0):
        s = rkc_stages(dt, RHO)
        y = OMEGA0 * dt
        rkc = abs(complex(rkc_stability(1j * y, s)))
        print(f"{dt:5.2f} {s:3d} {s / dt:10.1f} {rkc:8.5f} {math.log(rkc) / dt:11.2e}")
    print("2. relative error of u at t = 50 on the overdamped model (quasi-static balance)")
    print(f"{'dt':>5} {'rkc2 whole':>11} {'Strang':>8}")
    for dt in (0.05, 0.2, 0.5, 1.0):
        plain, split = overdamped_errors(dt)
        print(f"{dt:5.2f} {plain:11.2e} {split:8.2f}")

if __name__ == "__main__":
    main()
