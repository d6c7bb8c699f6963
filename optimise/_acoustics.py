"""Acoustic objectives: the equivalent radiated power and the radiated sound power of a housed
gearbox over a speed range, through the whole chain (docs/acoustics.md, "Optimising for noise").

The chain of one design (tooth modifications ``mods``) at one torque:

    mods → the quasi-static solve at each mesh position (its TE, the mesh stiffness K_m(θ))
         → the whine: the harmonic balance of the lumped dynamics at each speed
           (:func:`jaxgear.dynamics.whine_response`), orders h of the mesh frequency
         → the housing's forced response: one way (the bearing forces of the gearbox on rigid
           supports put on the housing's seats, :func:`jaxgear.acoustics.seat_forces` and
           :func:`jaxgear.acoustics.housing_response`), or coupled (a scene that carries the
           housing, :class:`jaxgear.scenes.Housing`: its condensed coordinates among the
           scene's)
         → the outward normal velocity v_n of the housing's skin facets at each speed and order
         → the power: the ERP ½ ρ c Σ_f |v_n,f|² A_f, or the radiated sound power
           W = ‖Lᴴ v‖² from the cached radiation resistance R ≈ L Lᴴ of the radiating surface at
           that frequency, or interpolated log-log between R at a grid of frequencies
           (:func:`fem_prep.acoustics.radiation_resistance`, computed once before the design
           loop: the loop never calls the boundary elements).

At each speed s the orders' powers are summed, each weighted by the A weighting of its frequency
(IEC 61672-1) when ``a_weighted`` (the overall dB(A) power), else as they are; a statistic over
the speeds (:class:`~optimise.Max`, :class:`~optimise.Mean`: the energy mean, or
:class:`~optimise.Quantile`) reduces them to one number (W), scaled by the unmodified design's.

The model's damping matrix is the one :func:`jaxgear.dynamics.dynamic_model` built for the design
it was given (held fixed, as :class:`~jaxgear.dynamics.DynamicModel` holds it under
differentiation); the mesh stiffness, the quasi-static motion and every force are the design's.
"""

from __future__ import annotations

import abc
from typing import ClassVar

import equinox as eqx
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Complex, Float

import jaxgear as jg
from jaxgear.acoustics import (
    HousingAcoustics,
    a_weighting,
    housing_response,
    radiated_power_at,
    radiated_power_low_rank,
    seat_forces,
)
from jaxgear.dynamics import (
    AbstractWhineMethod,
    DynamicModel,
    HarmonicBalance,
    TransmissionErrorSource,
    whine_response,
)

from ._objectives import AbstractObjective, AbstractStatistic, Max

__all__ = [
    "AbstractAcousticObjective",
    "AcousticPath",
    "EquivalentRadiatedPower",
    "RadiatedSoundPower",
    "SurfaceRadiation",
]

MAX_SPEED = 1e5  # rad/s


def _speeds(s) -> Float[Array, " S"]:
    return jnp.asarray(np.asarray(s, dtype=float).reshape(-1))


def _grid(g) -> Float[Array, " G"] | None:
    return None if g is None else jnp.asarray(np.asarray(g, dtype=float))


def _default_method() -> HarmonicBalance:
    return HarmonicBalance(8)


def _housing_offset(scene) -> int | None:
    """The first coordinate of the housing a scene carries (its first seat's node, the
    condensed coordinates following in order), or None."""
    structure = getattr(scene, "structure", None)
    for name, first in getattr(structure, "nodes", ()):
        if str(name).startswith("housing "):
            return int(first)
    return None


