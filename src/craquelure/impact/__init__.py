"""Concrete disc striking a rigid base: SPH (2D slice or 3D) with random particle masses (spec
``impact.md``): the material in :mod:`.material`, the specimen in :mod:`.initial_state`, the
engine in :mod:`.engine`, measurements in :mod:`.measure`, the CLI stages in :mod:`.api`."""
