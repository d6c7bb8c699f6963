"""The ring gear of a planetary stage as a rigid member or as a flexible condensed body, and the
resonance rule of its nodal-diameter modes under the planets' moving mesh forces
(docs/planetary.md, "A flexible ring gear" and "Which ring modes the planets excite").

A flexible ring adds, to the lumped model's rigid ring, the ring's elastic displacement at each
ring–planet contact: the planets move around the ring as the carrier turns, so the compliance
that couples the N ring meshes depends on the carrier position. With the ring's static in-plane
compliance ``F`` at its Z tooth stations (``fem_prep.ring_master_compliance`` of a ring condensed
on its root-patch masters), planet n at the angle ``phi_n`` of the ring's frame and the direction
``e_n`` of its mesh force on the ring, the ring meshes' compliance is

    C_nm = sum_(k, k') W_nk W_mk' e_n^T F_kk' e_m            (m/N, N x N),

``W_nk`` the stations' linear hats at ``phi_n`` (the interpolation the rim masters carry). Each
ring mesh's approach loses the ring's displacement there, ``w_n = sum_m C_nm P_m`` (P_m the
transverse ring-mesh forces, N): the contact problem gains N coordinates w with the stiffness
``C^-1`` and the ring cells' rows ``-cos(beta_b)`` on their planet's w.

In the dynamics (:func:`jaxgear.planetary.planetary_dynamics`) the ring keeps its 2Z station
displacements u (the ring frame's x, y at each station) as coordinates of constant stiffness
``F^-1`` (and, given, the stations' mass: the ring's nodal-diameter modes), and the ring cells'
rows gain ``-cos(beta_b) E_n`` with ``E_n = sum_k W_nk e_n^T`` on station k: the carrier angle
moves the rows, not the ring's matrices. Eliminating u statically gives back ``w = C P``.
The ring's coordinates live in the ring's frame: with the ring held they are inertial (no
Coriolis or centripetal terms), and only the contacts move around them. Each step the ring cells
reach only the two stations about each planet (:meth:`CondensedRing.window`): the dynamics solve
the contact on that window of coordinates (the cell space of :func:`jaxgear.dynamics.newmark`).

With ``modes`` (and the mass) the ring's coordinates are its m lowest modes of (M_u, F^-1) plus
the static correction of the ring's residual flexibility ``F - Phi_m Lambda_m^-1 Phi_m^T``
(the mode-acceleration method, R. R. Craig & A. J. Kurdila, *Fundamentals of Structural
Dynamics*, 2nd ed., 2006, §14.5; the basis of :mod:`jaxgear.dynamics._modal_basis`), integrated
by :func:`jaxgear.dynamics.newmark_modal`: exact in statics at any m, the station model with
every mode.

The station mass reduces the condensed ring statically onto its stations (Guyan): the ring's
motion between and behind the stations follows them, and its nodal-diameter modes come from
above. :class:`CraigBamptonRing` adds the condensed ring's own dynamics inside the stations: its
fixed-interface modes eta (the stations held) as coordinates that carry mass and stiffness and
no contact (Craig & Bampton 1968 with the stations as the interface;
``fem_prep.ring_craig_bampton``): the same statics, the ring's nodal-diameter frequencies
converging to the condensed FE ring's own as the kept modes grow.
"""

from __future__ import annotations

import abc
import math

import equinox as eqx
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Float

from fem_prep import RingStations

from .._util import as_float, check_integer, check_real, static_correction

__all__ = [
    "AbstractRingModel",
    "CondensedRing",
    "CraigBamptonRing",
    "RigidRing",
    "ring_contact_angles",
    "ring_excitation",
    "ring_resonances",
]


def modal_damping(M, K, ratio) -> Float[Array, "m m"]:
    """C = M Phi diag(2 zeta omega) Phi^T M (N s/m, (m, m)) on the modes Phi (mass-normalised)
    of (M, K), M positive definite (seed (2.35))."""
    low = jnp.linalg.cholesky(M)
    a = jnp.linalg.solve(low, jnp.linalg.solve(low, K).T)
    lam, vec = jnp.linalg.eigh(0.5 * (a + a.T))
    phi = jnp.linalg.solve(low.T, vec)  # mass-normalised
    mp = M @ phi
    omega = jnp.sqrt(jnp.clip(lam, 0.0))
    return mp @ ((2.0 * ratio * omega)[:, None] * mp.T)


