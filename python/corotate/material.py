"""Isotropic linear-elastic material."""

from __future__ import annotations

from dataclasses import dataclass

import corotate._core as _core

from ._numbers import real_number


@dataclass(frozen=True)
class Material:
    """Isotropic elastic material in SI units.

    E        Young's modulus [Pa], > 0
    nu       Poisson ratio [-], in (-1, 0.5); 0.5 (incompressible) is rejected
    density  mass density [kg/m^3], > 0

    Raises TypeError for a parameter that is not a real number (a bool is not), ValueError
    naming the bad parameter.
    """

    E: float = 1e6
    nu: float = 0.3
    density: float = 1000.0

    def __post_init__(self) -> None:
        for name in ("E", "nu", "density"):
            real_number(getattr(self, name), f"Material {name}")  # TypeError for True, "1e6", ...
        self._core()  # validates

    def _core(self) -> _core.Material:
        return _core.Material(float(self.E), float(self.nu), float(self.density))

    @property
    def lame(self) -> tuple[float, float]:
        """Lame parameters (lambda, mu) [Pa]."""
        m = self._core()
        return m.lame_lambda, m.lame_mu