class AcousticPath(eqx.Module):
    """The chain from a design to the housing's surface velocity: a lumped gearbox, its housing,
    the speeds and orders (the module docstring).

    Attributes:
        model: the lumped :class:`~jaxgear.dynamics.DynamicModel` of the gearbox at the design
            torque (:func:`jaxgear.dynamics.dynamic_model`, or
            :func:`jaxgear.io.build_dynamic_model` of a case; its damping is held; the design's
            modifications replace its ``mods``).
        housing: the housing's :class:`~jaxgear.acoustics.HousingAcoustics` (its skin and, one
            way, its loss factor).
        speeds: pinion speeds Ω (rad/s), (S,), each in (0, 1e5].
        orders: the harmonics h of the mesh frequency whose powers count (static ints in
            [1, H], H the method's harmonics).
        method: the whine's :class:`~jaxgear.dynamics.HarmonicBalance` (default H = 8) or
            :class:`~jaxgear.dynamics.TransmissionErrorSource`.
        positions: positions per mesh period of the whine's static solve (static int >= 4H + 1).
        seats, axes: one way: each bearing force component's seat index and axis
            (:func:`jaxgear.acoustics.seat_forces`; the scene's ``reaction_names`` work as axes);
            None: coupled (the model's scene carries the housing,
            :class:`jaxgear.scenes.Housing`: its condensed coordinates from its first seat's
            node ``housing <seat>`` on).
        rotation: one way: the (3, 3) rotation from the gear model's axes to the housing's, as a
            nested tuple (static), or None.

    Raises:
        ValueError: a speed outside (0, 1e5] rad/s, an order outside [1, H], too few positions,
            seats without axes (or of another length than the bearing forces), a coupled scene
            without a housing of the acoustics' size, a model that is not a lumped
            ``DynamicModel``. TypeError: a housing that is not a ``HousingAcoustics``.
    """

    model: DynamicModel
    housing: HousingAcoustics
    speeds: Float[Array, " S"] = eqx.field(converter=_speeds)
    orders: tuple[int, ...] = eqx.field(static=True, default=(1, 2, 3))
    method: AbstractWhineMethod = eqx.field(default_factory=_default_method)
    positions: int = eqx.field(static=True, default=64)
    seats: tuple[int, ...] | None = eqx.field(static=True, default=None)
    axes: tuple | None = eqx.field(static=True, default=None)
    rotation: tuple | None = eqx.field(static=True, default=None)

    def __check_init__(self):
        if not isinstance(self.model, DynamicModel):
            raise ValueError(
                f"model = {type(self.model).__name__}: allowed a lumped jaxgear.dynamics."
                "DynamicModel (dynamic_model of a torsional or lumped 3D scene)"
            )
        if not isinstance(self.housing, HousingAcoustics):
            raise TypeError(
                f"housing = {type(self.housing).__name__}: allowed jaxgear.acoustics."
                "housing_acoustics(...)"
            )
        s = np.asarray(self.speeds)
        if s.size == 0 or not np.all(np.isfinite(s)) or np.any(s <= 0) or np.any(s > MAX_SPEED):
            raise ValueError(
                f"speeds = {s.tolist()} rad/s: allowed pinion speeds in (0, {MAX_SPEED:.0e}]"
            )
        if not isinstance(self.method, AbstractWhineMethod):
            raise ValueError(
                f"method = {self.method!r}: allowed HarmonicBalance(H) or "
                "TransmissionErrorSource(H)"
            )
        H = int(self.method.harmonics)
        o = self.orders
        if (
            not isinstance(o, tuple)
            or not o
            or not all(isinstance(h, int) and not isinstance(h, bool) and 1 <= h <= H for h in o)
        ):
            raise ValueError(f"orders = {o!r}: allowed a tuple of ints in [1, {H}] (H harmonics)")
        if self.positions < 4 * H + 1:
            raise ValueError(f"positions = {self.positions}: allowed >= 4 H + 1 = {4 * H + 1}")
        n_h = self.housing.K.shape[0]
        if self.seats is None:
            first = _housing_offset(self.model.scene)
            if first is None or first + n_h > self.model.scene.mass().shape[0]:
                raise ValueError(
                    "seats = None (coupled): the model's scene must carry the housing "
                    f"(jaxgear.scenes.Housing of {n_h} coordinates); give seats and axes "
                    "for the one-way path"
                )
        else:
            r = len(self.model.scene.reaction_names)
            if self.axes is None or len(self.seats) != r or len(self.axes) != r:
                raise ValueError(
                    f"seats, axes: allowed one each per bearing force component ({r}), got "
                    f"{self.seats!r}, {self.axes!r}"
                )

    @property
    def coupled(self) -> bool:
        """Whether the scene carries the housing (``seats`` None)."""
        return self.seats is None

    def with_design(self, mods: jg.Modifications, torque) -> DynamicModel:
        """The model with the design's modifications and torque (its damping held). A train's
        model (one :class:`~jaxgear.Modifications` per mesh) takes ``mods`` on every mesh: the
        same modification on each gear's loaded flank."""
        t = jnp.asarray(torque, self.model.torque.dtype)
        if isinstance(self.model.mods, tuple) and isinstance(mods, jg.Modifications):
            mods = (mods,) * len(self.model.mods)
        return eqx.tree_at(lambda m: (m.mods, m.torque), self.model, (mods, t))

    def frequencies(self) -> np.ndarray:
        """The frequencies (Hz) of ``orders`` at ``speeds``, (S, O): order h of the mesh
        frequency (what a cached radiation resistance must be computed at)."""
        w = whine_response(
            self.model,
            np.asarray(self.speeds),
            TransmissionErrorSource(max(self.orders)),
            positions=4 * max(self.orders) + 1,
        )
        idx = np.asarray(self.orders)
        return np.asarray(w.frequency)[:, None] * np.asarray(w.orders)[None, idx]

    def surface_velocity(
        self, mods: jg.Modifications, torque, contact: jg.ContactLaw
    ) -> tuple[Float[Array, "S O"], Complex[Array, "S O F"]]:
        """The frequencies f (Hz, (S, O)) and the skin facets' outward normal velocity
        amplitudes v_n (m/s, one-sided, (S, O, F)) of design ``mods`` at ``torque`` (N·m), the
        static solve in the law ``contact``."""
        model = self.with_design(mods, torque)
        w = whine_response(
            model, self.speeds, self.method, positions=self.positions, contact=contact
        )
        idx = jnp.asarray(self.orders)
        freq = w.frequency[:, None] * w.orders[None, idx]
        ac = self.housing
        if self.coupled:
            first, n_h = _housing_offset(model.scene), ac.K.shape[0]
            q = w.coordinates[:, idx, first : first + n_h]  # (S, O, n_h): the housing's
            vn = (2j * jnp.pi * freq)[..., None] * (q @ ac.normal_map.T.astype(q.dtype))
            return freq, vn
        rot = None if self.rotation is None else np.asarray(self.rotation, dtype=float)
        loads = seat_forces(
            w.bearing_force[:, idx], self.seats, self.axes, ac.n_seats, rot
        )
        return freq, housing_response(ac, loads, freq).normal_velocity


