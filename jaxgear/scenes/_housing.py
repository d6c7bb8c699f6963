"""A flexible housing as a body of a lumped 3D scene: the bearings join the shafts to the
housing's seats instead of the ground (docs/housing.md).

The housing is condensed at its bearing seats by Craig–Bampton (:mod:`fem_prep.housing`): its
``h`` coordinates are the seats' 6-DOF masters (u_x, u_y, u_z, φ_x, φ_y, φ_z in the housing's
frame) and its interior fixed-interface modal coordinates, with the condensed stiffness K_h and
mass M_h (the feet clamped). :class:`Housing` places it in the scene's frame (a rotation R and
an offset t: x_scene = R x_housing + t) and gives it a damping C_h.

Coupling. A bearing at the shaft node of DOFs u_s (6) and scene position p, seated in the seat
of centre c (scene frame) and DOFs q (6, housing frame), acts on the relative displacement

    d = u_s − G q,   G = [[R, −S(p − c) R], [0, R]],

S(a) the cross-product matrix (a × ·): the point p moves with the seat as a rigid body,
u_p = R u_c + (R θ) × (p − c). Its energy ½ dᵀ K_b d adds K_b on the shaft node, −K_b G and
−Gᵀ K_b between shaft node and seat, and Gᵀ K_b G on the seat; its damping C_b likewise. The
bearing's force rows (:attr:`~jaxgear.scenes.Structure.reaction`) become K_b[:3] d: the force the
bearing transmits between shaft and housing. With a rigid, massless housing (q = 0) this is the
grounded bearing of :class:`~jaxgear.scenes.Bearing` exactly. A shaft whose coordinates are
taken in a frame turned by φ about z (a hybrid scene's condensed body's shaft, at its body
frame's angle at θ = 0) sees the seat through Q(φ)ᵀ G (its axisymmetric bearing acts in its own
frame; :func:`~jaxgear.scenes._mount.couple_housing`'s ``frames``).

Source: Craig & Bampton, AIAA J. 6 (1968); the seat coupling is the rigid-link (RBE2) relation of
the condensed bodies' bearing masters (:func:`fem_prep.couple_masters`).
"""

from __future__ import annotations

import math

import equinox as eqx
import jax.numpy as jnp
import numpy as np
import scipy.linalg as sla
from jaxtyping import Array, Float

__all__ = [
    "BAND_RTOL",
    "HOUSING_BAND",
    "Housing",
    "band_cutoff_hz",
    "band_holds",
    "band_speed_limit",
    "bearing_positions",
    "housing_band_hz",
]

#: a condensed housing's band: its response holds the frequencies up to f_c / HOUSING_BAND, f_c
#: the condensation's cut-off (docs/housing.md, "What the condensation keeps": the truncation
#: error grows as (f/f_k)² / (1 − (f/f_k)²) towards the first dropped mode f_k > f_c; the default
#: cut-off, :func:`fem_prep.housing.housing_cutoff_hz`, is this factor times the highest
#: mesh-order frequency, so that band holds every frequency the meshes excite)
HOUSING_BAND = 1.5
#: the relative round-off :func:`band_holds` allows a cut-off below HOUSING_BAND × f (a
#: cut-off derived as HOUSING_BAND × f from f itself holds f)
BAND_RTOL = 1e-12


def housing_band_hz(cutoff_hz: float) -> float:
    """f_b = f_c / :data:`HOUSING_BAND` (Hz): the top of the band a housing condensed with the
    cut-off ``cutoff_hz`` (Hz) holds; the orders above it meet the housing's modes beyond the
    cut-off, which the condensation leaves out."""
    return float(cutoff_hz) / HOUSING_BAND


def band_cutoff_hz(frequency_hz: float) -> float:
    """The least cut-off (Hz) whose band holds ``frequency_hz`` (Hz): :data:`HOUSING_BAND` × f."""
    return HOUSING_BAND * float(frequency_hz)


def band_holds(cutoff_hz: float, frequency_hz: float) -> bool:
    """Whether the band of a housing condensed with the cut-off ``cutoff_hz`` (Hz) holds the
    frequency ``frequency_hz`` (Hz): f_c >= :func:`band_cutoff_hz` (f) up to
    :data:`BAND_RTOL`. The rule a housed model's inputs are refused by where the housing's
    modes a frequency excites would be missing from the model."""
    return float(cutoff_hz) >= band_cutoff_hz(frequency_hz) * (1 - BAND_RTOL)


def band_speed_limit(cutoff_hz: float, mesh_orders) -> float:
    """Ω_b = 2π f_b / max_k |o_k| (rad/s): the highest input speed at which every mesh's
    order-1 frequency lies in the band f_b (:func:`housing_band_hz`) of a housing condensed
    with the cut-off ``cutoff_hz`` (Hz); ``mesh_orders``: each mesh's order o_k (its teeth per
    input turn; a carrier-frame order for a planetary stage), not all zero."""
    order = max(abs(float(o)) for o in mesh_orders)
    return 2 * math.pi * housing_band_hz(cutoff_hz) / order

