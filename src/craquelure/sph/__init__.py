"""SPH core shared by several models: kernels and neighbour search."""
