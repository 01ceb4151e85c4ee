r"""Uniform body force per unit mass, :math:`\mathbf g = (g_x, g_y)`:

.. math:: \dot{\mathbf v}^I \mathrel{+}= \mathbf g .

The pair sums of the momentum equation are antisymmetric, so the centre of mass of a layer
without substrate accelerates at exactly :math:`\mathbf g`. Over a run it can supply the kinetic
energy :math:`\tfrac12 M |\mathbf g|^2 t_{end}^2` (M the total mass), which the runaway guard
adds to its bound."""

from craquelure.registry import Effect, Param


def supplied_energy(engine) -> float:
    """1/2 M |g|^2 t_end^2: the kinetic energy of free fall over the run."""
    gx, gy = engine.scene.get("material.body_force")
    t_end = float(engine.scene.get("outputs.t_end"))
    return 0.5 * float(engine.mass.sum()) * (gx * gx + gy * gy) * t_end**2


EFFECT = Effect("drying", "body_force", "BODY_FORCE", "uniform body force per unit mass g",
                params=(Param("body_force", "material.body_force", "length/time^2", size=2,
                              convert=lambda g: [float(v) for v in g]),),
                energy=supplied_energy)