class SurfaceRadiation(eqx.Module):
    """The cached radiation of a surface, for :class:`RadiatedSoundPower`: at the acoustic
    path's own frequencies, or at a grid of frequencies that spans them.

    Attributes:
        vertex_map: (n, F): the radiating surface's vertex normal velocities (m/s) from the
            housing skin facets' (:attr:`jaxgear.acoustics.HousingResponse.normal_velocity`).
        factors: complex L with R ≈ L Lᴴ (:attr:`fem_prep.acoustics.RadiationResistance.factors`,
            (kg/s)^½): (S, O, n, r) at each speed's order frequency
            (:meth:`AcousticPath.frequencies`), or (G, n, r) at the grid ``grid_hz``.
        grid_hz: None (``factors`` at the path's frequencies), or (G,) increasing grid
            frequencies (Hz): each order's power is then interpolated log-log between the two
            grid frequencies that bracket it (:func:`jaxgear.acoustics.radiated_power_at`, as
            ``jaxgear run``'s ``[acoustics]`` does); NaN outside the grid, which
            :meth:`RadiatedSoundPower.scale` refuses.

    Raises:
        ValueError: shapes that do not fit.
    """

    vertex_map: Float[Array, "n F"]
    factors: Complex[Array, "S O n r"] | Complex[Array, "G n r"]
    grid_hz: Float[Array, " G"] | None = eqx.field(default=None, converter=_grid)

    def __check_init__(self):
        vm, L, g = self.vertex_map, self.factors, self.grid_hz
        if g is None:
            ok, want = vm.ndim == 2 and L.ndim == 4 and L.shape[2] == vm.shape[0], "(S, O, n, r)"
        else:
            ok = (vm.ndim == 2 and L.ndim == 3 and L.shape[1] == vm.shape[0] and g.ndim == 1
                  and g.shape[0] == L.shape[0])
            want = f"(G, n, r) with G = {g.shape[0] if g.ndim == 1 else g.shape} grid frequencies"
        if not ok:
            raise ValueError(
                f"vertex_map {vm.shape}, factors {L.shape}: allowed (n, F) and {want}"
            )


