"""Isotropic elastic materials: by Young's modulus and Poisson ratio, or by a law's own parameters."""

from __future__ import annotations

from dataclasses import dataclass

import corotate._core as _core

from ._numbers import real_number


@dataclass(frozen=True, init=False)
class Material:
    """Isotropic elastic material in SI units.

    The common case, which every model takes::

        cr.Material(E=1e6, nu=0.3, density=1000)

    E        Young's modulus [Pa], > 0
    nu       Poisson ratio [-], in (-1, 0.5); 0.5 (incompressible) is rejected
    density  mass density [kg/m^3], > 0

    A material given in a hyperelastic law's own parameters (the laws and their parameters
    are ``Material.law_parameters()``, read from the core)::

        cr.Material(law="mooney_rivlin", C10=0.3e6, C01=0.05e6, bulk=1e8, density=1100)

    Its E and nu are then the law's small-strain moduli (derived, not given): the "linear"
    and "corotational" models, a modal reduction and the force feedback use them; of the
    nonlinear models only that law's takes it. A law's model also takes a material given by
    E and nu (the law derives its parameters from them; see the law's header).

    Raises TypeError for a parameter that is not a real number (a bool is not), ValueError
    naming the bad parameter (unknown, missing, out of range).
    """

    E: float
    nu: float
    density: float
    law: str | None
    parameters: tuple[tuple[str, float], ...]

    def __init__(
        self,
        E: float | None = None,
        nu: float | None = None,
        density: float = 1000.0,
        *,
        law: str | None = None,
        **parameters: float,
    ) -> None:
        if law is None:
            if parameters:
                raise ValueError(
                    f"unknown material parameter(s) {', '.join(parameters)}: a law's own parameters need law=... "
                    f"({_law_list()}); otherwise give E, nu and density"
                )
            E, nu = 1e6 if E is None else E, 0.3 if nu is None else nu
            core = _core.Material(real_number(E, "Material E"), real_number(nu, "Material nu"), _density(density))
            named: tuple[tuple[str, float], ...] = ()
        else:
            if E is not None or nu is not None:
                raise ValueError(
                    f"a {law!r} material is given by its own parameters; its E and nu are derived from them "
                    "(give either E and nu, or law=... with its parameters)"
                )
            values = {k: real_number(v, f"Material {k}") for k, v in parameters.items()}
            core = _core.material_of_law(str(law), values, _density(density))
            names = [name for name, _ in _core.law_parameters()[core.law]]
            named = tuple(zip(names, core.parameters))
        object.__setattr__(self, "E", core.youngs_modulus)
        object.__setattr__(self, "nu", core.poisson_ratio)
        object.__setattr__(self, "density", core.density)
        object.__setattr__(self, "law", law)
        object.__setattr__(self, "parameters", named)

    def _core(self) -> _core.Material:
        if self.law is None:
            return _core.Material(float(self.E), float(self.nu), float(self.density))
        return _core.material_of_law(self.law, dict(self.parameters), float(self.density))

    @property
    def lame(self) -> tuple[float, float]:
        """Lame parameters (lambda, mu) [Pa] (small-strain)."""
        m = self._core()
        return m.lame_lambda, m.lame_mu

    @staticmethod
    def law_parameters() -> dict[str, list[tuple[str, str]]]:
        """{law: [(parameter, meaning), ...]} for every law with parameters of its own."""
        return {str(law): [(str(n), str(m)) for n, m in params] for law, params in _core.law_parameters().items()}


def _density(value: object) -> float:
    return real_number(value, "Material density")  # TypeError for True, "1e3", ...


def _law_list() -> str:
    return "; ".join(f"{law}: {', '.join(n for n, _ in params)}" for law, params in _core.law_parameters().items())
