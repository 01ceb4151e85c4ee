"""Beam-lattice fracture and flow (NUMFRAC / HiDEM family), 2D (spec ``lattice.md``)."""
