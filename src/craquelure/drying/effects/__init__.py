"""Drying-paste effects, one module each. Each module declares ``EFFECT`` (see
:mod:`craquelure.registry`) and the compiled fragment the engine splices in when a scene lists
the effect; ``PARAMS`` are the kernel parameters every effect set reads."""

from craquelure.registry import Param

PARAMS = (Param("support", "numerics.h", "length"),
          Param("box_length", "domain.box_length", "length"))
