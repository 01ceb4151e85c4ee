"""The softdyn kernel template: effects compiled in or out by their flags, and the sparse path
equal to the dense one."""

import math

import numpy as np
import pytest

from craquelure import codegen
from craquelure.softdyn.engine import Engine, Flags, kernels

from .test_engine import C_N, C_T, t1_setup

ALL = ("lubrication_normal", "lubrication_tangential", "hertz")
NO_TANGENTIAL = ("lubrication_normal", "hertz")


def test_effects_are_compiled_in_or_out():
    """Effects on demand: each effect set gets its own generated kernel with the absent effects
    as compile-time False, and the state only holds what the effects need."""
    src, _ = codegen.generate("craquelure.softdyn.kernel_template",
                              Flags(NO_TANGENTIAL).template_flags())
    assert "\nLUBRICATION_TANGENTIAL = False\n" in src and "\nHERTZ = True\n" in src
    mod = kernels(Flags(NO_TANGENTIAL))
    assert mod.LUBRICATION_TANGENTIAL is False and mod is not kernels(Flags(ALL))
    full = t1_setup().system
    no_t = t1_setup("effects=[lubrication_normal, hertz]").system
    rigid = t1_setup("effects=[lubrication_normal, lubrication_tangential]").system
    assert full.state_size == 8 + 6 + 12
    assert no_t.state_size == 8 + 6
    assert rigid.state_size == 8


def hex_cluster(rows, cols, gap, rng):
    d = 2.0 + gap
    pts = [(c * d + (r % 2) * d / 2, r * d * math.sqrt(3) / 2)
           for r in range(rows) for c in range(cols)]
    x = np.array(pts)
    pairs = [(i, j) for i in range(len(x)) for j in range(i + 1, len(x))
             if np.linalg.norm(x[i] - x[j]) < d * 1.01]
    F = 1e-3 * rng.standard_normal(x.shape)
    F -= F.mean(axis=0)
    return x, np.array(pairs), F


@pytest.mark.parametrize("effects", [Flags(ALL), Flags(NO_TANGENTIAL)])
def test_sparse_path_matches_dense(effects):
    """The N-sphere sparse (SuperLU / LSQR) solve gives the dense right-hand side (N = 20)."""
    rng = np.random.default_rng(9)
    x, pairs, F = hex_cluster(4, 5, 0.01, rng)
    common = dict(x0=x, pairs=pairs, F0=F, radius=1.0, viscosity=1.0, young=1.0, k_n=1.0,
                  k_t=1.0, c_n=C_N, c_t=C_T, tau_baumgarte=10.0, ramp_time=100.0, flags=effects)
    dense = Engine(**common, linear_solver="dense")
    sparse = Engine(**common, linear_solver="sparse")
    y = dense.initial_state()
    y[x.size: x.size + len(pairs)] = 1e-3 * rng.uniform(0.1, 1.0, len(pairs))
    a, b = dense.rhs(5.0, y), sparse.rhs(5.0, y)
    assert np.abs(a - b).max() <= 1e-8 * np.abs(a).max()
    assert sparse.solver == "sparse" and dense.solver == "dense"
