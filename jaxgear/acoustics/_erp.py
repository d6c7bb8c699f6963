"""The housing's forced vibration at its outer surface and its equivalent radiated power (ERP)
from the bearing forces at its seats (docs/whine.md, "Housing and ERP"): a one-way path (the
housing loaded by the forces of a gearbox on rigid supports), which the coupled model reuses
with its own seat forces.

At a frequency f (ω = 2πf) the condensed housing (Craig–Bampton at its seats,
:func:`fem_prep.housing.condensed_housing`) with a structural loss factor η answers the seat
forces F_b (6 per seat: forces, N, and moments, N·m) by

    (K (1 + iη) − ω² M) q = Eᵀ F_b,      u = Φ q,      v_n = iω N u,

solved on the condensed housing's modes (exact: K (1 + iη) and M share them), Φ the recovery
of the full FE displacement, N the facets' mean outward normal
(:func:`fem_prep.housing.outer_surface`), and the ERP, the power a surface vibrating with v_n
would radiate if every part of it radiated as a plane wave (radiation efficiency 1: close to the
radiated power above the coincidence frequency, an overestimate below it),

    P = ½ ρ c ∫_skin |v_n|² dS   (W; one-sided amplitudes v_n: v(t) = Re v_n e^{iωt}),

the integral exact for the elements' shape functions (quadratic on Tet10:
``HousingSurface.square_operator``; the facet means' Σ_f |v̄_n,f|² A_f, :func:`erp`, is lower,
2–3 % on the embedded housings' 40 mm cells, because a mean squared is not the mean square),

L_W = 10 log10(P / 1 pW) dB. Source: the ERP and its limits as compared in Fritze, Marburg &
Hardtke, "Estimation of radiated sound power: a case study on common approximation methods",
Acta Acustica united with Acustica 95 (2009).
"""

from __future__ import annotations

import math

import equinox as eqx
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Complex, Float

from fem_prep.acoustics import AIR

from ._power import sound_power_level

__all__ = [
    "HousingAcoustics",
    "HousingResponse",
    "erp",
    "housing_acoustics",
    "housing_response",
    "housing_vibration",
    "seat_forces",
    "total_level",
]

def erp(
    normal_velocity, areas, density: float = AIR.density, sound_speed: float = AIR.sound_speed
):
    """The equivalent radiated power P = ½ ρ c Σ_f |v_f|² A_f (W) of one-sided complex normal
    velocity amplitudes ``normal_velocity`` (m/s, (..., F)) on facets of ``areas`` (m², (F,)):
    the time mean of a harmonic velocity Re(v e^{iωt}) squared is ½|v|². Exact for a velocity
    constant on each facet; :func:`housing_vibration` integrates |v_n|² of the FE field
    itself (the module's note).

    Args:
        density: ρ of the fluid (kg/m³; default :data:`fem_prep.acoustics.AIR`'s 1.21).
        sound_speed: c (m/s; default AIR's 343).

    Returns:
        (...) W.
    """
    v = jnp.asarray(normal_velocity)
    v2 = jnp.abs(v) ** 2
    return 0.5 * density * sound_speed * jnp.einsum("...f,f->...", v2, jnp.asarray(areas))


class HousingAcoustics(eqx.Module):
    """A condensed housing ready for its forced response (:func:`housing_acoustics`).

    Attributes:
        K, M: the condensed stiffness and mass (n_c, n_c), seat DOFs first (6 per seat).
        eigenvalues: λ_k = ω_k² (rad²/s²) of (K, M), (n_c,) (the housing on its feet).
        shapes: Φ (n_c, n_c), mass-normalised (Φᵀ M Φ = I): with the structural damping
            K (1 + iη) the response is modal exactly, q = Φ diag(1 / ((1 + iη) λ − ω²)) Φᵀ F.
        normal_map: (F, n_c): each skin facet's mean outward normal displacement (m) per
            condensed coordinate.
        point_map: (P, n_c): the named points' outward normal displacement per coordinate.
        areas: (F,) facet areas (m²).
        square_map: (n_c, n_c) B with ‖B q‖² = ∫_skin |u·n|² dS (m⁴) of u = Φ q, exact for
            the elements' shape functions (the R of a QR of ``square_operator`` Φ).
        loss_factor: η of the housing's structural damping.
        density, sound_speed: ρ (kg/m³) and c (m/s) of the fluid.
        n_seats: seats (static). point_names: labels (static).
    """

    K: Float[Array, "n n"]
    M: Float[Array, "n n"]
    eigenvalues: Float[Array, " n"]
    shapes: Float[Array, "n n"]
    normal_map: Float[Array, "F n"]
    point_map: Float[Array, "P n"]
    areas: Float[Array, " F"]
    square_map: Float[Array, "n n"]
    loss_factor: Float[Array, ""]
    density: Float[Array, ""]
    sound_speed: Float[Array, ""]
    n_seats: int = eqx.field(static=True)
    point_names: tuple[str, ...] = eqx.field(static=True, default=())