def _optional_float(x):
    return None if x is None else as_float(x)


def ring_contact_angles(stage, travel) -> Float[Array, " n"]:
    """phi_n (rad): the planets' angles in the ring's frame at the mesh travel ``travel`` (m):
    ``psi_n + travel / r_b,ring``. The ring turns clockwise relative to the carrier by
    ``travel / r_b,ring`` (its mesh travels as fast as the sun's, :mod:`._planetary_mesh`), so
    the planets advance counter-clockwise around it; both frames coincide at ``travel = 0``."""
    return stage.planet_angles + travel / stage.ring.base_radius


def ring_force_directions(stage, angles) -> Float[Array, "n 2"]:
    """e_n (n, 2): the unit direction, in the ring's frame, of planet n's mesh force on the ring
    at the angle ``angles`` (rad): minus the gradient of the ring mesh's compression with the
    ring's translation in Lin & Parker's rows, ``(sin(phi + a_r), -cos(phi + a_r))``."""
    a = angles + stage.ring_pressure_angle
    return jnp.stack([jnp.sin(a), -jnp.cos(a)], axis=-1)


class AbstractRingModel(eqx.Module):
    """How the ring gear deforms under the ring meshes in
    :func:`~jaxgear.planetary.planetary_quasi_static` (:class:`RigidRing`, :class:`CondensedRing`,
    :class:`CraigBamptonRing`)."""

    @abc.abstractmethod
    def augment(self, stage, k_b, f, V, ring_rows, travel):
        """``(k_b', f', V')``: the structure stiffness, load and cell rows with the ring's
        coordinates added (none for a rigid ring) at the mesh travel ``travel`` (m).
        ``ring_rows`` (n_planets, c): the transverse ring-mesh force of each planet per cell
        force (cos beta_b on that planet's ring cells; beyond the theoretical path times the
        corner's rolling-free lever c,
        :meth:`~jaxgear.planetary.AbstractPlanetaryMeshes.ring_rows`)."""

    @abc.abstractmethod
    def dynamic_matrices(self, dtype, damping_ratio) -> tuple[Array, Array, Array]:
        """``(K_u, M_u, C_u)``: the stiffness (N/m), mass (kg) and damping (N s/m) of the
        ring's m coordinates in the dynamics, each (m, m) (m = 0 for a rigid ring); C_u modal
        at ``damping_ratio`` on the ring's own modes (:func:`modal_damping`)."""

    @abc.abstractmethod
    def contact_rows(self, stage, travel) -> Float[Array, "n m"]:
        """E (-, (n_planets, m)): each ring mesh's elastic ring displacement along its force,
        ``w_n = E_n u``, at the mesh travel ``travel`` (m)."""

    def window(self, stage, travel) -> tuple[Array, Array] | None:
        """``(idx, E_w)``: the ring coordinates the ring meshes reach at the mesh travel
        ``travel`` (m), (w,) int, and E on them, (n_planets, w) (``E[:, idx] = E_w``, zero
        elsewhere); None: the rows stay on every coordinate (a rigid ring)."""
        return None

    def modal_basis(self, dtype) -> tuple[Array, Array, Array] | None:
        """``(T, D, G)``: the ring's kept modes T (n_u, m, mass-normalised), their static
        correction D (n_u, m) and the residual flexibility G (m/N, (n_u, n_u)) when the ring is
        integrated in modal coordinates (n_u its coordinates: 2Z for :class:`CondensedRing`);
        None: on its own coordinates."""
        return None


