"""Impact-model effects, one module each: ``EFFECT`` declaration, equations in the docstring
and the numba fragment(s) the generated step kernels call when the scene lists the effect.

``PARAMS`` are the kernel parameters every effect set reads; the engine computes them
(:class:`craquelure.impact.engine.Settings`). The concrete's constants several effects read are
declared here once; an effect that is off leaves them at their neutral values: unit moduli keep
E, nu and the wave speed finite, strengths and a fracture energy never reached (no yield, no
softening)."""

from craquelure.registry import Param

PARAMS = tuple(Param(name, None, unit) for name, unit in (
    ("young", "Pa"), ("wave_speed", "m/s"), ("spacing", "m"), ("base_y", "m"),
    ("contact_radius", "m"), ("lx", "m"), ("ly", "m"), ("lz", "m"), ("flush_below", "1")))

BULK = Param("bulk", "material.bulk_modulus", "Pa", neutral=1.0)
SHEAR = Param("shear", "material.shear_modulus", "Pa", neutral=1.0)
F_C = Param("f_c", "material.f_c", "Pa", neutral=1e30, kernel=False)
F_T = Param("f_t", "material.f_t", "Pa", neutral=1e30, kernel=False)
G_F = Param("G_F", "material.G_F", "N/m", neutral=1e30, kernel=False)