#: a seat's six coordinates, in the housing's frame (m, rad): the names' last word (the lumped
#: scenes' node DOFs' spelling)
_SEAT_DOFS = ("u_x", "u_y", "u_z", "phi_x", "phi_y", "phi_z")


def _skew(a) -> np.ndarray:
    x, y, z = a
    return np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])


def _turn_z(phi: float) -> np.ndarray:
    """Q(φ) (6, 6): the rotation by φ (rad) about +z on a node's translations and rotation
    vector."""
    c, s = math.cos(phi), math.sin(phi)
    r = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    return np.kron(np.eye(2), r)


def _rotation(value) -> np.ndarray:
    R = np.eye(3) if value is None else np.asarray(value, dtype=float)
    if (
        R.shape != (3, 3)
        or not np.all(np.isfinite(R))
        or not np.allclose(R @ R.T, np.eye(3), atol=1e-9)
        or not np.linalg.det(R) > 0
    ):
        raise ValueError(
            f"Housing: rotation = {value!r}, allowed a proper rotation matrix (3, 3) "
            "(R Rᵀ = I, det R = +1)"
        )
    return R


class Housing(eqx.Module):
    """A condensed housing placed in a scene's frame, with its damping (build with :meth:`of`).

    Attributes:
        K, M: the condensed stiffness (SI per coordinate pair) and mass (kg, kg·m²), (h, h);
            rows ``6 s .. 6 s + 5`` seat ``s``'s master (u_x, u_y, u_z (m), φ_x, φ_y, φ_z
            (rad), housing frame), then the interior modal coordinates.
        C: the damping (units of K·s), (h, h): modal, ζ_k = η/2 on each free-seat mode k of
            (K, M) (:meth:`of`), the viscous equivalent of the loss factor η at resonance.
        seat_positions: static, the seats' centres in the scene frame (m), ((x, y, z), ...).
        rotation: static, R (3 × 3 nested tuple): housing frame → scene frame.
        seat_names: static, the seats' labels.
        modes_hz: static, the kept fixed-interface modes' frequencies (Hz).
        cutoff_hz: static, the condensation's cut-off (Hz).
    """

    K: Float[Array, "h h"]
    M: Float[Array, "h h"]
    C: Float[Array, "h h"]
    seat_positions: tuple = eqx.field(static=True)
    rotation: tuple = eqx.field(static=True)
    seat_names: tuple = eqx.field(static=True)
    modes_hz: tuple = eqx.field(static=True, default=())
    cutoff_hz: float = eqx.field(static=True, default=math.inf)

    @property
    def size(self) -> int:
        """h, the housing's coordinates."""
        return self.K.shape[0]

    @property
    def band_hz(self) -> float:
        """The top of the band its condensed response holds (Hz, :func:`housing_band_hz` of
        ``cutoff_hz``; inf without a cut-off)."""
        return housing_band_hz(self.cutoff_hz)

    @property
    def n_seats(self) -> int:
        return len(self.seat_names)

    @classmethod
    def of(
        cls,
        condensed,
        *,
        loss_factor: float = 0.0,
        rotation=None,
        offset=(0.0, 0.0, 0.0),
    ) -> Housing:
        """The housing of a condensed housing (:class:`fem_prep.housing.CondensedHousing`: its
        ``K``, ``M``, ``seat_positions``, ``seat_names``, ``modes_hz`` and ``cutoff_hz``),
        placed by x_scene = R x_housing + ``offset``.

        Args:
            condensed: the condensed housing (seat masters first, in its own frame, m).
            loss_factor: η >= 0: modal damping C = M Φ diag(η ω_k) Φᵀ M on the free-seat
                modes Φ (mass-normalised) of (K, M), ζ_k = η/2.
            rotation: R (3, 3), housing frame → scene frame (None: the identity).
            offset: t (3,) (m).

        Raises:
            ValueError/TypeError: a negative loss factor, R not a proper rotation, an offset
                not 3 finite numbers, K and M not square of equal size or smaller than the
                seats' DOFs.
        """
        if isinstance(loss_factor, bool) or not isinstance(loss_factor, (int, float)):
            raise TypeError(f"Housing: loss_factor = {loss_factor!r}, allowed a number >= 0")
        if not (math.isfinite(loss_factor) and loss_factor >= 0):
            raise ValueError(f"Housing: loss_factor = {loss_factor!r}, allowed >= 0")
        R = _rotation(rotation)
        t = np.asarray(offset, dtype=float)
        if t.shape != (3,) or not np.all(np.isfinite(t)):
            raise ValueError(f"Housing: offset = {offset!r}, allowed 3 finite numbers (m)")
        K, M = np.asarray(condensed.K, float), np.asarray(condensed.M, float)
        names = tuple(str(s) for s in condensed.seat_names)
        if (
            K.ndim != 2
            or K.shape[0] != K.shape[1]
            or K.shape != M.shape
            or K.shape[0] < 6 * len(names)
        ):
            raise ValueError(
                f"Housing: K {K.shape} and M {M.shape}, allowed square, equal, >= 6 per seat "
                f"({6 * len(names)})"
            )
        K, M = 0.5 * (K + K.T), 0.5 * (M + M.T)
        C = np.zeros_like(K)
        if loss_factor > 0:
            lam, phi = sla.eigh(K, M)
            MP = M @ phi
            C = MP @ np.diag(loss_factor * np.sqrt(np.maximum(lam, 0.0))) @ MP.T
        seats = np.asarray(condensed.seat_positions, float).reshape(-1, 3) @ R.T + t
        return cls(
            K=jnp.asarray(K),
            M=jnp.asarray(M),
            C=jnp.asarray(C),
            seat_positions=tuple(tuple(float(x) for x in p) for p in seats),
            rotation=tuple(tuple(float(x) for x in r) for r in R),
            seat_names=names,
            modes_hz=tuple(float(f) for f in np.asarray(condensed.modes_hz)),
            cutoff_hz=float(condensed.cutoff_hz),
        )

    def coordinate_names(self) -> tuple[str, ...]:
        """The name of each of the h coordinates, in order: ``"housing <seat> <dof>"`` per
        seat (``<seat>`` its name in :attr:`seat_names`, ``<dof>`` u_x, u_y, u_z (m), phi_x,
        phi_y, phi_z (rad), housing frame: a lumped scene's node DOFs), then
        ``"housing mode <k>"`` (k = 1 .. h − 6 n_seats) per interior modal coordinate.
        Returns a tuple of h strings. The one spelling of the
        housing's coordinates wherever they are named: a scene's structure nodes
        (``"housing <seat>"``, its seat's first coordinate), a housed planetary stage's
        ``dof_names`` and the coupled gearbox's ``coordinate_names``."""
        seats = tuple(f"housing {name} {d}" for name in self.seat_names for d in _SEAT_DOFS)
        return seats + tuple(f"housing mode {k + 1}" for k in range(self.size - len(seats)))

    def seat_transform(self, seat: int, point) -> np.ndarray:
        """G (6, 6) of the module docstring: the scene-frame motion (u, θ) of the point
        ``point`` (3,) (m, scene frame) rigidly attached to seat ``seat``, per unit seat
        coordinate (housing frame)."""
        R = np.asarray(self.rotation)
        c = np.asarray(self.seat_positions[seat])
        G = np.zeros((6, 6))
        G[:3, :3] = R
        G[3:, 3:] = R
        G[:3, 3:] = -_skew(np.asarray(point, float) - c) @ R
        return G

    def seat_spring(self, seat: int, point, stiffness, frame: float = 0.0) -> tuple:
        """The blocks of a spring K_b (6, 6) (SI per coordinate pair) between a node u (6: its
        translations and rotation vector, in a frame turned by ``frame`` φ (rad) about +z from
        the scene frame) at ``point`` (3,) (m, scene frame) and seat ``seat``'s coordinates q
        (6): the energy ½ dᵀ K_b d of d = u − Q(φ)ᵀ G q (module docstring) is
        ``½ [u; q]ᵀ [[A, B], [Bᵀ, D]] [u; q]`` with (A, B, D) = (K_b, −K_b G', G'ᵀ K_b G'),
        G' = Q(φ)ᵀ G. Returns (A, B, D, G'), each (6, 6). The one seat coupling of the lumped,
        hybrid and planetary scenes (a damping C_b takes the same blocks)."""
        G = self.seat_transform(seat, point)
        if frame:
            G = _turn_z(-float(frame)) @ G  # Q(φ)ᵀ G: the seat seen from the node's frame
        a = np.asarray(stiffness, float)
        return a, -a @ G, G.T @ a @ G, G

    def nearest_seat(self, point) -> int:
        """The seat whose centre is nearest ``point`` (3,) (m, scene frame)."""
        d = np.linalg.norm(np.asarray(self.seat_positions) - np.asarray(point, float), axis=1)
        return int(np.argmin(d))


def bearing_positions(shafts, centres, gear_z) -> list[list[np.ndarray]]:
    """The scene-frame position (m) of every bearing, shaft after shaft in each shaft's bearing
    order: shaft i's axis runs along +z through ``centres[i]`` (the centre of its first gear,
    (3,)), its position ``s`` along the shaft (m from its start) at z = centre_z + s −
    ``gear_z[i]`` (that gear's position along the shaft).

    Args:
        shafts: the :class:`~jaxgear.scenes.ShaftSpec` of each shaft. centres: (n_shafts, 3) (m).
        gear_z: (n_shafts,) (m).

    Returns:
        per shaft, a list of (3,) positions.
    """
    out = []
    for spec, c, g in zip(shafts, centres, gear_z, strict=True):
        c = np.asarray(c, float)
        out.append([c + np.array([0.0, 0.0, b.z - float(g)]) for b in spec.bearings])
    return out
