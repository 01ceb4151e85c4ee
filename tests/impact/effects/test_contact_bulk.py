"""Checks 9 and 10 (spec section 10): contact impulse and restitution with both stiffness
formulas (the bulk formula, ``contact_bulk``, against the mass-based one), zero-mass contact,
the kinematic constraint's energy balance. Small discs."""

import numpy as np
import pytest

from craquelure.impact.initial_state import build_specimen
from craquelure.scene import load_scene
from tests.impact.runs import simulate

ELASTIC = "[elasticity, artificial_viscosity, {contact}]"


def run(overrides, seed=0):
    scene = load_scene("impact/default", overrides)
    return simulate(scene, seed, progress=False)


ELASTIC_DISC = ["particles.diameter_cells=20", "particles.impact_velocity=1.0",
                "particles.gap=0.0", "outputs.t_end=1.6e-4", "outputs.series_dt=1.0e-6",
                "outputs.snapshot_times=[]"]


@pytest.fixture(scope="module")
def elastic_runs():
    """Check 9's elastic disc at 1 m/s: both formulas with ``contact_a: auto`` (the project's
    values), the bulk formula at the spec's a = 0.1 and 4x stiffer than auto."""
    out = {}
    for key, contact, a in (("contact_bulk", "contact_bulk", "auto"),
                            ("contact_mass", "contact_mass", "auto"),
                            ("contact_bulk_spec", "contact_bulk", 0.1),
                            ("contact_bulk_stiffer", "contact_bulk", 25.0)):
        out[key] = run([*ELASTIC_DISC, f"effects={ELASTIC.format(contact=contact)}",
                        f"numerics.contact_a={a}"])
    return out


@pytest.mark.slow
@pytest.mark.parametrize("contact", ["contact_bulk", "contact_mass", "contact_bulk_spec"])
def test_elastic_disc_impulse_restitution_energy(elastic_runs, contact):
    sp, eng, series, _ = elastic_runs[contact]
    mass = sp.mass.sum()
    v_in, v_out = -1.0, series["vcm_y"][-1]
    assert series["contact_force"][-1] == 0.0  # contact over
    assert eng.impulse == pytest.approx(mass * (v_out - v_in), rel=1e-2)
    assert eng.max_penetration < 0.2 * sp.spacing
    assert v_out / -v_in >= 0.8
    assert np.abs(series["balance_error"]).max() < 0.02


def peak(run) -> float:
    """Peak of the contact force history F(t) (impulse per 1 us sample, as in the datasets;
    the per-step penalty force also carries the springs' step-scale ringing)."""
    return float(run[2]["contact_force"].max())


@pytest.mark.slow
def test_peak_forces_of_both_formulas_agree(elastic_runs):
    """Check 9 with the project's scale factors (mass-based 0.1, bulk half-cell 6.27);
    measured 5.10e5 and 5.14e5 N/m."""
    assert elastic_runs["contact_bulk"][1].s.contact_a == pytest.approx(6.27, abs=0.01)
    assert elastic_runs["contact_mass"][1].s.contact_a == 0.1
    bulk, mass = peak(elastic_runs["contact_bulk"]), peak(elastic_runs["contact_mass"])
    assert abs(bulk - mass) / max(bulk, mass) < 0.25


@pytest.mark.slow
def test_bulk_peak_is_converged_in_the_penalty_stiffness(elastic_runs):
    """The reason for ``auto``: at the half-cell stiffness the peak no longer depends on the
    penalty, the disc's compliance sets it: 4x stiffer (a = 25) changes it by < 5 %
    (measured 1.2 %; the all-kinematic hard-contact limit, a >= 50, is 5.19e5 N/m)."""
    auto, stiffer = peak(elastic_runs["contact_bulk"]), peak(elastic_runs["contact_bulk_stiffer"])
    assert abs(stiffer - auto) / stiffer < 0.05


@pytest.mark.slow
def test_spec_bulk_penalty_peak_is_rigid_mass_on_springs(elastic_runs):
    """Why the spec's a = 0.1 fails check 9 (reported, not the project's value): the peak
    follows a rigid disc of mass M on the penalty springs of the N_c bottom-row particles,
    F = v sqrt(N_c k M) (= 2.69e5 N/m; measured 2.44e5: the disc's compliance lowers it 10 %),
    about half the mass-based peak (5.14e5 N/m)."""
    sp, eng, _, _ = elastic_runs["contact_bulk_spec"]
    n_c = int(np.sum(sp.y < sp.y.min() + 0.5 * sp.spacing))
    k = eng.prm[eng.k.P_K_BULK]
    rigid = 1.0 * np.sqrt(n_c * k * sp.mass.sum())
    assert eng.force_peak == pytest.approx(rigid, rel=0.15)
    assert eng.force_peak < rigid  # the disc's compliance is in series with the springs
    assert peak(elastic_runs["contact_bulk_spec"]) < 0.6 * peak(elastic_runs["contact_mass"])


ZERO_MASSES = ["particles.diameter_cells=20", "particles.masses.distribution=poisson",
               "particles.precrack=pf1", "outputs.t_end=1.5e-4", "outputs.snapshot_times=[]"]
FULL = ("[elasticity, plasticity, damage, artificial_viscosity, artificial_stress, "
        "variable_smoothing_length, {contact}]")


def bottom_zero_seed():
    """First seed whose Poisson-like masses put a zero mass in the bottom row (the particles
    that reach the base; PF#1's line ends R/2 above the contact)."""
    scene = load_scene("impact/default", ZERO_MASSES)
    for seed in range(100):
        sp = build_specimen(scene, seed)
        if ((sp.mass == 0) & (sp.y <= sp.y.min() + 0.5 * sp.spacing)).any():
            return seed
    raise AssertionError("no seed with a zero mass in the bottom row")


def test_zero_masses_safe_with_bulk_contact():
    sp, eng, _, _ = run([*ZERO_MASSES, f"effects={FULL.format(contact='contact_bulk')}"],
                        bottom_zero_seed())
    st = eng.state
    # PF#1 one particle column (10 on the 20-cell disc) + the Poisson-like zeros (1.8 %)
    assert (sp.mass == 0).sum() > 12
    assert np.isfinite(st.x).all() and np.isfinite(st.y).all() and np.isfinite(st.sig).all()
    assert st.y.min() >= 0.5 * sp.spacing - 0.5 * sp.spacing  # r_c - 0.5 Delta


@pytest.mark.parametrize("kappa", [1.0, 1.5])
def test_kinematic_constraint_keeps_the_energy_balance(kappa):
    """Uniform masses with the half-cell stiffness leave the lightest 10-25 % of the particles
    (m < 4 k dt^2) to the kinematic constraint. It must act on the mid-step velocity too
    (else the material pass and the drift see a motion into the base that the floor undoes:
    35 % balance error), and only a particle's arrival removes energy: the base's reaction to
    the kick's pull does no work (logging ½ m (a dt/2)^2 per kick made 1.8 % at kappa = 1.5;
    now 0.3 %). 1 % is the bound the workflow's runs meet with any penalty stiffness."""
    sp, eng, series, _ = run(["particles.diameter_cells=20",
                              "particles.masses.distribution=uniform", "outputs.t_end=4.0e-4",
                              "outputs.snapshot_times=[]", f"numerics.kappa={kappa}"], seed=0)
    assert eng.impulse_kin > 0.02 * eng.impulse  # the constraint has done real work
    assert np.abs(series["balance_error"]).max() < 0.01
