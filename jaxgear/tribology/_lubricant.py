"""The lubricant: kinematic viscosity from two measured viscosities by Walther's equation (ASTM
D341), density at the oil temperature, the pressure–viscosity coefficient.

Walther's equation (ASTM D341-20, eq. (1)), ν in mm²/s and T in K:

    log₁₀ log₁₀(ν + 0.7) = A − B log₁₀ T,

its two constants A, B through ν₄₀ (at 313.15 K) and ν₁₀₀ (at 373.15 K), the two viscosities an
oil's data sheet gives (ISO 3104). Density ρ(T) = ρ₁₅ (1 − γ (T − 15 °C)), γ the oil's volumetric
thermal expansion coefficient (mineral oils ≈ 6e-4 1/K; default 0: ρ₁₅ at every temperature).
The dynamic viscosity at the oil temperature is η₀ = ν ρ.
"""

from __future__ import annotations

import equinox as eqx
import jax.numpy as jnp
from jaxtyping import Array, Float

from .._util import as_float, check_real

__all__ = ["Lubricant"]

_T40, _T100 = 313.15, 373.15


class Lubricant(eqx.Module):
    """An oil at its operating temperature (SI units but the temperature, in °C).

    Args:
        viscosity_40, viscosity_100: kinematic viscosities ν₄₀ > ν₁₀₀, each in [2e-6, 0.1]
            (m²/s; ISO VG 320 is about 320e-6 at 40 °C; Walther's equation is stated from 2e-6),
            at 40 °C and 100 °C.
        density: ρ₁₅ (kg/m³), in (500, 2000), at 15 °C.
        pressure_viscosity: Barus' pressure–viscosity coefficient α (1/Pa), in (0, 1e-7]
            (mineral gear oils 15e-9 to 30e-9; the value at the oil temperature).
        oil_temperature: the oil's temperature at the mesh inlet ϑ_oil (°C), in (−50, 250).
        thermal_expansion: γ (1/K), in [0, 0.01); default 0.

    Raises:
        ValueError: one line naming the parameter, its value and the allowed range.
    """

    viscosity_40: Float[Array, ""]
    viscosity_100: Float[Array, ""]
    density: Float[Array, ""]
    pressure_viscosity: Float[Array, ""]
    oil_temperature: Float[Array, ""]
    thermal_expansion: Float[Array, ""]

    def __init__(
        self,
        viscosity_40,
        viscosity_100,
        density,
        pressure_viscosity,
        oil_temperature,
        thermal_expansion=0.0,
    ):
        w = "Lubricant"
        # Walther's equation (ASTM D341) is stated from 2 mm²/s; below 0.3 mm²/s it has no value
        check_real("viscosity_40", viscosity_40, "m²/s", lo=2e-6, hi=0.1, where=w)
        check_real("viscosity_100", viscosity_100, "m²/s", lo=2e-6, hi=0.1, where=w)
        try:
            bad = float(viscosity_100) >= float(viscosity_40)
        except Exception:  # noqa: BLE001 - traced: checked where used
            bad = False
        if bad:
            raise ValueError(
                f"{w}: viscosity_100 = {float(viscosity_100)!r} m²/s is out of range: allowed <"
                f" viscosity_40 = {float(viscosity_40)!r} m²/s"
            )
        check_real(
            "density", density, "kg/m³", lo=500.0, hi=2000.0, lo_open=True, hi_open=True, where=w
        )
        check_real(
            "pressure_viscosity", pressure_viscosity, "1/Pa", lo=0.0, hi=1e-7, lo_open=True, where=w
        )
        check_real(
            "oil_temperature",
            oil_temperature,
            "°C",
            lo=-50.0,
            hi=250.0,
            lo_open=True,
            hi_open=True,
            where=w,
        )
        check_real(
            "thermal_expansion", thermal_expansion, "1/K", lo=0.0, hi=0.01, hi_open=True, where=w
        )
        self.viscosity_40 = as_float(viscosity_40)
        self.viscosity_100 = as_float(viscosity_100)
        self.density = as_float(density)
        self.pressure_viscosity = as_float(pressure_viscosity)
        self.oil_temperature = as_float(oil_temperature)
        self.thermal_expansion = as_float(thermal_expansion)

    def kinematic_viscosity(self, temperature=None) -> Float[Array, ...]:
        """ν (m²/s) at ``temperature`` (°C, any shape; default the oil temperature): Walther's
        equation through ν₄₀ and ν₁₀₀ (the module docstring)."""
        t = self.oil_temperature if temperature is None else jnp.asarray(temperature)
        y40 = jnp.log10(jnp.log10(self.viscosity_40 * 1e6 + 0.7))
        y100 = jnp.log10(jnp.log10(self.viscosity_100 * 1e6 + 0.7))
        b = (y40 - y100) / (jnp.log10(_T100) - jnp.log10(_T40))
        y = y40 - b * (jnp.log10(t + 273.15) - jnp.log10(_T40))
        return (10.0 ** (10.0**y) - 0.7) * 1e-6

    def density_at(self, temperature=None) -> Float[Array, ...]:
        """ρ (kg/m³) at ``temperature`` (°C; default the oil temperature)."""
        t = self.oil_temperature if temperature is None else jnp.asarray(temperature)
        return self.density * (1.0 - self.thermal_expansion * (t - 15.0))

    @property
    def dynamic_viscosity(self) -> Float[Array, ""]:
        """η₀ = ν ρ (Pa·s) at the oil temperature and ambient pressure."""
        return self.kinematic_viscosity() * self.density_at()
