"""Tribology objectives: the mesh power loss, the mesh's loss of efficiency, the smallest specific
film thickness λ and the largest flash temperature along the path of contact, each read from the
quasi-static result of the design at a torque by :func:`jaxgear.tribology.mesh_tribology` (and
:func:`jaxgear.tribology.mesh_flash_temperature`); docs/tribology.md,
"Optimising the tribology".

Each is an :class:`~optimise.AbstractQuasiStaticObjective`: the design is solved at each torque of
the objective (the design torque, or a torque range ``torques`` reduced by ``statistic``, as
:class:`~optimise.RobustTeRms` does for the TE RMS), and the value is scaled by the unmodified
design's at the design torque, so the optimiser sees 1 at the start. The lubricated mesh (the
pair, the oil, its speed, the flanks' roughness and material, the film formula and friction law)
is one :class:`MeshLubrication`; a case file's ``[lubricant]`` builds it in :mod:`jaxgear.io`.

Differentiable in the tooth modifications through the line loads (the smooth contact law of the
problem); μ (Schlenk's) depends on the torque and the oil, not on the modifications. The minimum
λ and the maximum flash temperature are extrema over the cells: differentiable almost
everywhere, with a kink where the critical cell changes, as :class:`~optimise.MaxLineLoad`.
"""

from __future__ import annotations

import abc
from typing import ClassVar

import equinox as eqx
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Float

import jaxgear as jg
import jaxgear.tribology as tr

from ._objectives import AbstractQuasiStaticObjective, AbstractStatistic, Max

__all__ = [
    "AbstractTribologyObjective",
    "EfficiencyLoss",
    "MaxFlashTemperature",
    "MeshLubrication",
    "MeshPowerLoss",
    "MinSpecificFilm",
]

