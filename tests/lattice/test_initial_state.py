"""Lattice initial states (lattice spec sections 2 and 7): the block and the fretting pad as two
bodies never bonded to each other (the pad's own bonds unbreakable), the boundary conditions
and top loads of the scene, the seeded bond disorder, and a time step that is the scene's
fraction of the stiffest oscillator's stable step."""

import copy
import math

import numpy as np
import pytest
import yaml

from craquelure.lattice.engine import PARAMS, stable_step_estimate
from craquelure.lattice.geometry import REMOVED
from craquelure.lattice.initial_state import build_system, engine_params, time_step
from craquelure.registry import parameter_vector
from craquelure.scene import load_scene, load_scene_text
from tests.lattice.blocks import block_height


def test_block_loads_and_clamps_follow_the_scene():
    scene = load_scene("lattice/glen")
    system, labels = build_system(scene, 0)
    nx, ny, spacing = (scene.get(k) for k in ("domain.nx", "domain.ny", "particles.spacing"))
    assert system.n == nx * ny
    assert (system.fix[:, labels["row"] == 0] == 1).all()  # clamp_bottom
    assert (system.fix[:, labels["row"] > 0] == 0).all()
    top = labels["row"] == ny - 1
    # the top row carries the stresses over the periodic width nx L
    assert system.load[0, top].sum() == pytest.approx(scene.get("loads.top_shear_stress")
                                                      * nx * spacing, rel=1e-12)
    assert system.load[1, top].sum() == pytest.approx(-scene.get("loads.top_normal_stress")
                                                      * nx * spacing, rel=1e-12)
    assert (system.load[:, ~top] == 0).all()
    assert system.y[top].min() - system.y.min() == pytest.approx(block_height(scene), rel=1e-12)


def test_the_pad_is_a_second_body_driven_from_its_top():
    scene = load_scene("lattice/fretting")
    system, labels = build_system(scene, 0)
    body = labels["body"]
    assert body.max() == 1 and (body == 1).sum() > 10
    assert (body[system.bi] == body[system.bj]).all()  # no bond joins pad and block
    assert (system.unbreakable[body[system.bi] == 1] == 1).all()
    assert (system.unbreakable[body[system.bi] == 0] == 0).all()
    gap = system.y[body == 1].min() - system.y[body == 0].max()
    assert gap == pytest.approx(scene.get("particles.spacing") + scene.get("domain.pad")["gap"])
    driven = system.drive[0] == 1
    assert driven.any() and (body[driven] == 1).all()
    assert system.load[1, driven].sum() == pytest.approx(-scene.get("domain.pad")["load"])


def test_bond_disorder_is_the_scenes_fraction_and_seeded():
    scene = load_scene("lattice/calving", ["domain.nx=30", "domain.ny=8"])
    removed = [build_system(scene, seed)[0].state == REMOVED for seed in (3, 3, 4)]
    n = removed[0].size
    assert removed[0].sum() == round(scene.get("particles.bond_removal") * n)
    np.testing.assert_array_equal(removed[0], removed[1])
    assert (removed[0] != removed[2]).any()


def test_time_step_is_the_fraction_of_the_stiffest_oscillator():
    scene = load_scene("lattice/glen")
    system, _ = build_system(scene, 0)
    # beams only: dt_factor x the beam lattice's stable step
    assert time_step(scene, system) == pytest.approx(
        scene.get("numerics.dt_factor") * stable_step_estimate(system), rel=1e-12)
    # a bed spring adds its frequency: w^2 = (2/dt_beam)^2 + k_bed/m
    calving = load_scene("lattice/calving", ["domain.nx=30", "domain.ny=8"])
    system, _ = build_system(calving, 0)
    w2 = (2 / stable_step_estimate(system)) ** 2 + calving.get("bed.stiffness") / system.mass.min()
    w2 += 1.5 * calving.get("contact.stiffness") * math.sqrt(0.1 * system.L) / system.mass.min()
    assert time_step(calving, system) == pytest.approx(
        calving.get("numerics.dt_factor") * 2 / math.sqrt(w2), rel=1e-12)


def packed_params(scene):
    system, _ = build_system(scene, 0)
    return parameter_vector("lattice", values={**engine_params(scene, system),
                                               "period_x": system.period_x})


def test_buoyancy_off_leaves_its_densities_unread():
    """Without buoyancy the kernel's parameter vector is the same whether or not the scene
    gives material.rho and rho_w (their declared neutral values, no fallback to the disc
    density); with buoyancy it holds the scene's."""
    small = ["domain.nx=30", "domain.ny=8"]
    on = load_scene("lattice/calving", small)
    given = on.with_overrides(["effects=[beams, fracture, contact, gravity, drag, bed]"])
    data = copy.deepcopy(given.data)
    del data["material"]["rho"], data["material"]["rho_w"]
    p = packed_params(given)
    assert np.array_equal(p, packed_params(load_scene_text(yaml.safe_dump(data), "absent")))
    neutral = parameter_vector("lattice")
    assert p[PARAMS.index("rho")] == neutral[PARAMS.index("rho")]
    assert p[PARAMS.index("rho_w")] == neutral[PARAMS.index("rho_w")]
    assert packed_params(on)[PARAMS.index("rho")] == on.get("material.rho")


def test_optional_lattice_keys_mean_what_their_absence_says():
    """numerics.mass_damping_until absent: mass damping to the end (inf); domain.water_level
    absent with drag: no water line (-inf, nothing below it)."""
    scene = load_scene("lattice/calving", ["domain.nx=30", "domain.ny=8"])
    assert packed_params(scene)[PARAMS.index("mass_damping_until")] == 150.0
    data = copy.deepcopy(scene.data)
    del data["numerics"]["mass_damping_until"], data["domain"]["water_level"]
    data["effects"] = ["beams", "gravity", "drag", "bed"]
    data["drag"]["everywhere"] = True
    p = packed_params(load_scene_text(yaml.safe_dump(data), "absent"))
    assert p[PARAMS.index("mass_damping_until")] == math.inf
    assert p[PARAMS.index("water_level")] == -math.inf
