"""Drying-paste effects, one module each. Each module declares ``EFFECT`` (see
:mod:`craquelure.registry`) and the compiled fragment the engine splices in when a scene lists
the effect."""