class MeshLubrication(eqx.Module):
    """The lubricated mesh of the tribology objectives: what
    :func:`jaxgear.tribology.mesh_tribology` takes besides the result and the torque.

    Attributes:
        pair: the mesh's gear pair (:class:`jaxgear.GearPair`), its pinion driving.
        lubricant: :class:`jaxgear.tribology.Lubricant`.
        speed: pinion speed ω₁ (rad/s) > 0 (the oil's entrainment and the sliding; not the
            problem's ``speed``, which loads condensed bodies centrifugally).
        roughness: (R_a1, R_a2) (m), each in (0, 1e-5].
        youngs_modulus, poisson_ratio: both gears' (Pa, -).
        film: the film formula kind (default :class:`jaxgear.tribology.DowsonHigginson`).
        friction: the friction kind (default :class:`jaxgear.tribology.Schlenk` with X_L = 1).
        thermal_coefficients: (B_M1, B_M2) (W s^½/(m² K)) of the flash temperature; default
            steel's.

    Raises:
        ValueError: one line naming the argument, its value and the allowed range (as
            :func:`jaxgear.tribology.mesh_tribology`), before any computation.
    """

    pair: jg.AbstractGearPair
    lubricant: tr.Lubricant
    speed: Float[Array, ""]
    roughness: Float[Array, " 2"]
    youngs_modulus: float = eqx.field(static=True)
    poisson_ratio: float = eqx.field(static=True)
    film: tr.AbstractFilmFormula
    friction: tr.AbstractFriction
    thermal_coefficients: Float[Array, " 2"]

    def __init__(
        self,
        pair,
        lubricant,
        speed,
        roughness,
        youngs_modulus,
        poisson_ratio,
        *,
        film=None,
        friction=None,
        thermal_coefficients=(
            tr.STEEL_THERMAL_CONTACT_COEFFICIENT,
            tr.STEEL_THERMAL_CONTACT_COEFFICIENT,
        ),
    ):
        w = "MeshLubrication"
        film = tr.DowsonHigginson() if film is None else film
        friction = tr.Schlenk() if friction is None else friction
        checks = (
            ("pair", pair, jg.AbstractGearPair, "a GearPair or InternalGearPair"),
            ("lubricant", lubricant, tr.Lubricant, "a jaxgear.tribology.Lubricant"),
            ("film", film, tr.AbstractFilmFormula, "a film formula kind"),
            ("friction", friction, tr.AbstractFriction, "a friction kind"),
        )
        for name, value, kind, allowed in checks:
            if not isinstance(value, kind):
                raise ValueError(f"{w}: {name} = {type(value).__name__}: allowed {allowed}")
        _positive(w, "speed", speed, "rad/s", 1e5)
        _positive(w, "youngs_modulus", youngs_modulus, "Pa", 1e13)
        ra = np.asarray(roughness, dtype=float)
        if ra.shape != (2,) or not np.all((ra > 0) & (ra <= 1e-5)):
            raise ValueError(
                f"{w}: roughness = {roughness!r} m is out of range: allowed (R_a1, R_a2), each in "
                "(0, 1e-05] m"
            )
        nu = float(poisson_ratio)
        if not 0.0 <= nu < 0.5:
            raise ValueError(f"{w}: poisson_ratio = {nu:g} is out of range: allowed [0, 0.5)")
        bm = np.asarray(thermal_coefficients, dtype=float)
        if bm.shape != (2,) or not np.all(bm > 0):
            raise ValueError(
                f"{w}: thermal_coefficients = {thermal_coefficients!r} W s^½/(m² K) is out of "
                "range: allowed (B_M1, B_M2), each > 0"
            )
        self.pair = pair
        self.lubricant = lubricant
        self.speed = jnp.asarray(float(speed))
        self.roughness = jnp.asarray(ra)
        self.youngs_modulus = float(youngs_modulus)
        self.poisson_ratio = nu
        self.film = film
        self.friction = friction
        self.thermal_coefficients = jnp.asarray(bm)

    def tribology(self, result: jg.QuasiStaticResult, torque) -> tr.MeshTribology:
        """Film and sliding loss of ``result`` (one mesh) at pinion torque ``torque`` (N·m)."""
        dtype = result.line_load.dtype
        return tr.mesh_tribology(
            self.pair,
            result,
            self.lubricant,
            jnp.asarray(torque, dtype),
            self.speed.astype(dtype),
            self.roughness.astype(dtype),
            self.youngs_modulus,
            self.poisson_ratio,
            film=self.film,
            friction=self.friction,
        )

    def max_flash_temperature(self, result: jg.QuasiStaticResult, torque) -> Float[Array, ""]:
        """Blok's largest flash temperature θ_fl (K) along the path of contact of ``result`` at
        ``torque`` (N·m) (:func:`jaxgear.tribology.mesh_flash_temperature`); its derivative is
        the one at the hottest cell (the first, at a tie)."""
        flash = tr.mesh_flash_temperature(
            self.pair,
            self.tribology(result, torque),
            self.youngs_modulus,
            self.poisson_ratio,
            thermal_coefficients=self.thermal_coefficients.astype(result.line_load.dtype),
        ).reshape(-1)
        return flash[jnp.argmax(flash)]


def _positive(where, name, value, unit, hi):
    try:
        v = float(value)
    except (TypeError, ValueError):
        v = float("nan")
    if not 0.0 < v <= hi:
        raise ValueError(
            f"{where}: {name} = {value!r} {unit} is out of range: allowed (0, {hi:.0e}] {unit}"
        )


def _torque_range(t) -> Float[Array, " T"] | None:
    return None if t is None else jnp.asarray(np.asarray(t, dtype=float).reshape(-1))


