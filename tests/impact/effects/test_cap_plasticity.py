"""The CSCM-like concrete (impact spec section 2 item 5) at a material point, strain-driven:
triaxial compression on the compression meridian, the uniaxial strengths and G_F of check 6 with
the cap model, the compressive damage's energy and the CSCM-form rate enhancement."""

import math

import numpy as np
import pytest

from craquelure.impact.effects.cap_plasticity import murray_fits
from craquelure.impact.material import drive, standard_concrete

MAT = standard_concrete(band=0.008)  # l_c = 2 Delta, the default at kappa = 1
CAP = MAT.cap


def test_constants_are_murrays_fits_at_43_1_mpa():
    m = murray_fits(43.1e6)
    assert m["alpha"] / 1e6 == pytest.approx(15.79, abs=0.01)
    assert m["theta"] == pytest.approx(0.340, abs=1e-3)
    assert m["kappa0"] / 1e6 == pytest.approx(97.98, abs=0.01)
    # alpha through the uniaxial point, e through Kupfer's equibiaxial point
    assert CAP.alpha / 1e6 == pytest.approx(14.80, abs=0.01)
    assert CAP.e == pytest.approx(0.611, abs=1e-3)
    assert CAP.X0 / 1e6 == pytest.approx(330.6, abs=0.1)


def triaxial(confinement: float, strain: float = 0.05, n: int = 1500, **kw):
    """Hydrostatic loading to the confinement, then axial (yy) shortening at constant lateral
    stress; returns (peak deviator q, I1' at the peak, axial strain at the peak)."""
    n1 = 60
    path = np.zeros((n1 + n, 4))
    path[:n1, 1] = np.linspace(0.0, -confinement / (3 * MAT.bulk), n1)
    path[n1:, 1] = path[n1 - 1, 1] - np.linspace(0.0, strain, n)
    lateral = np.zeros((n1 + n, 2))
    lateral[:n1] = -confinement * np.linspace(0.0, 1.0, n1)[:, None]
    lateral[n1:] = -confinement
    eps, sig = drive(MAT, path, free=("xx", "zz"), plastic="cap", targets=lateral, **kw)
    assert sig[n1:, [0, 2 + 1]] == pytest.approx(-confinement, rel=1e-6, abs=1.0)
    q = sig[:, 0] - sig[:, 1]
    i = int(np.argmax(q))
    return q[i], -(sig[i, 0] + sig[i, 1] + sig[i, 3]), eps[i, 1]


@pytest.mark.parametrize("confinement", [0.0, 25e6, 50e6, 100e6])
def test_triaxial_compression_peak_on_the_meridian(confinement):
    q, i1, _ = triaxial(confinement, compressive=True)
    meridian = math.sqrt(3.0) * float(CAP.F_f(i1))
    assert q == pytest.approx(meridian, rel=0.05)
    assert i1 == pytest.approx(3 * confinement + q, rel=1e-6)


def test_high_confinement_needs_the_cap_to_harden():
    # at 100 MPa the meridian lies at I1' = 792 MPa, beyond the initial cap X0 = 331 MPa: the
    # peak is reached only after compaction has moved the cap (a stiff, non-hardening cap would
    # stop q at X0 - 300 MPa = 31 MPa)
    q, i1, strain = triaxial(100e6)
    assert i1 > 2 * CAP.X0
    assert -strain > 0.01


def test_uniaxial_compression_f_c_then_crushing_energy():
    n = 6000
    path = np.zeros((n, 4))
    path[:, 1] = np.linspace(0.0, -1.1 * MAT.eps_fc, n)
    eps, sig = drive(MAT, path, free=("xx", "zz"), plastic="cap", compressive=True)
    assert -sig[:, 1].min() == pytest.approx(MAT.f_c, rel=1e-2)
    # plastic work after the peak x l_c = G_fc = 100 G_F
    peak = int(np.argmin(sig[:, 1]))
    post = np.trapezoid(-sig[peak:, 1], -eps[peak:, 1]) * MAT.band
    residual = -sig[-1, 1]
    assert residual < 0.02 * MAT.f_c
    elastic_return = 0.5 * MAT.f_c**2 / MAT.young * MAT.band
    assert post + elastic_return == pytest.approx(100 * MAT.G_F, rel=0.03)


def test_equibiaxial_compression_1_16_f_c():
    path = np.zeros((400, 4))
    path[:, 0] = path[:, 1] = np.linspace(0.0, -6e-3, 400)
    _, sig = drive(MAT, path, free=("zz",), plastic="cap")
    assert -sig[:, 1].min() == pytest.approx(1.16 * MAT.f_c, rel=1e-2)


def tension(rate: float | None, n: int = 4000, **kw):
    dif = 1.0 if rate is None else 7.0
    strain = np.concatenate([np.linspace(0, 2 * dif * MAT.kappa0, n // 2),
                             np.linspace(2 * dif * MAT.kappa0, 1.05 * dif * MAT.kappa_f,
                                         n // 2)[1:]])
    path = np.zeros((strain.size, 4))
    path[:, 1] = strain
    dt = 1.0 if rate is None else (strain[1] - strain[0]) / rate
    if rate is not None:
        # constant rate: equal steps throughout
        path[:, 1] = np.arange(strain.size) * (strain[1] - strain[0])
    return drive(MAT, path, free=("xx", "zz"), plastic="cap", compressive=True,
                 rate=rate is not None, dt=dt, **kw)


def test_uniaxial_tension_f_t_and_G_F_with_the_cap_model():
    eps, sig = tension(None)
    assert sig[:, 1].max() == pytest.approx(MAT.f_t, rel=1e-2)
    assert np.trapezoid(sig[:, 1], eps[:, 1]) * MAT.band == pytest.approx(MAT.G_F, rel=1e-2)


@pytest.mark.parametrize(("rate", "dif"), [(1.0, 1.5), (10.0, 2.6), (100.0, 6.1)])
def test_tensile_dynamic_increase_factor(rate, dif):
    _, sig = tension(rate, n=3000)
    assert sig[:, 1].max() / MAT.f_t == pytest.approx(dif, rel=0.10)


def test_compressive_dynamic_increase_factor():
    # CSCM's overstress at a steady rate: 1 + E eta_0c rate^(1 - n_c) / f_c with Murray's
    # eta_0c = 3.16e-4, n_c = 0.78: 1.22 / 1.36 / 1.60 at 1 / 10 / 100 1/s (no compressive damage:
    # the plateau is the inviscid f_c)
    for rate, dif in ((1.0, 1.22), (10.0, 1.36), (100.0, 1.60)):
        n, step = 4000, 1e-5
        path = np.zeros((n, 4))
        path[:, 1] = -np.arange(n) * step
        _, sig = drive(MAT, path, free=("xx", "zz"), plastic="cap", rate=True, dt=step / rate)
        assert -sig[:, 1].min() / MAT.f_c == pytest.approx(dif, rel=0.03)