class RigidRing(AbstractRingModel):
    """The lumped model's ring as it is: rigid, on its bearing and torsional supports (the
    default)."""

    def augment(self, stage, k_b, f, V, ring_rows, travel):
        return k_b, f, V

    def dynamic_matrices(self, dtype, damping_ratio):
        zero = jnp.zeros((0, 0), dtype)
        return zero, zero, zero

    def contact_rows(self, stage, travel):
        return jnp.zeros((stage.n_planets, 0), jnp.result_type(travel))


class CondensedRing(AbstractRingModel):
    """A flexible ring: its static in-plane compliance at Z equally spaced tooth stations,
    station k at ``2 pi k / Z`` from the ring frame's x axis (``fem_prep.ring_master_compliance``
    of a ring condensed on its root-patch masters, supported by its housing).

    Its displacement adds to the lumped ring's rigid motion: the lumped ring's supports stay
    in the stage (hold them stiff when the FE ring's support is the housing). Loads are taken
    at the stations' hats at the planet's angle (the pitch point lies on the line of centres),
    spread across the face width; the teeth's moment on the rim about the root circle is not
    carried (the rim masters carry translations only).

    In the dynamics the ring's 2Z station displacements are coordinates (module docstring):
    massless without ``mass`` (the ring quasi-static at every step: the compliance in series
    with the ring meshes, moving with the carrier), or with the stations' mass
    (``fem_prep.ring_station_mass``: the condensed ring reduced statically onto its stations)
    so that its nodal-diameter modes respond.

    With ``modes`` = m (and the mass) the dynamics integrate the ring in its m lowest modes
    plus the static correction of the others (module docstring): the same ring, fewer
    coordinates to step (m instead of 2Z); exact in statics, the station model with m = 2Z.

    Attributes:
        compliance: F (m/N), ``(Z, 2, Z, 2)``, symmetric positive definite as a ``2Z x 2Z``
            matrix.
        mass: M_u (kg), ``(Z, 2, Z, 2)`` symmetric positive definite, or None: a massless
            (quasi-static) ring.
        modes: m (static), 1..2Z: the ring's modes kept in the dynamics (needs ``mass``), or
            None: its 2Z station displacements.

    Raises:
        ValueError: a shape, value or count out of range (one line).
    """

    compliance: Float[Array, "z 2 z 2"] = eqx.field(converter=as_float)
    mass: Float[Array, "z 2 z 2"] | None = eqx.field(converter=_optional_float, default=None)
    modes: int | None = eqx.field(static=True, default=None)

    def __check_init__(self):
        F = self.compliance
        if F.ndim != 4 or F.shape[1] != 2 or F.shape[3] != 2 or F.shape[0] != F.shape[2]:
            raise ValueError(
                f"CondensedRing: compliance has shape {F.shape}; allowed (Z, 2, Z, 2), Z >= 3"
            )
        check_integer("CondensedRing: compliance.shape[0]", F.shape[0], 3)
        check_real("compliance", F, "m/N", where="CondensedRing")
        if self.mass is not None:
            if self.mass.shape != F.shape:
                raise ValueError(
                    f"CondensedRing: mass has shape {self.mass.shape}; allowed {F.shape} (the "
                    "compliance's)"
                )
            check_real("mass", self.mass, "kg", where="CondensedRing")
        if self.modes is not None:
            if self.mass is None:
                raise ValueError(
                    f"{type(self).__name__}: modes = {self.modes} needs the ring's mass "
                    "(allowed: None for a massless ring)"
                )
            top, words = self._coordinates()
            if isinstance(self.modes, bool) or not isinstance(self.modes, int) or not (
                1 <= self.modes <= top
            ):
                raise ValueError(
                    f"{type(self).__name__}: modes = {self.modes!r} is out of range: allowed an "
                    f"integer 1..{top} ({words})"
                )

    def _coordinates(self) -> tuple[int, str]:
        """The ring's number of coordinates in the dynamics, and what they are (words)."""
        return 2 * self.stations, f"2 x the {self.stations} stations"

    @property
    def stations(self) -> int:
        """Z, the number of tooth stations."""
        return self.compliance.shape[0]

    def hat_support(self, angles) -> tuple[Array, Array]:
        """``(k0, xi)``: the station before each of ``angles`` (rad), (n,) int, and the
        fraction of the way to the next one, (n,): the linear hats there are ``1 - xi`` on k0
        and ``xi`` on k0 + 1 (mod Z)."""
        z = self.stations
        t = jnp.mod(angles, 2 * math.pi) / (2 * math.pi / z)
        k0 = jnp.floor(t)
        return k0.astype(jnp.int32) % z, t - k0

    def hats(self, angles) -> Float[Array, "n z"]:
        """W (n, Z): the stations' linear hats at ``angles`` (rad)."""
        z = self.stations
        k0, xi = self.hat_support(angles)
        eye = jnp.eye(z, dtype=self.compliance.dtype)
        return (1 - xi)[:, None] * eye[k0] + xi[:, None] * eye[(k0 + 1) % z]

    def mesh_compliance(self, stage, travel) -> Float[Array, "n n"]:
        """C (m/N, (n_planets, n_planets)) of the ring meshes at the mesh travel ``travel``
        (m): module docstring."""
        E = self.station_rows(stage, travel)
        z2 = 2 * self.stations
        return E @ self.compliance.reshape(z2, z2) @ E.T

    def station_rows(self, stage, travel) -> Float[Array, "n zz"]:
        """E (n_planets, 2Z): ``E_n = sum_k W_nk e_n^T`` on the stations' (x, y) at the mesh
        travel ``travel`` (m): the ring's displacement at planet n along its mesh force is
        ``E_n u``, and the force P_n e_n spread on the stations is ``E_n^T P_n``."""
        phi = ring_contact_angles(stage, travel)
        E = self.hats(phi)[:, :, None] * ring_force_directions(stage, phi)[:, None, :]
        return E.reshape(E.shape[0], 2 * self.stations)

    def dynamic_matrices(self, dtype, damping_ratio):
        z2 = 2 * self.stations
        F = self.compliance.reshape(z2, z2).astype(dtype)
        K = jnp.linalg.inv(0.5 * (F + F.T))
        K = 0.5 * (K + K.T)
        if self.mass is None:  # quasi-static: no inertia, no damping
            zero = jnp.zeros((z2, z2), dtype)
            return K, zero, zero
        M = self.mass.reshape(z2, z2).astype(dtype)
        M = 0.5 * (M + M.T)
        return K, M, modal_damping(M, K, damping_ratio)

    def contact_rows(self, stage, travel):
        return self.station_rows(stage, travel)

    def window(self, stage, travel):
        """The two stations about each planet (the hats' support): idx (4 n_planets,) the
        (x, y) of stations k_n, k_n + 1 of planet n, E_w (n_planets, 4 n_planets) planet n's
        ``(1 - xi) e_n, xi e_n`` on its four (module docstring)."""
        z, n = self.stations, stage.n_planets
        phi = ring_contact_angles(stage, travel)
        k0, xi = self.hat_support(phi)
        st = jnp.stack([k0, (k0 + 1) % z], axis=-1)  # (n, 2)
        idx = (2 * st[:, :, None] + jnp.arange(2, dtype=jnp.int32)[None, None, :]).reshape(-1)
        w = jnp.stack([1 - xi, xi], axis=-1)[:, :, None] * ring_force_directions(stage, phi)[
            :, None, :]  # (n, 2, 2)
        E = jnp.eye(n, dtype=w.dtype)[:, :, None] * w.reshape(n, 1, 4)
        return idx, E.reshape(n, 4 * n)

    def modal_basis(self, dtype):
        if self.modes is None:
            return None

        K, M, _ = self.dynamic_matrices(dtype, 0.0)
        low = jnp.linalg.cholesky(M)
        a = jnp.linalg.solve(low, jnp.linalg.solve(low, K).T)
        _, vec = jnp.linalg.eigh(0.5 * (a + a.T))
        phi = jnp.linalg.solve(low.T, vec)  # mass-normalised, ascending
        T, Q = phi[:, : self.modes], phi[:, self.modes :]
        D, G = static_correction(T, Q, K)
        return T, D, G

    def augment(self, stage, k_b, f, V, ring_rows, travel):
        n = stage.n_planets
        C = self.mesh_compliance(stage, travel)
        Kw = jnp.linalg.inv(0.5 * (C + C.T))
        d = k_b.shape[0]
        K = jnp.zeros((d + n, d + n), dtype=k_b.dtype)
        K = K.at[:d, :d].set(k_b).at[d:, d:].set(0.5 * (Kw + Kw.T))
        return K, jnp.concatenate([f, jnp.zeros(n, f.dtype)]), jnp.concatenate(
            [V, -ring_rows.T], axis=1
        )


