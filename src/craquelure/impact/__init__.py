"""Concrete disc striking a rigid base: 2D plane-strain SPH with random particle masses
(spec ``impact.md``). Material point model in :mod:`.material`, specimen geometry and masses in
:mod:`.specimen`, the effect-specialised SPH engine in :mod:`.engine`, measurements in
:mod:`.measure`, the CLI stages in :mod:`.api`."""
