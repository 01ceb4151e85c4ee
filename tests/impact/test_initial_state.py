"""Checks 1 and 2 (spec section 10): kernel normalisation and the mass sampling."""

import math

import numpy as np
import pytest
from scipy import integrate, stats

from craquelure.impact.api import initial_state
from craquelure.impact.initial_state import build_specimen, grid, initial_smoothing_length
from craquelure.scene import load_scene
from craquelure.sph.kernels import CUBIC, kernel_w_array, w


@pytest.mark.parametrize("dim", [2, 3])
def test_cubic_kernel_has_unit_integral(dim):
    h = 1.3
    s = 2 * h
    shell = (lambda r: 2 * math.pi * r) if dim == 2 else (lambda r: 4 * math.pi * r * r)
    val, _ = integrate.quad(lambda r: w("cubic", np.array([r]), s, dim)[0] * shell(r), 0, s,
                            points=[h], epsabs=1e-14, epsrel=1e-13)
    assert val == pytest.approx(1.0, abs=1e-10)


def test_lattice_partition_of_unity_at_kappa_1():
    spacing = 1.0
    h = 1.2 * spacing
    ij = np.arange(-5, 6)
    gx, gy = np.meshgrid(ij, ij)
    r = np.hypot(gx, gy).ravel() * spacing
    total = kernel_w_array(CUBIC, r, 2 * h, 2).sum() * spacing**2
    assert total == pytest.approx(1.0, abs=1e-3)


def test_disc_has_1264_particles():
    x, _ = grid("disc", 40, 1, 0.004)
    assert x.size == 1264


SCENE = load_scene("impact/default")


@pytest.mark.parametrize("dist", ["uniform", "normal", "poisson"])
def test_masses_total_positive_mean_one_and_shape(dist):
    scene = SCENE.with_overrides([f"particles.masses.distribution={dist}"])
    homo = build_specimen(SCENE, 0)
    mbar = scene.get("material.rho0") * scene.get("particles.spacing") ** 2
    omegas = []
    for seed in range(20):
        sp = build_specimen(scene, seed)
        assert sp.mass.sum() == pytest.approx(homo.mass.sum(), rel=1e-12)
        assert (sp.mass >= 0).all()
        assert np.array_equal(sp.x, homo.x) and np.array_equal(sp.y, homo.y)
        omega = sp.mass / mbar
        assert omega.mean() == pytest.approx(1.0, rel=1e-12)
        omegas.append(omega)
        st = initial_state(scene, sp)
        assert (st.rho == scene.get("material.rho0")).all()
        assert st.h == pytest.approx(1.2 * 1.0 * 0.004, rel=1e-14)
    omega = np.concatenate(omegas)
    if dist == "uniform":
        p = stats.kstest(omega, stats.uniform(0, 2).cdf).pvalue
        # 0.5 % below 0.01 mbar (20 x 1264 draws: sd 0.044 %)
        assert np.mean(omega < 0.01) == pytest.approx(0.005, abs=0.002)
    elif dist == "normal":
        a = (0 - 1.0) / 0.3
        p = stats.kstest(omega, stats.truncnorm(a, np.inf, loc=1.0, scale=0.3).cdf).pvalue
    else:
        # m_i = k_i M / sum k: the smallest positive mass is k = 1 (P(k=1) = 7 %)
        k = np.concatenate([np.rint(o / o[o > 0].min()) for o in omegas]).astype(int)
        assert np.allclose(np.concatenate([o / o[o > 0].min() for o in omegas]), k, atol=1e-9)
        assert np.mean(k == 0) == pytest.approx(math.exp(-4.0), abs=0.004)
        counts = np.bincount(k, minlength=12)[:12]
        expected = stats.poisson(4.0).pmf(np.arange(12)) * k.size
        counts[-1] += (k >= 12).sum()
        expected[-1] += stats.poisson(4.0).sf(11) * k.size
        p = stats.chisquare(counts, expected * counts.sum() / expected.sum()).pvalue
    assert p > 0.01


@pytest.mark.parametrize("kappa", [0.7, 1.0, 1.5])
def test_initial_smoothing_length_is_kappa_1_2_spacing(kappa):
    scene = SCENE.with_overrides([f"numerics.kappa={kappa}"])
    assert initial_smoothing_length(scene) == pytest.approx(1.2 * kappa * 0.004)


@pytest.mark.parametrize("layout,expected_angle", [("pf1", 0.0), ("pf2", 30.0), ("pf3", 0.0)])
def test_precrack_layouts_are_zero_mass_lines(layout, expected_angle):
    from craquelure.impact.measure import principal_axis

    sp = build_specimen(SCENE.with_overrides([f"particles.precrack={layout}"]), 0)
    homo = build_specimen(SCENE, 0)
    assert (sp.mass[sp.precrack] == 0).all()
    assert np.array_equal(sp.mass[~sp.precrack], homo.mass[~sp.precrack])  # not renormalised
    extent, angle, _ = principal_axis(sp.x[sp.precrack], sp.y[sp.precrack])
    assert extent == pytest.approx(sp.radius, abs=2 * sp.spacing)  # length R
    assert angle == pytest.approx(expected_angle, abs=3.0)
    # one particle column wide: exactly one zero-mass particle in every grid row it spans
    rows, counts = np.unique(np.round(sp.y[sp.precrack] / sp.spacing), return_counts=True)
    assert (counts == 1).all()
    assert rows.size == pytest.approx(sp.radius * math.cos(math.radians(expected_angle))
                                      / sp.spacing, abs=1.01)
