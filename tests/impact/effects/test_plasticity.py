"""The plastic returns (Drucker-Prager cone; the cap model's return beside it) are objective:
returning a rotated trial stress gives the rotated return."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from craquelure.impact.effects.cap_plasticity import cap_return
from craquelure.impact.effects.plasticity import dp_return
from craquelure.impact.material import standard_concrete

from .tensors import matrix, random_stress, rotate

MAT = standard_concrete()


@pytest.mark.parametrize("seed", range(4))
def test_plastic_returns_are_objective(seed):
    """Drucker-Prager and the cap model depend on I1, J2 (and J3 for the cap's Lode angle):
    returning a rotated trial stress gives the rotated return, and the same plastic strain."""
    rng = np.random.default_rng(20 + seed)
    q = Rotation.random(random_state=20 + seed).as_matrix()
    s = random_stress(rng, -150e6, 5e6)
    alpha, k = MAT.dp
    a, deps_a, _ = dp_return(s, alpha, k, MAT.shear)
    b, deps_b, _ = dp_return(rotate(s, q), alpha, k, MAT.shear)
    assert deps_b == pytest.approx(deps_a, rel=1e-9, abs=1e-15)
    assert np.allclose(matrix(b), q @ matrix(a) @ q.T, atol=1e-9 * np.abs(s).max())
    c = MAT.cap_vector()
    args = (0.0, c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7], c[8], c[20], c[21], MAT.bulk,
            MAT.shear, 1.0)
    a, dv_a, deps_a, _ = cap_return(s, *args)
    b, dv_b, deps_b, _ = cap_return(rotate(s, q), *args)
    assert dv_b == pytest.approx(dv_a, rel=1e-9, abs=1e-15)
    assert deps_b == pytest.approx(deps_a, rel=1e-9, abs=1e-15)
    assert np.allclose(matrix(b), q @ matrix(a) @ q.T, atol=1e-9 * np.abs(s).max())
