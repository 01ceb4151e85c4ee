"""Effects of the lattice model, one module each (discovered by :mod:`craquelure.registry`);
``PARAMS`` are the kernel parameters every effect set reads. Values without a scene path come
from :func:`craquelure.lattice.initial_state.engine_params` (beam constants, the stable step) or
the engine (period); the neutral values make a probe that is not a scene a unit block."""

import math

from craquelure.registry import Param

PARAMS = (
    Param("dt", None, "time"),
    Param("beta", None, "time"),  # bond damping time 2 zeta sqrt(m/k_n)
    Param("gamma", "numerics.mass_damping", "1/time"),
    Param("area", None, "length", neutral=1.0),
    Param("inertia", None, "length^3", neutral=1.0 / 12),
    Param("width", None, "length", neutral=1.0),
    Param("E_b", None, "stress", neutral=1.0),
    Param("block", None, "length", neutral=1.0),
    Param("cell_area", None, "length^2", neutral=math.sqrt(3) / 2),
    Param("period_x", None, "length"),
    Param("drive_vx", None, "length/time"),
    Param("drive_vy", None, "length/time"),
    Param("drive_amplitude", "domain.pad.amplitude", "length", optional=True),
    Param("drive_period", "domain.pad.period", "time", optional=True),
    Param("drive_start", "domain.pad.press_time", "time", optional=True),
    Param("load_ramp", "loads.ramp_time", "time"),
    # NaN until given: the schema owns its value (engine.require_schema_owned)
    Param("energy_tolerance", "numerics.energy_tolerance", neutral=math.nan),
    Param("energy_floor", None, "energy", neutral=1e-300),
    # absent: mass damping to the end
    Param("mass_damping_until", "numerics.mass_damping_until", "time", neutral=math.inf,
          optional=True),
)