class AbstractTribologyObjective(AbstractQuasiStaticObjective):
    """A tribology objective (the module docstring): :meth:`of_tribology` of the design's
    quasi-static result at each torque, reduced by ``statistic``.

    Attributes:
        lubrication: :class:`MeshLubrication`.
        torques_Nm: the torques (N·m), (T,), each > 0, or None (the design torque).
        statistic: the reduction over the torques (default :class:`~optimise.Max`).

    Raises:
        ValueError: not a :class:`MeshLubrication`, an empty torque range or a torque <= 0, a
            statistic that is not one.
    """

    lubrication: MeshLubrication
    torques_Nm: Float[Array, " T"] | None = eqx.field(default=None, converter=_torque_range)
    statistic: AbstractStatistic = eqx.field(default_factory=Max)

    def __check_init__(self):
        if not isinstance(self.lubrication, MeshLubrication):
            raise ValueError(
                f"{type(self).__name__}: lubrication = {type(self.lubrication).__name__}: allowed "
                "an optimise.MeshLubrication"
            )
        if self.torques_Nm is not None:
            t = np.asarray(self.torques_Nm)
            if t.size == 0 or np.any(~(t > 0)):
                raise ValueError(f"torques = {t.tolist()} N·m: allowed one or more, each > 0")
        if not isinstance(self.statistic, AbstractStatistic):
            raise ValueError(
                f"statistic = {self.statistic!r}: allowed optimise.Max(), Mean() or Quantile(q)"
            )

    @abc.abstractmethod
    def of_tribology(self, result: jg.QuasiStaticResult, torque) -> Float[Array, ""]:
        """The unscaled objective (``units``) of one quasi-static result at ``torque`` (N·m)."""

    def at_torque(self, problem, mods, torque, contact):
        return self.of_tribology(self.solve(problem, mods, torque, contact), torque)

    def of_result(self, result, problem):
        """The objective of ``result`` at ``problem``'s design torque."""
        return self.of_tribology(result, problem.design_torque)

    def scale(self, unmodified, torque):
        return float(self.of_tribology(unmodified, torque))

    def torques(self, design_torque):
        if self.torques_Nm is None:
            return np.array([float(design_torque)])
        return np.asarray(self.torques_Nm)

    def reduce(self, values):
        return self.statistic(values)


class MeshPowerLoss(AbstractTribologyObjective):
    """The mesh's sliding power loss P_VZP (W): the local loss μ w v_g integrated over the
    contact lines and averaged over the mesh positions (:class:`jaxgear.tribology.MeshTribology`
    ``mean_power_loss``)."""

    name: ClassVar[str] = "power_loss"
    units: ClassVar[str] = "W"

    def of_tribology(self, result, torque):
        return self.lubrication.tribology(result, torque).mean_power_loss


class EfficiencyLoss(AbstractTribologyObjective):
    """The mesh's loss of efficiency 1 − η_Z = P_VZP/(T ω₁) (-): minimising it maximises the
    mesh efficiency. At one torque it is the power loss over a constant; over a torque range it
    weighs each torque's loss by its input power."""

    name: ClassVar[str] = "efficiency_loss"
    units: ClassVar[str] = "dimensionless"

    def of_tribology(self, result, torque):
        return 1.0 - self.lubrication.tribology(result, torque).efficiency


class MinSpecificFilm(AbstractTribologyObjective):
    """1/λ_min (-): the inverse of the smallest specific film thickness λ = h_min/R_a over the
    loaded cells (:attr:`jaxgear.tribology.MeshTribology.min_specific_film`); minimising it
    raises the thinnest film. With the default :class:`~optimise.Max` over a torque range it is
    1/(the smallest λ over the torques)."""

    name: ClassVar[str] = "min_specific_film"
    units: ClassVar[str] = "inverse_lambda"

    def of_tribology(self, result, torque):
        return 1.0 / self.lubrication.tribology(result, torque).min_specific_film


class MaxFlashTemperature(AbstractTribologyObjective):
    """Blok's largest flash temperature θ_fl (K) along the path of contact
    (:meth:`MeshLubrication.max_flash_temperature`; ISO/TS 6336-20's flash temperature from
    jaxgear's line loads)."""

    name: ClassVar[str] = "max_flash_temperature"
    units: ClassVar[str] = "K"

    def of_tribology(self, result, torque):
        return self.lubrication.max_flash_temperature(result, torque)
