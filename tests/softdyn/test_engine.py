"""Pair kinematics, friction tensors, elastic response and the velocity system (spec checks 1, 2,
3, 6); the effect specialisation and the sparse path are in test_kernel_template.py."""

import math

import numpy as np
import pytest

from craquelure.errors import SceneError
from craquelure.scene import load_scene, load_scene_text
from craquelure.softdyn.engine import run
from craquelure.softdyn.initial_state import build
from craquelure.softdyn.kernel_template import PARAMS

C_N, C_T = 1.5 * math.pi, math.pi


def t1_setup(*overrides):
    return build(load_scene("softdyn/t1_single", list(overrides)))


def random_t1_state(setup, rng, s_scale=3e-3):
    """T1 positions jiggled by 1e-4 R, deflections of both signs, q perpendicular to n."""
    sysm = setup.system
    y = sysm.initial_state()
    n, d, npair = sysm.n, sysm.d, sysm.n_pairs
    y[: n * d] += 1e-4 * rng.standard_normal(n * d)
    x = sysm.unpack(y)[0]
    if sysm.flags.hertz:
        y[n * d: n * d + npair] = s_scale * rng.uniform(-0.3, 1.0, npair)
        if sysm.flags.tangential:
            q = 1e-3 * rng.standard_normal((npair, d))
            for k, (i, j) in enumerate(sysm.pairs):
                nv = (x[i] - x[j]) / np.linalg.norm(x[i] - x[j])
                q[k] -= (q[k] @ nv) * nv
            y[n * d + npair:] = q.ravel()
    return y


def fdot_direct(xi, xj, s, q, vij, p, literal):
    """df_ij/dt straight from the kinematics (spec sections 2-5), not from the closed forms."""
    R, eta, E, kn, kt, cn, ct = (p[PARAMS.index(k)]
                                 for k in ("R", "eta", "E", "k_n", "k_t", "c_n", "c_t"))
    rv = xi - xj
    r = np.linalg.norm(rv)
    n = rv / r
    Q = np.eye(n.size) - np.outer(n, n)
    h = r - 2 * R + s
    a = math.sqrt(R * (h + abs(s)))
    zn, zt = cn * eta * a**4 / h**3, ct * eta * a**2 / h
    fn, ft = E * a * kn * s, E * a * kt * q
    w = -vij - (fn / zn) * n - ft / zt            # pair balance
    ndot = Q @ vij / r
    sdot = n @ w + (ndot @ q if literal else 0.0)
    qdot = Q @ w - n * (ndot @ q) - (s * ndot if literal else 0.0)
    hdot = n @ vij + sdot
    adot = R * (hdot + np.sign(s) * sdot) / (2 * a)
    g = kn * s * n + kt * q
    gdot = kn * sdot * n + kn * s * ndot + kt * qdot
    return E * adot * g + E * a * gdot


def elastic_force(xi, xj, s, q, p):
    R, E, kn, kt = (p[PARAMS.index(k)] for k in ("R", "E", "k_n", "k_t"))
    r = np.linalg.norm(xi - xj)
    n = (xi - xj) / r
    a = math.sqrt(R * (r - 2 * R + s + abs(s)))
    return E * a * (kn * s * n + kt * q)


@pytest.mark.parametrize("rule", ["corotating", "literal"])
def test_closed_forms_match_direct_evaluation(rule):
    """Check 3: A_ij, b_ij equal the affine evaluation of df_ij/dt to 1e-10 relative."""
    rng = np.random.default_rng(3)
    setup = t1_setup(f"numerics.deflection_rule={rule}")
    sysm = setup.system
    for _ in range(5):
        y = random_t1_state(setup, rng)
        ev = sysm.evaluate(0.05 * setup.tau, y)
        for k, (i, j) in enumerate(sysm.pairs):
            args = (ev["x"][i], ev["x"][j], ev["s"][k], ev["q"][k])
            b = fdot_direct(*args, np.zeros(2), sysm.p, rule == "literal")
            A = np.column_stack([fdot_direct(*args, e, sysm.p, rule == "literal") - b
                                 for e in np.eye(2)])
            scale = np.abs(ev["A"][k]).max()
            assert np.abs(ev["A"][k] - A).max() <= 1e-10 * scale
            assert np.abs(ev["b"][k] - b).max() <= 1e-10 * max(np.abs(b).max(), 1e-300)