class CraigBamptonRing(CondensedRing):
    """A flexible ring with its own dynamics inside the stations: the condensed FE ring reduced
    Craig–Bampton style onto its Z stations' in-plane displacements u and its m lowest
    fixed-interface modes eta (the stations held; ``fem_prep.ring_craig_bampton``, R. R. Craig
    & M. C. C. Bampton, AIAA J. 6 (1968) 1313; the thesis's (2.3)-(2.5) with the stations as
    the interface):

        K = [[F^-1, 0], [0, diag(eigenvalues)]],    M = [[M_u, M_ue], [M_ue^T, I]]

    on the coordinates (u, eta), M_u the stations' (Guyan) mass and M_ue the ``coupling``. The
    ring meshes touch only u (the contact rows and the window are :class:`CondensedRing`'s,
    zero on eta), the fixed-interface modes carry mass and stiffness only: the statics are the
    station ring's at any m (eta carries no load and no static coupling), and as m grows the
    ring's nodal-diameter modes fall from the station model's (Guyan: from above) to the
    condensed FE ring's own.

    In the dynamics (:func:`jaxgear.planetary.planetary_dynamics`) the ring's coordinates are
    (u, eta), 2Z + m of them, with modal damping at the run's ratio on the ring's own modes;
    with ``modes`` = k (1..2Z + m) its k lowest modes plus the static correction of the others,
    integrated by :func:`jaxgear.dynamics.newmark_modal` (as :class:`CondensedRing`). In
    :func:`~jaxgear.planetary.planetary_quasi_static` it is the station ring (:meth:`augment`).

    Attributes:
        compliance: F (m/N), ``(Z, 2, Z, 2)``, symmetric positive definite as a ``2Z x 2Z``
            matrix.
        mass: M_u (kg), ``(Z, 2, Z, 2)`` symmetric positive definite (required).
        modes: k (static), 1..2Z + m: the ring's modes kept in the dynamics, or None: its
            2Z + m coordinates.
        eigenvalues: Lambda ((rad/s)^2, (m,), m >= 0, each > 0): the fixed-interface modes'
            (mass-normalised; ``fem_prep.RingStations.interior_eigenvalues``).
        coupling: M_ue (kg^(1/2), ``(Z, 2, m)``): their mass coupling to the stations
            (``fem_prep.RingStations.coupling``).

    Raises:
        ValueError: a shape, value or count out of range, or no mass (one line).
    """

    eigenvalues: Float[Array, " m"] | None = eqx.field(converter=_optional_float, default=None)
    coupling: Float[Array, "z 2 m"] | None = eqx.field(converter=_optional_float, default=None)

    def __check_init__(self):
        name = "CraigBamptonRing"
        if self.mass is None or self.eigenvalues is None or self.coupling is None:
            raise ValueError(f"{name}: mass, eigenvalues and coupling are required (allowed: "
                             "arrays; a massless ring is a CondensedRing)")
        lam, z = self.eigenvalues, self.stations
        if lam.ndim != 1 or self.coupling.shape != (z, 2, lam.shape[0]):
            raise ValueError(
                f"{name}: eigenvalues {lam.shape} and coupling {self.coupling.shape}: allowed "
                f"(m,) and ({z}, 2, m)"
            )
        check_real("eigenvalues", lam, "(rad/s)^2", where=name)
        check_real("coupling", self.coupling, "kg^(1/2)", where=name)
        if lam.shape[0] and float(jnp.min(lam)) <= 0.0:
            raise ValueError(f"{name}: eigenvalues min = {float(jnp.min(lam)):.6g}: allowed > 0")

    @classmethod
    def from_stations(cls, stations, interior: int | None = None,
                      modes: int | None = None) -> CraigBamptonRing:
        """The ring of a ``fem_prep.RingStations`` (:func:`fem_prep.ring_stations`) with its
        ``interior`` lowest coupled fixed-interface modes (None: all of them) and ``modes`` as
        the attribute.

        Raises:
            ValueError: ``stations`` not a ``fem_prep.RingStations``, ``interior`` outside
                0..m, or no fixed-interface modes (one line).
        """
        if not isinstance(stations, RingStations):
            raise ValueError(
                f"CraigBamptonRing.from_stations: stations = {stations!r:.60} "
                f"({type(stations).__name__}) is out of range: allowed a fem_prep.RingStations "
                "(fem_prep.ring_stations)"
            )
        lam, cpl = stations.interior_eigenvalues, stations.coupling
        if lam is None or cpl is None:
            raise ValueError("CraigBamptonRing.from_stations: the stations have no fixed-"
                             "interface modes (allowed: fem_prep.ring_stations' RingStations)")
        m = len(lam)
        if interior is not None and (isinstance(interior, bool) or not isinstance(
                interior, (int, np.integer)) or not 0 <= interior <= m):
            raise ValueError(f"CraigBamptonRing.from_stations: interior = {interior!r} is out of "
                             f"range: allowed an integer 0..{m} (the coupled fixed-interface "
                             "modes)")
        return cls(stations.compliance, stations.mass, modes, np.asarray(lam)[:interior],
                   np.asarray(cpl)[:, :, :interior])

    @property
    def interior(self) -> int:
        """m, the fixed-interface modes kept."""
        return 0 if self.eigenvalues is None else self.eigenvalues.shape[0]

    def _coordinates(self):
        return 2 * self.stations + self.interior, (
            f"2 x the {self.stations} stations + {self.interior} fixed-interface modes")

    def dynamic_matrices(self, dtype, damping_ratio):
        """``(K, M, C)`` on (u, eta) (class docstring), each (2Z + m, 2Z + m); C modal at
        ``damping_ratio`` on the ring's own modes (:func:`modal_damping`)."""
        z2, m = 2 * self.stations, self.interior
        F = self.compliance.reshape(z2, z2).astype(dtype)
        Ku = jnp.linalg.inv(0.5 * (F + F.T))
        K = jnp.zeros((z2 + m, z2 + m), dtype)
        K = K.at[:z2, :z2].set(0.5 * (Ku + Ku.T)).at[z2:, z2:].set(
            jnp.diag(self.eigenvalues.astype(dtype)))
        Mu = self.mass.reshape(z2, z2).astype(dtype)
        cpl = self.coupling.reshape(z2, m).astype(dtype)
        M = jnp.block([[0.5 * (Mu + Mu.T), cpl], [cpl.T, jnp.eye(m, dtype=dtype)]])
        return K, M, modal_damping(M, K, damping_ratio)

    def contact_rows(self, stage, travel):
        """E (n_planets, 2Z + m): the station rows (:meth:`CondensedRing.station_rows`), zero
        on the fixed-interface modes."""
        E = self.station_rows(stage, travel)
        return jnp.concatenate([E, jnp.zeros((E.shape[0], self.interior), E.dtype)], axis=1)


