r"""Scenarios: the T1 of four spheres (spec section 6) and two-sphere approach/separation/sliding
(companion paper), from a validated scene, plus their time-series datasets.

T1 [S unless tagged]: d = 2R + h0, A = (-d/2, 0), B = (d/2, 0), C = (0, sqrt3 d/2),
D = (0, -sqrt3 d/2); all six pairs in a fixed list with zero initial deflection [D]; C pushed down
and D up by F_v, A and B pushed toward each other by F_h. The scene gives the reduced AB load
F~ = |F_v/sqrt3 - F_h|/(E R^2) and r = F_h/F_v, so F_v = F~ E R^2/|1/sqrt3 - r| [D] and
tau = eta R^2/F with F = F~ E R^2 (for r = 0: tau = sqrt3 eta R^2/F_v, spec Eq. 29). theta is the
angle between AC and AB. ``numerics.mirror_symmetry`` (default on) [D]: the rates are projected
on the two mirror symmetries of the rhombus (x -> -x swapping A and B, y -> -y swapping C and D;
the spec's T1 is symmetric, check 9). Without it the blocked rhombus is unstable to a rigid
rotation grown from round-off (both load pairs are compressive and fixed in direction, and the
tangential springs relax through the sliding films) until the sgn(s) kink of a(h, s) stalls the
stiff solvers. The T1 ends when the CD normal force reaches phi (F_v - F_h/sqrt3)
(``stop: cd_force``) or when theta <= theta_end (``stop: angle``).

Pair: spheres 0 and 1 on the x axis at distance 2R + h0, loaded by F = F~ E R^2 toward each other
(compression) or apart (tension), optionally with a tangential couple T (y) for sliding.
"""

import math
from dataclasses import dataclass

import numpy as np
import xarray as xr

from craquelure.errors import SceneError
from craquelure.registry import parameter_vector
from craquelure.softdyn import theory
from craquelure.softdyn.effects.hertz import interaction_radius2
from craquelure.softdyn.engine import Engine, flags_for
from craquelure.softdyn.integrate import Result
from craquelure.softdyn.kernel_template import PARAMS

SQRT3 = math.sqrt(3.0)
T1_PARTICLES = ("A", "B", "C", "D")
T1_PAIRS = ((0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3))
T1_PAIR_NAMES = ("AB", "AC", "AD", "BC", "BD", "CD")

def material_constants(scene) -> dict[str, float]:
    """E, k_n, k_t and c_t of a scene as the kernel reads them: each effect's own when it is on,
    the neutral value its declaration gives when it is off; E, the force unit F = F~ E R^2,
    whenever the scene gives it (:func:`craquelure.registry.parameter_vector`)."""
    p = dict(zip(PARAMS, parameter_vector("softdyn", scene, {"inv_tau_B": 0.0, "t_r": 0.0}),
                 strict=True))
    return {"young": p["E"], "k_n": p["k_n"], "k_t": p["k_t"], "c_t": p["c_t"]}


@dataclass
class Setup:
    """A system with its scales: force unit F, time unit tau, F_v (T1) and the stop function."""

    scene: object
    system: Engine
    force: float          # F = F~ E R^2
    tau: float            # eta R^2 / F
    f_v: float            # T1: vertical load; pair: F
    f_h: float
    h0: float             # units of R

    @property
    def arrangement(self) -> str:
        return self.scene.get("particles.arrangement")

    def stop_function(self):
        kind = self.scene.get("outputs.stop")
        if kind == "none":
            return None
        sysm = self.system
        if kind in ("cd_force", "angle") and self.arrangement != "t1":
            raise SceneError(f"outputs.stop: {kind!r} needs particles.arrangement: t1")
        if kind == "cd_force":
            target = self.scene.get("outputs.phi") * (self.f_v - self.f_h / SQRT3)
            return lambda t, y: self.pair_normal_force(t, y, 5) / target - 1.0
        if kind == "angle":
            theta_end = math.radians(self.scene.get("outputs.theta_end_deg"))
            return lambda t, y: theta_end - t1_angle(sysm.unpack(y)[0])
        gap_end = self.scene.optional("outputs.gap_end")
        if gap_end is None:
            raise SceneError("outputs.gap_end: required with stop: gap")
        sign = 1.0 if self.scene.get("loads.direction") == "tension" else -1.0
        radius = sysm.radius
        return lambda t, y: sign * (sysm.min_gap(y) - gap_end * radius)

    def pair_normal_force(self, t: float, y: np.ndarray, k: int) -> float:
        sysm = self.system
        if sysm.flags.hertz:
            x, s, _ = sysm.unpack(y)
            i, j = sysm.pairs[k]
            r = float(np.linalg.norm(x[i] - x[j]))
            h = r - 2.0 * sysm.radius + s[k]
            a = math.sqrt(interaction_radius2(sysm.radius, h, float(s[k])))
            return sysm.young * a * sysm.k_n * float(s[k])
        return float(sysm.evaluate(t, y)["f_n"][k])