def test_direct_evaluation_matches_finite_differences():
    """The reference df/dt itself is the derivative of f along the motion (central differences,
    Richardson-extrapolated: agreement to 1e-7 relative)."""
    rng = np.random.default_rng(4)
    setup = t1_setup()
    sysm = setup.system
    y = random_t1_state(setup, rng)
    t = 0.05 * setup.tau
    ev = sysm.evaluate(t, y)
    ydot = ev["ydot"]

    def forces(yy):
        x, s, q = sysm.unpack(yy)
        return np.array([elastic_force(x[i], x[j], s[k], q[k], sysm.p)
                         for k, (i, j) in enumerate(sysm.pairs)])

    def central(eps):
        return (forces(y + eps * ydot) - forces(y - eps * ydot)) / (2 * eps)

    eps = 1e-3 * setup.tau * 1e-2
    fd = (4 * central(eps / 2) - central(eps)) / 3
    v = ev["v"]
    direct = np.array([fdot_direct(ev["x"][i], ev["x"][j], ev["s"][k], ev["q"][k],
                                   v[i] - v[j], sysm.p, False)
                       for k, (i, j) in enumerate(sysm.pairs)])
    assert np.abs(fd - direct).max() <= 1e-7 * np.abs(direct).max()


@pytest.mark.parametrize("effects", [
    "[lubrication_normal, lubrication_tangential, hertz]",
    "[lubrication_normal, hertz]",
    "[lubrication_normal, lubrication_tangential]",
])
def test_gap_law_and_zero_mean_velocity(effects):
    """Check 1: dh/dt = -f_n/zeta_n for every pair to round-off, whatever the velocities;
    check 2 (instantaneous part): sum_i v_i = 0 and sum_i F_i = 0."""
    rng = np.random.default_rng(5)
    setup = t1_setup(f"effects={effects}")
    sysm = setup.system
    for t in (0.05 * setup.tau, 3.0 * setup.tau):
        y = random_t1_state(setup, rng)
        ev = sysm.evaluate(t, y)
        v = ev["v"]
        if sysm.flags.hertz:
            sdot = ev["ydot"][sysm.n * sysm.d: sysm.n * sysm.d + sysm.n_pairs]
        else:
            sdot = np.zeros(sysm.n_pairs)
        for k, (i, j) in enumerate(sysm.pairs):
            hdot = ev["n"][k] @ (v[i] - v[j]) + sdot[k]
            law = -ev["f_n"][k] / ev["zeta_n"][k]
            assert abs(hdot - law) <= 1e-12 * max(abs(law), np.abs(v).max())
        assert np.abs(v.sum(axis=0)).max() <= 1e-13 * np.abs(v).max()
        assert np.abs(ev["load"].sum(axis=0)).max() <= 1e-15 * setup.f_v


def test_velocities_enforce_the_balance_with_baumgarte_rate():
    """The velocity system makes d/dt (F_i + sum_j f_ij) = -(F_i + sum_j f_ij)/tau_B."""
    rng = np.random.default_rng(7)
    setup = t1_setup()
    sysm = setup.system
    y = random_t1_state(setup, rng)
    t = 3.0 * setup.tau  # after the ramp: dF/dt = 0
    ev = sysm.evaluate(t, y)
    eps = 1e-6 * setup.tau

    def resid(sign):
        return sysm.evaluate(t + sign * eps, y + sign * eps * ev["ydot"])["residual"]

    rate = (resid(1) - resid(-1)) / (2 * eps)
    target = -ev["residual"] / (setup.scene.get("numerics.baumgarte_time") * setup.tau)
    assert np.abs(rate - target).max() <= 1e-5 * np.abs(target).max()


def test_scene_errors():
    with pytest.raises(SceneError, match="lubrication_normal"):
        t1_setup("effects=[hertz, lubrication_tangential]")
    with pytest.raises(SceneError, match="literal"):
        t1_setup("effects=[lubrication_normal, hertz]", "numerics.deflection_rule=literal")
    text = load_scene("softdyn/t1_single").source_text.replace("  young: 1.0\n", "")
    with pytest.raises(SceneError, match="needs material.young"):
        load_scene_text(text)
    with pytest.raises(SceneError, match="unknown effect"):
        load_scene("softdyn/t1_single", ["effects=[lubrication_normal, gravity]"])
    with pytest.raises(SceneError, match="1/sqrt"):
        t1_setup(f"loads.fh_over_fv={1 / math.sqrt(3)!r}")


def test_three_dimensional_vectors_give_the_planar_result():
    """Spheres in a plane: d = 3 vectors reproduce the d = 2 run (opening time of a pair)."""
    out = []
    for dim in (2, 3):
        setup = build(load_scene("softdyn/two_sphere_separation", [f"domain.dim={dim}"]))
        res = run(setup, sample_times_tau=np.array([]))
        out.append(res.t_stop / setup.tau)
    assert out[1] == pytest.approx(out[0], rel=1e-7)