def ring_excitation(
    n_planets: int, ring_teeth: int, harmonic: int, max_nd: int
) -> tuple[np.ndarray, np.ndarray]:
    """Which nodal-diameter modes of a fixed ring the h-th mesh harmonic of N equally spaced
    planets excites, and at which order of the carrier speed (docs/planetary.md, "Which ring
    modes the planets excite").

    Planet j sits at ``theta_j(t) = Omega_c t + 2 pi j / N`` on the ring; its ring mesh meets a
    new tooth every ``2 pi / Z_r`` of its travel, so its mesh force at harmonic h is
    ``P_h exp(i h Z_r theta_j(t))`` (its phase ``h Z_r 2 pi j / N`` is Parker & Lin's ring-mesh
    phase). The circumferential harmonic n of the N moving point loads is

        q_n(t) = (1 / 2 pi) sum_j P_h exp(i (h Z_r - n) theta_j(t))
               = (P_h / 2 pi) exp(i (h Z_r - n) Omega_c t) sum_j exp(2 pi i (h Z_r - n) j / N),

    and the sum over the planets is N when ``h Z_r - n = 0 (mod N)``, else 0: the seed's rule
    (3.9) with the N planets in the place of the teeth and the ring's teeth phasing them. A
    standing n-diameter mode (n >= 0, the pair cos n theta, sin n theta) is excited by the
    travelling waves ``n`` and ``-n``: where ``h Z_r - s n = 0 (mod N)``, s = +1 or -1, at
    the frequency ``|h Z_r - s n| Omega_c``; it resonates where its natural frequency equals
    that. h = 0 (the mean mesh forces) excites the multiples of N at ``n Omega_c``.

    Args:
        n_planets: N (>= 1).
        ring_teeth: |Z_r| (>= 1).
        harmonic: h (>= 0).
        max_nd: the largest nodal diameter listed (>= 0).

    Returns:
        ``(nd, order)``: int arrays, one entry per excited (n, s) with ``nd = n`` ascending and
        ``order = |h Z_r - s n|``, the excitation frequency per carrier speed (a mode n excited
        by both waves appears twice, n = 0 once).
    """
    check_integer("n_planets", n_planets, 1)
    check_integer("ring_teeth", ring_teeth, 1)
    check_integer("harmonic", harmonic, 0)
    check_integer("max_nd", max_nd, 0)
    hz = harmonic * ring_teeth
    nd, order = [], []
    for n in range(max_nd + 1):
        for s in (1, -1) if n else (1,):
            if (hz - s * n) % n_planets == 0:
                nd.append(n)
                order.append(abs(hz - s * n))
    return np.array(nd, dtype=int), np.array(order, dtype=int)