class AbstractAcousticObjective(AbstractObjective):
    """A power radiated by the housing of a gearbox over the speeds of an
    :class:`AcousticPath` (W), the orders' powers summed at each speed (A-weighted when
    ``a_weighted``), reduced over the speeds by ``statistic`` (default :class:`Max`, the loudest
    speed; :class:`Mean` the energy mean), scaled by the unmodified design's value in exact
    contact. The problem's structure is the path model's scene.
    """

    path: AcousticPath
    statistic: AbstractStatistic = eqx.field(default_factory=Max)
    a_weighted: bool = eqx.field(static=True, default=True)

    units: ClassVar[str] = "W"

    def __check_init__(self):
        if not isinstance(self.path, AcousticPath):
            raise ValueError(f"path = {type(self.path).__name__}: allowed an optimise.AcousticPath")
        if not isinstance(self.statistic, AbstractStatistic):
            raise ValueError(
                f"statistic = {self.statistic!r}: allowed optimise.Max(), Mean() or Quantile(q)"
            )

    @abc.abstractmethod
    def order_powers(self, freq, velocity) -> Float[Array, "S O"]:
        """The power (W) of each speed and order from the skin's normal velocity (S, O, F)."""

    def per_speed(self, mods, torque, contact) -> Float[Array, " S"]:
        """The orders' power summed at each speed (W; A-weighted when ``a_weighted``)."""
        freq, vn = self.path.surface_velocity(mods, torque, contact)
        p = self.order_powers(freq, vn)
        if self.a_weighted:
            p = p * 10.0 ** (a_weighting(freq) / 10.0)
        return jnp.sum(p, axis=-1)

    def at_torque(self, problem, mods, torque, contact):
        return self.statistic(self.per_speed(mods, torque, contact))

    def scale(self, unmodified, torque):
        """The unmodified design's value (W) at ``torque``, exact contact."""
        zero = jg.Modifications()
        return float(self.statistic(self.per_speed(zero, torque, jg.ExactContact())))

    def with_structure(self, change):
        """The objective on its path's model with the scene ``change(scene)`` (the model's
        damping, modes and mean mesh stiffness held: module docstring)."""
        return eqx.tree_at(lambda o: o.path.model.scene, self, change(self.path.model.scene))

    def prepare(self, scene, positions_per_pitch):
        """The path model's scene (``scene`` must be it)."""
        if scene is not self.path.model.scene:
            raise ValueError(
                f"objective = {self.name!r} runs on its path's model: pass path.model.scene as "
                "the structure"
            )
        return scene


class EquivalentRadiatedPower(AbstractAcousticObjective):
    """The housing's equivalent radiated power (W): ½ ρ c Σ_f |v_n,f|² A_f at each speed and
    order (:func:`jaxgear.acoustics.erp`; radiation efficiency 1)."""

    name: ClassVar[str] = "erp"

    def order_powers(self, freq, velocity):
        ac = self.path.housing
        v2 = jnp.real(velocity) ** 2 + jnp.imag(velocity) ** 2
        return 0.5 * ac.density * ac.sound_speed * jnp.einsum("sof,f->so", v2, ac.areas)


class RadiatedSoundPower(AbstractAcousticObjective):
    """The radiated sound power (W) W = ‖Lᴴ v‖² at each speed and order from the cached
    radiation resistance (``radiation``, a :class:`SurfaceRadiation`: v the radiating
    surface's vertex normal velocities, ``vertex_map`` @ v_n)."""

    radiation: SurfaceRadiation = eqx.field(kw_only=True)

    name: ClassVar[str] = "sound_power"

    def __check_init__(self):
        if not isinstance(self.radiation, SurfaceRadiation):
            raise ValueError(
                f"radiation = {type(self.radiation).__name__}: allowed an "
                "optimise.SurfaceRadiation"
            )
        n_s, n_o = self.path.speeds.shape[0], len(self.path.orders)
        if self.radiation.grid_hz is None and self.radiation.factors.shape[:2] != (n_s, n_o):
            raise ValueError(
                f"radiation.factors: {self.radiation.factors.shape[:2]} frequencies, allowed "
                f"(S, O) = ({n_s}, {n_o}), the path's speeds and orders"
            )
        if self.radiation.vertex_map.shape[1] != self.path.housing.areas.shape[0]:
            raise ValueError(
                f"radiation.vertex_map: {self.radiation.vertex_map.shape[1]} facets, allowed the "
                f"housing skin's {self.path.housing.areas.shape[0]}"
            )

    def order_powers(self, freq, velocity):
        rad = self.radiation
        v = velocity @ rad.vertex_map.T.astype(velocity.dtype)  # (S, O, n)
        if rad.grid_hz is None:
            return radiated_power_low_rank(v, rad.factors)
        # R's convention is e^{-iωt}: the conjugate of the whine's one-sided amplitudes
        return radiated_power_at(jnp.conj(v), freq, rad.factors, rad.grid_hz)

    def scale(self, unmodified, torque):
        """The unmodified design's value (W) at ``torque``, exact contact.

        Raises:
            ValueError: a value that is not finite (a frequency of the path outside the
                radiation's grid)."""
        value = super().scale(unmodified, torque)
        if not np.isfinite(value):
            raise ValueError(
                f"radiation.grid_hz = [{float(self.radiation.grid_hz[0]):.6g}, "
                f"{float(self.radiation.grid_hz[-1]):.6g}] Hz: allowed a grid that spans the "
                "path's order frequencies (AcousticPath.frequencies())"
            )
        return value