def t1_angle(x: np.ndarray) -> float:
    """Angle (rad) between AC and AB."""
    ab, ac = x[1] - x[0], x[2] - x[0]
    cross = ab[0] * ac[1] - ab[1] * ac[0]
    if x.shape[1] == 3:
        cross = float(np.linalg.norm(np.cross(ab, ac)))
    return math.atan2(abs(cross), float(ab @ ac))


def build(scene) -> Setup:
    """The system and scales of a scene (T1 or pair)."""
    flags = flags_for(scene)
    radius = scene.get("material.radius")
    eta = scene.get("material.viscosity")
    constants = material_constants(scene)
    young, k_n, k_t, c_t = (constants[k] for k in ("young", "k_n", "k_t", "c_t"))
    c_n = scene.get("material.c_n")
    dim = scene.get("domain.dim")
    h0 = scene.get("particles.h0")
    force = scene.get("loads.reduced_force") * young * radius**2
    tau = eta * radius**2 / force
    symmetry = ()
    d = (2.0 + h0) * radius
    if scene.get("particles.arrangement") == "t1":
        r = scene.get("loads.fh_over_fv")
        if abs(1.0 / SQRT3 - r) < 1e-6:
            raise SceneError("loads.fh_over_fv: 1/sqrt(3) makes the AB load vanish; tau is "
                             "undefined (choose a value on either side)")
        f_v = force / abs(1.0 / SQRT3 - r)
        f_h = r * f_v
        x0 = np.array([[-d / 2, 0.0], [d / 2, 0.0], [0.0, SQRT3 * d / 2], [0.0, -SQRT3 * d / 2]])
        F0 = np.array([[f_h, 0.0], [-f_h, 0.0], [0.0, -f_v], [0.0, f_v]])
        pairs, pnames, names = np.array(T1_PAIRS), T1_PAIR_NAMES, T1_PARTICLES
        if scene.get("numerics.mirror_symmetry"):
            # mirror x -> -x swaps A and B, mirror y -> -y swaps C and D
            symmetry = (((1, 0, 2, 3), (-1.0, 1.0, 1.0)), ((0, 1, 3, 2), (1.0, -1.0, 1.0)))
    else:
        f_v, f_h = force, 0.0
        sign = 1.0 if scene.get("loads.direction") == "compression" else -1.0
        tang = scene.get("loads.tangential_over_normal") * force
        x0 = np.array([[-d / 2, 0.0], [d / 2, 0.0]])
        F0 = np.array([[sign * force, tang], [-sign * force, -tang]])
        pairs, pnames, names = np.array([(0, 1)]), ("01",), ("0", "1")
    symmetry = tuple((perm, signs[:dim]) for perm, signs in symmetry)
    if dim == 3:
        x0 = np.hstack([x0, np.zeros((x0.shape[0], 1))])
        F0 = np.hstack([F0, np.zeros((F0.shape[0], 1))])
    system = Engine(
        x0=x0, pairs=pairs, F0=F0, radius=radius, viscosity=eta, young=young, k_n=k_n,
        k_t=k_t, c_n=c_n, c_t=c_t, tau_baumgarte=scene.get("numerics.baumgarte_time") * tau,
        ramp_time=scene.get("loads.ramp_time") * tau, flags=flags,
        linear_solver=scene.get("numerics.linear_solver"), pair_names=pnames,
        particle_names=names, symmetry=symmetry)
    return Setup(scene=scene, system=system, force=force, tau=tau, f_v=f_v, f_h=f_h, h0=h0)