def _check_positive(name, value, unit, zero=False):
    ok = isinstance(value, (int, float, np.floating)) and not isinstance(value, bool)
    if not ok or not math.isfinite(value) or (value < 0 if zero else value <= 0):
        raise ValueError(f"{name} = {value!r}: allowed a number {'>=' if zero else '>'} 0 {unit}")


def housing_acoustics(
    condensed,
    surface,
    *,
    loss_factor: float = 0.02,
    density: float = AIR.density,
    sound_speed: float = AIR.sound_speed,
    dtype=None,
) -> HousingAcoustics:
    """Gather a condensed housing and its skin for :func:`housing_response`.

    Args:
        condensed: a :class:`fem_prep.housing.CondensedHousing` (K, M, recovery, seat names).
        surface: its mesh's :func:`fem_prep.housing.outer_surface` (the same mesh: the
            recovery's rows are its DOFs).
        loss_factor: η >= 0, the housing's structural damping (K (1 + iη); 0.02: a
            cast-iron or aluminium casing with its joints, about 1 % of critical damping).
        density, sound_speed: the fluid's ρ (kg/m³) and c (m/s), > 0 (air at 20 °C).
        dtype: float dtype (None: JAX's default float).

    Returns:
        :class:`HousingAcoustics`.

    Raises:
        ValueError: a surface of another mesh, a negative loss factor, ρ or c <= 0.
    """
    _check_positive("loss_factor", loss_factor, "", zero=True)
    _check_positive("density", density, "kg/m^3")
    _check_positive("sound_speed", sound_speed, "m/s")
    rec = np.asarray(condensed.recovery)
    if surface.normal_operator.shape[1] != rec.shape[0]:
        raise ValueError(
            f"surface: {surface.normal_operator.shape[1]} DOFs, condensed housing of "
            f"{rec.shape[0]}: allowed the outer_surface of the condensed housing's own mesh"
        )
    dtype = jnp.zeros(()).dtype if dtype is None else dtype
    pop = surface.point_operator
    pmap = np.zeros((0, rec.shape[1])) if pop is None else pop @ rec
    import scipy.linalg as sla  # the modes once, at construction (the housing is NumPy's)
    import scipy.sparse as sp

    lam, phi = sla.eigh(np.asarray(condensed.K), np.asarray(condensed.M))
    sq = surface.square_operator
    if sq is None:  # a surface without it: the facet means
        sq = sp.diags(np.sqrt(np.asarray(surface.areas))) @ surface.normal_operator
    square = np.linalg.qr(np.asarray(sq @ rec), mode="r")  # ‖R q‖ = ‖S Φ q‖
    return HousingAcoustics(
        K=jnp.asarray(condensed.K, dtype),
        M=jnp.asarray(condensed.M, dtype),
        eigenvalues=jnp.asarray(lam, dtype),
        shapes=jnp.asarray(phi, dtype),
        normal_map=jnp.asarray(surface.normal_operator @ rec, dtype),
        point_map=jnp.asarray(pmap, dtype),
        areas=jnp.asarray(surface.areas, dtype),
        square_map=jnp.asarray(square, dtype),
        loss_factor=jnp.asarray(loss_factor, dtype),
        density=jnp.asarray(density, dtype),
        sound_speed=jnp.asarray(sound_speed, dtype),
        n_seats=len(condensed.seat_names),
        point_names=tuple(surface.point_names),
    )


