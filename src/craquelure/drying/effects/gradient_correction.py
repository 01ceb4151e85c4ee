r"""Kernel-gradient correction of the velocity gradient (Bonet & Lok 1999; Randles & Libersky
1996), an option beyond the paper:

.. math:: L^I_{ab} = \sum_c \Big[\sum_J V_J (v^J_a - v^I_a)\,\partial_c W_{IJ}\Big]
   (M^I)^{-1}_{cb}, \qquad
   M^I_{cb} = \sum_J V_J (r^J_c - r^I_c)\,\partial_b W_{IJ}.

:math:`M^I = \mathbf 1` in the bulk of a regular arrangement (check 2: 1.00088), so the bulk is
unchanged; near a free surface (a crack face, the edge of the strip of check 10) the kernel
support is truncated, :math:`M \approx \tfrac12` across the edge, and the uncorrected L
underestimates the strain rate there by about 2. The correction makes L exact for every linear
velocity field, at free edges too. Only L (hence D, the viscous and elastic stress, continuity)
is corrected; the momentum equation keeps its symmetric pairwise form, so momentum is still
conserved exactly. Where :math:`|\det M| < 10^{-3}` (a particle with almost no neighbours)
the raw L is kept [D]."""

from numba import njit

from craquelure.registry import Effect

EFFECT = Effect("drying", "gradient_correction", "GRADIENT_CORRECTION",
                "kernel-gradient correction of the velocity gradient (exact at free edges)")

MIN_DETERMINANT = 1e-3


@njit(inline="always", cache=True)
def corrected_gradient(lxx, lxy, lyx, lyy, mxx, mxy, myx, myy):
    """L M^{-1} for the 2x2 matrices L and M (raw L if M is nearly singular)."""
    det = mxx * myy - mxy * myx
    if abs(det) < MIN_DETERMINANT:
        return lxx, lxy, lyx, lyy
    ixx = myy / det
    ixy = -mxy / det
    iyx = -myx / det
    iyy = mxx / det
    return (lxx * ixx + lxy * iyx, lxx * ixy + lxy * iyy,
            lyx * ixx + lyy * iyx, lyx * ixy + lyy * iyy)
