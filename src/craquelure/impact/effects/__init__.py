"""Impact-model effects, one module each: ``EFFECT`` declaration, equations in the docstring
and the numba fragment(s) the generated step kernels call when the scene lists the effect."""