def seat_forces(bearing_force, seats, axes, n_seats: int, rotation=None) -> Complex[Array, "... s"]:
    """The seat loads (..., 6 n_seats) of bearing force components (..., r): component j (N;
    the force the shaft puts on its support, ``R X`` of a lumped 3D scene:
    :attr:`~jaxgear.dynamics.WhineResponse.bearing_force`, names in the scene's
    ``reaction_names``) added to the force along axis ``axes[j]`` of seat ``seats[j]``; the
    moments stay zero (each bearing at its seat's centre).

    Args:
        bearing_force: (..., r), real or complex.
        seats: r seat indices (ints 0..n_seats − 1; a seat may take several bearings).
        axes: r axes of the gear model's frame: 0, 1, 2 or "x", "y", "z", or a reaction name
            ending in "Fx", "Fy", "Fz" (a scene's ``reaction_names``).
        n_seats: the housing's seats.
        rotation: None, or the (3, 3) matrix from the gear model's axes to the housing's.

    Raises:
        ValueError: lengths that differ from r, a seat index or an axis out of range.
    """
    f = jnp.asarray(bearing_force)
    r = f.shape[-1]
    seats = tuple(int(s) for s in seats)
    axes = tuple(axes)
    if len(seats) != r or len(axes) != r:
        raise ValueError(
            f"seats, axes: {len(seats)} and {len(axes)} entries for {r} force components: "
            "allowed one each per component"
        )
    bad = [s for s in seats if not 0 <= s < n_seats]
    if bad:
        raise ValueError(f"seats = {seats}: allowed indices 0..{n_seats - 1}")

    def axis(a):
        k = "xyz".find(a[-1].lower()) if isinstance(a, str) and a else a
        if isinstance(k, bool) or k not in (0, 1, 2):
            raise ValueError(f"axes: {a!r}, allowed 0, 1, 2, 'x', 'y', 'z' or a name ending Fx")
        return k

    S = np.zeros((n_seats, 3, r))
    for j, (s, a) in enumerate(zip(seats, axes, strict=True)):
        S[s, axis(a), j] = 1.0
    real = f.real.dtype
    g = jnp.einsum("sij,...j->...si", jnp.asarray(S, real), f)  # (..., n_seats, 3)
    if rotation is not None:
        g = jnp.einsum("ij,...sj->...si", jnp.asarray(rotation, real), g)
    out = jnp.concatenate([g, jnp.zeros_like(g)], axis=-1)  # forces, then zero moments
    return out.reshape(*g.shape[:-2], 6 * n_seats)


class HousingResponse(eqx.Module):
    """The housing's steady response to seat loads at frequencies (..., one per order and
    speed), one-sided complex amplitudes (q(t) = Re q e^{iωt}).

    Attributes:
        frequency: f (Hz), (...).
        coordinates: q (..., n_c): the condensed coordinates (seat DOFs, m / rad, then the
            modal amplitudes; :func:`fem_prep.housing.write_housing_ods_vtu` draws them).
        normal_velocity: v_n (m/s), (..., F): each skin facet's mean outward normal velocity.
        point_velocity: (m/s), (..., P): at the named points.
        power: ERP (W), (...). level: its L_W (dB re 1 pW), (...).
    """

    frequency: Float[Array, ...]
    coordinates: Complex[Array, "... n"]
    normal_velocity: Complex[Array, "... F"]
    point_velocity: Complex[Array, "... P"]
    power: Float[Array, ...]
    level: Float[Array, ...]


def total_level(power, axis=-1):
    """The overall L_W (dB re 1 pW) of powers summed over ``axis`` (the orders)."""
    return sound_power_level(jnp.sum(jnp.asarray(power), axis=axis))