def ring_resonances(
    frequencies_hz: dict[int, float], n_planets: int, ring_teeth: int, harmonics: int = 2
) -> list[dict[str, float]]:
    """The carrier speeds at which the planets' mesh harmonics meet the ring's nodal-diameter
    modes (a fixed ring; the crossings of a Campbell diagram of the ring's modes against the
    mesh orders, :func:`ring_excitation`).

    Args:
        frequencies_hz: the ring's natural frequency (Hz) of each nodal diameter n (>= 0) to
            check, e.g. from ``fem_prep`` (``{2: 319.6, 3: 902.5}``).
        n_planets: N. ring_teeth: |Z_r|.
        harmonics: the mesh harmonics h = 1 .. ``harmonics`` (and h = 0, the mean forces).

    Returns:
        One dict per crossing, sorted by carrier speed: ``nd``, ``harmonic``, ``order`` (the
        excitation frequency per carrier speed, ``|h Z_r -/+ n|``), ``frequency_hz`` and
        ``carrier_speed_hz`` (revolutions per second: frequency / order); order 0 (a static
        load pattern) never resonates and is left out.
    """
    check_integer("harmonics", harmonics, 0)
    out = []
    top = max(frequencies_hz) if frequencies_hz else 0
    for h in range(harmonics + 1):
        nd, order = ring_excitation(n_planets, ring_teeth, h, top)
        for n, k in zip(nd.tolist(), order.tolist(), strict=True):
            hit = {"nd": n, "harmonic": h, "order": k}
            if n in frequencies_hz and k > 0 and hit not in out:  # h = 0: both waves alike
                out.append(hit)
    for r in out:
        r["frequency_hz"] = float(frequencies_hz[r["nd"]])
        r["carrier_speed_hz"] = r["frequency_hz"] / r["order"]
    return sorted(out, key=lambda r: r["carrier_speed_hz"])
