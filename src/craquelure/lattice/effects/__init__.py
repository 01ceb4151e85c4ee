"""Effects of the lattice model, one module each (discovered by :mod:`craquelure.registry`)."""