def housing_response(acoustics: HousingAcoustics, loads, frequency) -> HousingResponse:
    """The housing's vibration and ERP under seat loads (the module's equations).

    Args:
        acoustics: :func:`housing_acoustics`.
        loads: seat loads F_b (..., 6 n_seats), complex one-sided amplitudes (N, N·m), the
            seats' DOF order (u_x, u_y, u_z, θ_x, θ_y, θ_z per seat; :func:`seat_forces`).
        frequency: f (Hz) >= 0 of each load, broadcastable to loads' leading shape (a whine
            sweep's order frequencies: ``w.frequency[:, None] * w.orders[None, :]``).

    Returns:
        :class:`HousingResponse` with the loads' leading shape.

    Raises:
        TypeError: not a HousingAcoustics. ValueError: loads of another seat count.
    """
    if not isinstance(acoustics, HousingAcoustics):
        raise TypeError(f"acoustics = {acoustics!r}: allowed housing_acoustics(...)")
    F = jnp.asarray(loads)
    nb = 6 * acoustics.n_seats
    if F.shape[-1] != nb:
        raise ValueError(
            f"loads: {F.shape[-1]} per frequency, allowed 6 n_seats = {nb} (forces and moments)"
        )
    lead = F.shape[:-1]
    f = jnp.broadcast_to(jnp.asarray(frequency, acoustics.K.dtype), lead)
    cdt = jnp.result_type(acoustics.K.dtype, jnp.complex64)
    phi = acoustics.shapes
    lam = acoustics.eigenvalues * (1 + 1j * acoustics.loss_factor)
    w2 = (2 * jnp.pi * f)[..., None] ** 2
    lam = lam.reshape((1,) * (w2.ndim - 1) + lam.shape)
    modal = (F.astype(cdt) @ phi[:nb].astype(cdt)) / (lam - w2)  # Φ_bᵀ F / ((1 + iη) λ − ω²)
    return housing_vibration(acoustics, modal @ phi.T.astype(cdt), f)


def housing_vibration(acoustics: HousingAcoustics, coordinates, frequency) -> HousingResponse:
    """The housing's surface vibration and ERP of its condensed coordinates q at frequencies:
    v_n = iω N Φ q at every skin facet (its mean) and at the named points, and the ERP
    P = ½ ρ c ∫ |v_n|² dS = ½ ρ c ω² ‖B q‖² (the module's equations, B ``square_map``). :func:`housing_response` solves q from seat loads (the one-way path);
    a coupled model's response holds q itself: the housing's coordinates of a lumped 3D scene
    with a :class:`~jaxgear.scenes.Housing` (``WhineResponse.coordinates[..., n0:n0 + n_c]``,
    n0 the structure's ``housing <first seat>`` node), in the condensed housing's own order
    and frame.

    Args:
        acoustics: :func:`housing_acoustics`.
        coordinates: q (..., n_c), one-sided complex amplitudes (m, rad, modal amplitudes).
        frequency: f (Hz) >= 0, broadcastable to q's leading shape.

    Returns:
        :class:`HousingResponse` with q's leading shape.

    Raises:
        TypeError: not a HousingAcoustics. ValueError: q of another size than n_c.
    """
    if not isinstance(acoustics, HousingAcoustics):
        raise TypeError(f"acoustics = {acoustics!r}: allowed housing_acoustics(...)")
    n_c = acoustics.K.shape[0]
    q = jnp.asarray(coordinates)
    if q.ndim == 0 or q.shape[-1] != n_c:
        raise ValueError(
            f"coordinates: shape {q.shape}, allowed (..., {n_c}) (the condensed coordinates)"
        )
    cdt = jnp.result_type(acoustics.K.dtype, jnp.complex64)
    q = q.astype(cdt)
    f = jnp.broadcast_to(jnp.asarray(frequency, acoustics.K.dtype), q.shape[:-1])
    iw = (2j * jnp.pi * f)[..., None]
    vn = iw * (q @ acoustics.normal_map.T.astype(cdt))
    vp = iw * (q @ acoustics.point_map.T.astype(cdt))
    bq = iw * (q @ acoustics.square_map.T.astype(cdt))
    p = 0.5 * acoustics.density * acoustics.sound_speed * jnp.sum(
        jnp.real(bq) ** 2 + jnp.imag(bq) ** 2, axis=-1
    )
    return HousingResponse(
        frequency=f,
        coordinates=q,
        normal_velocity=vn,
        point_velocity=vp,
        power=p,
        level=sound_power_level(p),
    )
