r"""Material point model of the concrete (spec section 2), composed from the effect fragments.

Update order per particle and step (spec section 3): Jaumann trial effective stress
(:mod:`.effects.elasticity`) → Drucker-Prager return (:mod:`.effects.plasticity`) or the
CSCM-like cap return (:mod:`.effects.cap_plasticity`, shear strength scaled by the compressive
damage of :mod:`.effects.compressive_damage`) → Rankine damage and nominal stress
(:mod:`.effects.damage`) → with :mod:`.effects.rate_effects` the viscoplastic blend of the
trial and that inviscid stress. :class:`Concrete` holds the derived constants.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from craquelure.errors import SceneError
from craquelure.impact.effects.cap_plasticity import CapSurface, surface_constants
from craquelure.impact.effects.compressive_damage import softening_strain
from craquelure.impact.effects.plasticity import dp_constants
from craquelure.impact.effects.rate_effects import RATE_PARAMS, rate_constants

# The constants a scene gives the concrete (declared by the effects that read them,
# :mod:`craquelure.impact.effects`; neutral when those are all off).
MATERIAL_CONSTANTS = ("bulk", "shear", "f_c", "f_t", "G_F")


@dataclass(frozen=True)
class Concrete:
    """Derived constants of the concrete model (SI units)."""

    bulk: float
    shear: float
    f_c: float
    f_bc_ratio: float
    f_t: float
    G_F: float
    band: float  # crack-band width l_c
    gfc_ratio: float = 100.0  # G_fc / G_F (compressive damage)

    @property
    def young(self) -> float:
        return 9.0 * self.bulk * self.shear / (3.0 * self.bulk + self.shear)

    @property
    def poisson(self) -> float:
        return (3.0 * self.bulk - 2.0 * self.shear) / (2.0 * (3.0 * self.bulk + self.shear))

    @property
    def dp(self) -> tuple[float, float]:
        return dp_constants(self.f_c, self.f_bc_ratio)

    @property
    def cap(self) -> CapSurface:
        return surface_constants(self.f_c, self.f_bc_ratio)

    @property
    def eps_fc(self) -> float:
        """Plastic strain at full compressive damage (G_fc = gfc_ratio G_F dissipated over l_c
        in uniaxial compression)."""
        return softening_strain(self.f_c, self.G_F, self.band, self.cap, self.gfc_ratio)

    @property
    def rates(self) -> dict[str, float]:
        return rate_constants(self.f_c)

    def cap_vector(self) -> np.ndarray:
        """Constants of the cap and rate branches, in the kernels' order (``CAP_PARAMS``)."""
        c, r = self.cap, self.rates
        return np.array([c.alpha, c.lam, c.beta, c.theta, c.e, c.X0, c.W, c.D1, c.D2,
                         self.eps_fc, *(r[k] for k in RATE_PARAMS), self.f_t, self.f_c,
                         c.kappa0, c.R])

    @property
    def eps_0(self) -> float:
        return self.f_t / self.young

    @property
    def eps_f(self) -> float:
        return 2.0 * self.G_F / (self.f_t * self.band)

    @property
    def hillerborg_length(self) -> float:
        return self.young * self.G_F / self.f_t**2

    def validate(self) -> None:
        if self.eps_f <= self.eps_0:
            raise SceneError(
                f"material.crack_band_width: the crack band width {self.band:g} m is >= 2 l_ch "
                f"= {2 * self.hillerborg_length:g} m (l_ch = E G_F/f_t^2 from material.G_F, "
                f"material.f_t and the moduli): linear softening would snap back")


def standard_concrete(band: float = 0.0048) -> Concrete:
    """Spec Table 1 values (K, G, f_c, f_t, G_F) with l_c = h(0) = 1.2 * 4 mm by default."""
    return Concrete(bulk=14.15e9, shear=12.92e9, f_c=43.1e6, f_bc_ratio=1.16,
                    f_t=0.30 * (43.1 - 8.0) ** (2.0 / 3.0) * 1e6, G_F=83.25, band=band)


__all__ = ["Concrete", "standard_concrete"]
