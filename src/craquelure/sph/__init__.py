"""SPH core shared by the drying-paste and concrete-impact models: kernels, neighbour search,
mesh fields, the mass-consistency solve, the effects and the engine."""
