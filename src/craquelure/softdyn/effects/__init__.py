"""Soft Dynamics effects: one module per physical effect (see :mod:`craquelure.registry`)."""