def predictions(scene) -> dict[str, float]:
    """h*, h0/h*, T_P, T_H and the quadrature T_sep (units of R and tau)."""
    ft = scene.get("loads.reduced_force")
    k_n, c_n, h0 = material_constants(scene)["k_n"], scene.get("material.c_n"), \
        scene.get("particles.h0")
    hs = theory.h_star(ft, k_n)
    return {"h_star": hs, "h0_over_h_star": h0 / hs, "T_P": theory.t_poiseuille(h0, c_n),
            "T_H": theory.t_hertz(h0, ft, k_n, c_n),
            "T_sep": theory.t_separation(h0, ft, k_n, c_n) if h0 < 1.0 else 0.0,
            "regime": theory.regime(h0, ft, k_n)}


def series_dataset(setup: Setup, result: Result) -> xr.Dataset:
    """Time series of a run: positions, gaps, deflections, forces, frictions, angle."""
    sysm, tau = setup.system, setup.tau
    rows = [sysm.evaluate(t, y) for t, y in zip(result.t, result.y, strict=True)]
    dims = ("x", "y", "z")[: sysm.d]

    def stack(key):
        return np.array([row[key] for row in rows])

    # variables without attributes: long names and units from craquelure.cf's table on writing
    ds = xr.Dataset({
        "position": (("time", "particle", "dim"), stack("x") / sysm.radius),
        "velocity": (("time", "particle", "dim"), stack("v") * tau / sysm.radius),
        "gap": (("time", "pair"), stack("h") / sysm.radius),
        "deflection_normal": (("time", "pair"), stack("s") / sysm.radius,
                              {"units": "R", "long_name": "s (> 0: compression)"}),
        "interaction_radius": (("time", "pair"), stack("a") / sysm.radius),
        "force_normal": (("time", "pair"), stack("f_n") / setup.f_v,
                         {"units": "F_v", "long_name": "f_ij . n (> 0: compressive)"}),
        "force_tangential": (("time", "pair"), np.linalg.norm(stack("f_t"), axis=-1) / setup.f_v),
        "zeta_n": (("time", "pair"), stack("zeta_n") / (sysm.viscosity * sysm.radius)),
        "zeta_t": (("time", "pair"), stack("zeta_t") / (sysm.viscosity * sysm.radius)),
        "balance_residual": ("time", np.abs(stack("residual")).max(axis=(1, 2)) / setup.f_v,
                             {"units": "F_v", "long_name": "max_i |F_i + sum_j f_ij|"})},
        coords={"time": result.t / tau, "particle": list(sysm.particle_names),
                "pair": list(sysm.pair_names), "dim": list(dims)})
    if setup.arrangement == "t1":
        ds["theta"] = ("time", np.degrees([t1_angle(row["x"]) for row in rows]))
    ds.attrs.update(run_attrs(setup, result))
    return ds


def run_attrs(setup: Setup, result: Result) -> dict[str, object]:
    sc = setup.scene
    return {
        "tau": setup.tau, "force_unit": setup.force, "F_v": setup.f_v, "F_h": setup.f_h,
        "h0": setup.h0, "reduced_force": sc.get("loads.reduced_force"),
        **predictions(sc), "stop": sc.get("outputs.stop"),
        "stopped": int(result.stopped), "duration": result.t_stop / setup.tau,
        "integrator": sc.get("numerics.integrator"), "n_steps": result.n_steps,
        "n_rhs": result.n_rhs, "n_rejected": result.n_rejected,
        "integration_wall_time_s": result.wall_time_s, "linear_solver": setup.system.solver,
        "deflection_rule": sc.get("numerics.deflection_rule")}
