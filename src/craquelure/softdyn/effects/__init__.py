"""Soft Dynamics effects: one module per physical effect (see :mod:`craquelure.registry`);
``PARAMS`` are the kernel parameters every effect set reads (the Baumgarte rate and the ramp
time in the time unit of the scenario, computed by the engine)."""

from craquelure.registry import Param

PARAMS = (
    Param("R", "material.radius", "length"),
    # the force unit F = F~ E R^2 whenever the scene gives E; a rigid scene without it: 1
    Param("E", "material.young", "stress", neutral=1.0, optional=True),
    Param("inv_tau_B", None, "1/time"),
    Param("t_r", None, "time"),
)
