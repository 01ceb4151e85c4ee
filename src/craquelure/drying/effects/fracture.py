r"""Fracture by particle removal (drying spec section 4).

The criterion's stress measure s of the total 2D stress (viscous + elastic + drying, evaluated
with the rates of the accepted state) is the scene's ``material.fracture_stress_measure``:

- ``half_trace`` (default, the source's text): :math:`s = \bar\sigma = \mathrm{tr}\,\sigma/2`;
- ``trace``: :math:`s = \mathrm{tr}\,\sigma`: a factor 2 between load and threshold, the
  headline Table I profile's one declared departure (open doubt 7; why this form: the drying
  page): the same model as ``half_trace`` with :math:`\sigma_Y/2` and the initial stress
  amplitude doubled, at Table I's :math:`\sigma_Y`, :math:`v_r` and :math:`t^*`;
- ``max_principal``: :math:`s = \sigma_1 = \mathrm{tr}\,\sigma/2 +
  \sqrt{((\sigma_{xx} - \sigma_{yy})/2)^2 + \sigma_{xy}^2}` (Rankine).

After every accepted step, every particle with :math:`s > \sigma_Y` is deleted: it keeps its
index with ``alive = 0``, leaves the neighbour search, and its mass, momentum and history
vanish. The multistep integrator then restarts (its history is invalid)."""

import numpy as np
from numba import njit

from craquelure.registry import Effect

# flag None: acts between steps (engine), not in the rate kernel
EFFECT = Effect("drying", "fracture", None,
                "remove particles whose criterion stress (default tr(sigma)/2) exceeds sigma_Y",
                requires=("material.yield_stress",), diagnostics=("n_removed", "alive"))

MEASURES = ("half_trace", "trace", "max_principal")
SOURCE_MEASURE = "half_trace"
MEASURE_TEXT = {"half_trace": "tr(sigma)/2", "trace": "tr(sigma)",
                "max_principal": "largest principal stress"}


def criterion_stress(stress: np.ndarray, measure: str) -> np.ndarray:
    """The criterion's stress measure of the total stress rows (xx, yy, xy), per particle."""
    sxx, syy, sxy = stress[0], stress[1], stress[2]
    if measure == "half_trace":
        return 0.5 * (sxx + syy)
    if measure == "trace":
        return sxx + syy
    if measure == "max_principal":
        return 0.5 * (sxx + syy) + np.hypot(0.5 * (sxx - syy), sxy)
    raise ValueError(f"material.fracture_stress_measure = {measure!r} is not allowed; allowed "
                     f"values: {', '.join(MEASURES)}")


# How each criterion departs from the source's text: the factor between load and threshold
# (the headline profile's declared departure) or a different measure (a sensitivity).
DEPARTURE = {"trace": "a factor 2 between load and threshold, the headline profile's declared "
                      "departure",
             "max_principal": "a sensitivity, open doubt 7"}


def departure_note(measure: str) -> str:
    """'' for the source's criterion, else the sentence every caption and row carries."""
    if measure == SOURCE_MEASURE:
        return ""
    return (f"fracture criterion {MEASURE_TEXT[measure]} > sigma_Y departs from the source's "
            f"tr(sigma)/2 > sigma_Y ({DEPARTURE[measure]})")


@njit(cache=True)
def particles_to_remove(criterion, alive, yield_stress):
    """Indices of live particles whose criterion stress is strictly above the yield stress."""
    return np.nonzero(alive & (criterion > yield_stress))[0]
