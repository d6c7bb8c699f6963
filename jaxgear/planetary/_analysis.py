"""Analyses of a lumped planetary stage: natural modes with their types (Lin & Parker 1999),
the mesh phases (Parker & Lin 2004) and the quasi-static load sharing with planet-pin errors
(ISO 6336-1's K_gamma). Conventions: :mod:`jaxgear.planetary._stage` and docs/planetary.md."""

from __future__ import annotations

import enum

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Float

from ._stage import AbstractPlanetaryModel, PlanetaryStage
from ..dynamics import matrix_modal_analysis
from .._util import as_float, check_instance, check_integer, check_real, is_traced

__all__ = [
    "LoadSharing",
    "ModeType",
    "PlanetaryModes",
    "campbell",
    "classify_modes",
    "load_sharing",
    "mesh_phases",
    "phasing_excites",
    "planetary_modes",
]


class ModeType(enum.Enum):
    """The vibration-mode types of a planetary stage with equally spaced planets (Lin & Parker
    1999): ROTATIONAL (multiplicity 1, the central members rotate only, the planets move alike),
    TRANSLATIONAL (multiplicity 2, the central members translate only), PLANET (multiplicity
    N - 3, the central members still); MIXED where none holds (unequal spacing, an accidental
    coincidence of two types). In the 3D model (:class:`~jaxgear.planetary.SpatialPlanetary`;
    Eritenel & Parker 2009) ROTATIONAL_AXIAL (multiplicity 1: the central members rotate and move
    axially only) and TRANSLATIONAL_TILTING (multiplicity 2: they translate and tilt only) take the
    places of the first two."""

    ROTATIONAL = "rotational"
    TRANSLATIONAL = "translational"
    PLANET = "planet"
    MIXED = "mixed"
    ROTATIONAL_AXIAL = "rotational-axial"
    TRANSLATIONAL_TILTING = "translational-tilting"


class PlanetaryModes(eqx.Module):
    """Natural modes of a stage model.

    Attributes:
        frequencies: natural frequencies (Hz), shape ``(n_dof,)``, ascending; a rigid-body
            mode gives 0: an eigenvalue omega^2 <= 1e-9 times the largest is one (round-off
            either side of 0), the rule of :func:`~jaxgear.dynamics.modal_analysis`.
        shapes: mode shapes, shape ``(n_dof, n_dof)``, column j for ``frequencies[j]``, in the
            model's coordinates (m), mass-normalised: ``shapes.T M shapes = I``.
    """

    frequencies: Float[Array, " n_dof"]
    shapes: Float[Array, "n_dof n_dof"]


def check_model_stage(where: str, model, stage) -> None:
    """Refuse, in one ``ValueError`` line naming the argument, a ``model`` that is not a
    planetary model kind (:class:`~jaxgear.planetary.AbstractPlanetaryModel`: an object such as
    ``jaxgear.planetary.PlanarPlanetary()``, not its name) or a ``stage`` that is not a
    :class:`~jaxgear.planetary.PlanetaryStage`."""
    check_instance("model", model, AbstractPlanetaryModel, "a planetary model object: "
                   "jaxgear.planetary.PlanarPlanetary(), TorsionalPlanetary() or SpatialPlanetary()", where)
    check_instance("stage", stage, PlanetaryStage, "a jaxgear.planetary.PlanetaryStage", where)


@eqx.filter_jit
def planetary_modes(model: AbstractPlanetaryModel, stage: PlanetaryStage) -> PlanetaryModes:
    """The undamped natural modes at zero carrier speed: ``K phi = omega^2 M phi`` (K with the
    stage's constant mesh springs) through :func:`~jaxgear.dynamics.matrix_modal_analysis`, the
    modal solve of every model (the symmetric problem ``L^-1 K L^-T``, M = L L^T, Cholesky, with
    ``jnp.linalg.eigh``; its rigid-body rule, :class:`PlanetaryModes`); jit-able and
    differentiable in the stage's values (away from repeated and zero frequencies).

    Args:
        model: the model kind (:class:`~jaxgear.planetary.PlanarPlanetary`,
            :class:`~jaxgear.planetary.TorsionalPlanetary`).
        stage: the stage.

    Returns:
        :class:`PlanetaryModes`.

    Raises:
        ValueError: ``model`` or ``stage`` of the wrong kind (:func:`check_model_stage`).
    """
    check_model_stage("planetary_modes", model, stage)
    k = model.stiffness_matrix(stage)
    # the stage's constant mesh springs are in K already: no separate mesh-averaged part
    modes = matrix_modal_analysis(model.mass_matrix(stage), k, jnp.zeros_like(k))
    return PlanetaryModes(modes.frequency, modes.shapes)


#: the carrier speeds :func:`campbell` takes (rad/s, either sense): the case files' and the
#: command line's bound on speeds (1e5 rad/s, about 955 000 rpm: beyond any gear)
MAX_CARRIER_SPEED = 1e5
#: the mesh travel speeds it takes (m/s, either sense): beyond any gear's pitch-line velocity
MAX_MESH_SPEED = 1e5


def campbell(
    model: AbstractPlanetaryModel,
    stage: PlanetaryStage,
    carrier_speeds: Float[Array, " n_speeds"],
    mesh_speeds: Float[Array, " n_speeds"] | None = None,
) -> Float[Array, "n_speeds n_dof"]:
    """Natural frequencies in the carrier frame against the carrier speed, with the Coriolis
    and centripetal terms (Cooley & Parker 2012): ``M q'' + (Omega G + v G_v) q' + (K -
    Omega^2 K_Omega + Omega v K_v) q = 0`` (G_v, K_v: the gyroscopic moments of the members'
    spin relative to the carrier, :meth:`~jaxgear.planetary.AbstractPlanetaryModel.spin_matrices`;
    zero but in :class:`~jaxgear.planetary.SpatialPlanetary`). With ``K_e = S S`` (S its symmetric
    square root) and ``M = L L^T``, the first-order form in ``(S q, L^T q')`` has the real
    skew-symmetric matrix ``[[0, S L^-T], [-L^-1 S, -L^-1 (Omega G + v G_v) L^-T]]``, whose
    eigenvalues +-i omega come from the Hermitian ``eigh`` (so it runs on every device and is
    differentiable at simple values).

    Args:
        model, stage: as :func:`planetary_modes`.
        carrier_speeds: carrier speeds Omega (rad/s), shape ``(n_speeds,)``.
        mesh_speeds: the mesh travel speed v (m/s) at each carrier speed, shape
            ``(n_speeds,)`` (the sun turns at v / r_bs relative to the carrier; the ring held:
            v = r_br Omega); None (default): 0, every member turning with the carrier.

    Returns:
        Frequencies (Hz), shape ``(n_speeds, n_dof)``, ascending per speed; at Omega = v = 0
        those of :func:`planetary_modes`.

    Raises:
        ValueError: a speed not finite or beyond :data:`MAX_CARRIER_SPEED` (rad/s) or
            :data:`MAX_MESH_SPEED` (m/s), one line naming the argument (values not traced).
        EquinoxRuntimeError: a speed past divergence (K_e not positive semi-definite).
        ValueError: ``model`` or ``stage`` of the wrong kind (:func:`check_model_stage`).
    """
    check_model_stage("campbell", model, stage)
    check_real("carrier_speeds", carrier_speeds, "rad/s", lo=-MAX_CARRIER_SPEED,
               hi=MAX_CARRIER_SPEED, where="campbell")
    if mesh_speeds is not None:
        check_real("mesh_speeds", mesh_speeds, "m/s", lo=-MAX_MESH_SPEED, hi=MAX_MESH_SPEED,
                   where="campbell")
    freqs, diverged = _campbell(model, stage, carrier_speeds, mesh_speeds)
    # under a caller's jit/vmap/grad: eqx.error_if on the frequencies; else read on the host
    # (an eqx.error_if on concrete values compiles a program holding a Python callback, which
    # JAX's persistent compilation cache never stores: each CLI run compiled it again)
    if is_traced(diverged):
        return eqx.error_if(freqs, jnp.any(diverged), _PAST_DIVERGENCE)
    if bool(np.any(np.asarray(diverged))):
        raise eqx.EquinoxRuntimeError(_PAST_DIVERGENCE)
    return freqs


_PAST_DIVERGENCE = "campbell: past divergence"


@eqx.filter_jit
def _campbell(model, stage, carrier_speeds, mesh_speeds):
    """:func:`campbell`'s compiled body: (frequencies, whether each speed is past divergence,
    K_e not positive semi-definite)."""
    m = model.mass_matrix(stage)
    k = model.stiffness_matrix(stage)
    g = model.gyroscopic_matrix(stage)
    kc = model.centripetal_matrix(stage)
    g_v, k_v = model.spin_matrices(stage)
    low = jnp.linalg.cholesky(m)
    n = m.shape[0]

    def one(omega, v):
        lam, u = jnp.linalg.eigh(k - omega**2 * kc + omega * v * k_v)
        diverged = jnp.min(lam) < -1e-9 * jnp.max(jnp.abs(lam))
        s = (u * jnp.sqrt(jnp.clip(lam, 0.0))[None, :]) @ u.T
        b = jnp.linalg.solve(low, s).T  # S L^-T
        gyro = omega * g + v * g_v
        c = jnp.linalg.solve(low, jnp.linalg.solve(low, gyro).T).T  # L^-1 G L^-T
        a = jnp.block([[jnp.zeros((n, n)), b], [-b.T, -c]])
        w = jnp.linalg.eigvalsh(-1j * a)
        return w[n:] / (2.0 * jnp.pi), diverged

    speeds = jnp.reshape(as_float(carrier_speeds), (-1,))
    v = jnp.zeros_like(speeds) if mesh_speeds is None else jnp.reshape(
        as_float(mesh_speeds), (-1,))
    return jax.vmap(one)(speeds, jnp.broadcast_to(v, speeds.shape))


def classify_modes(
    modes: PlanetaryModes,
    model: AbstractPlanetaryModel,
    stage: PlanetaryStage,
    rtol: float = 1e-7,
    still: float = 1e-8,
) -> tuple[tuple[ModeType, int], ...]:
    """The type and multiplicity of each mode (host-side, NumPy; not traced).

    Modes whose frequencies agree within ``rtol`` times the highest frequency form one group.
    For N >= 3 equally spaced planets each group is typed by projecting its span on the three
    subspaces that the stage's cyclic symmetry keeps apart (Lin & Parker 1999; Eritenel &
    Parker 2009 for the 3D model): ROTATIONAL (the central members' rotations, and the
    planets' motions of harmonic 0: every planet alike in its own frame), TRANSLATIONAL (the
    central members' translations, and the planets' harmonic 1: p_n = a cos psi_n + b sin
    psi_n) and PLANET (the central members still, the planets' other harmonics; also harmonic
    1 in a model without central translations, the torsional one). Each of these subspaces is
    invariant under M and K, so a group's span is the sum of its parts in each: the part's
    dimension is the number of modes of that type at that frequency, which also types a group
    in which modes of two types share a frequency (the 3D model's planets tilting alike about
    their radial axes and a planet mode, at N >= 4). A group whose projections are not 0 or 1
    within ``still`` (the eigenvalues of Q^T P Q, Q an orthonormal basis of its span) is MIXED.

    Otherwise (unequal spacing, fewer than three planets) the share of the group's squared
    amplitude on the central members' translations and rotations decides: both below
    ``still`` -> PLANET, rotations only -> ROTATIONAL, translations only -> TRANSLATIONAL, else
    MIXED; a group with the central members still in which every planet moves alike is
    ROTATIONAL.

    Returns:
        One ``(ModeType, multiplicity)`` per mode, in the order of ``modes.frequencies``: the
        multiplicity of its type within its group of equal frequencies (a group of two types
        lists its rotational modes first, then translational, then planet; its shapes are any
        basis of the group).
    """
    check_instance(
        "model", model, AbstractPlanetaryModel, "a planetary model kind", "classify_modes"
    )
    f = np.asarray(modes.frequencies)
    phi = np.asarray(modes.shapes)
    tol = rtol * max(float(f.max()), 1.0)
    rotational, translational = (ModeType(name) for name in model.mode_types())
    groups, start = [], 0
    for j in range(1, len(f) + 1):
        if j == len(f) or f[j] - f[j - 1] > tol:
            groups.append(range(start, j))
            start = j
    projectors = _harmonic_projectors(model, stage, phi.shape[0])
    out = []
    for g in groups:
        block = phi[:, list(g)]
        if projectors is None:
            kind = _by_shares(block, model, stage, still, rotational, translational)
            out += [(kind, len(g))] * len(g)
            continue
        q, _ = np.linalg.qr(block)
        dims = []
        for p in projectors:
            lam = np.linalg.eigvalsh(q.T @ p @ q)
            if np.any(np.minimum(np.abs(lam), np.abs(1.0 - lam)) > still):
                dims = None
                break
            dims.append(int(np.sum(lam > 0.5)))
        if dims is None or sum(dims) != len(g):
            out += [(ModeType.MIXED, len(g))] * len(g)
            continue
        for kind, d in zip((rotational, translational, ModeType.PLANET), dims, strict=True):
            out += [(kind, d)] * d
    return tuple(out)


def _harmonic_projectors(model, stage, n_dof: int):
    """(P_rot, P_trans, P_planet), each (n_dof, n_dof), orthogonal projectors summing to the
    identity (:func:`classify_modes`), or None where the planets are not N >= 3 equally spaced
    (their harmonics then mix the types) or the coordinates are not per member alike."""
    n = stage.n_planets
    per = n_dof // (n + 3)
    psi = np.asarray(stage.planet_angles, dtype=float)
    turns = np.sort(np.mod(psi - psi[0], 2 * np.pi)) * n / (2 * np.pi)
    if n < 3 or per * (n + 3) != n_dof or np.max(np.abs(turns - np.arange(n))) > 1e-6:
        return None
    trans = list(model.central_translations(stage))
    rot = list(model.central_rotations(stage))
    harmonic0 = np.full((n, n), 1.0 / n)
    basis = np.stack([np.cos(psi), np.sin(psi)], -1) * np.sqrt(2.0 / n)
    harmonic1 = basis @ basis.T
    eye = np.eye(per)
    out = []
    for idx, planets in ((rot, harmonic0), (trans, harmonic1)):
        p = np.zeros((n_dof, n_dof))
        p[idx, idx] = 1.0
        if idx:  # without central translations (torsional) harmonic 1 is a planet mode's
            p[3 * per :, 3 * per :] = np.kron(planets, eye)
        out.append(p)
    return out[0], out[1], np.eye(n_dof) - out[0] - out[1]


def _by_shares(block, model, stage, still, rotational, translational) -> ModeType:
    """A group's type from the share of its squared amplitude on the central members'
    translations and rotations (:func:`classify_modes`, unequal spacing)."""
    total = np.sum(block**2)
    t_share = np.sum(block[list(model.central_translations(stage))] ** 2) / total
    r_share = np.sum(block[list(model.central_rotations(stage))] ** 2) / total
    types = {
        (False, False): ModeType.PLANET,
        (False, True): rotational,
        (True, False): translational,
        (True, True): ModeType.MIXED,
    }
    kind = types[(bool(t_share > still), bool(r_share > still))]
    if kind is ModeType.PLANET and _planets_alike(block, stage.n_planets, still):
        kind = rotational
    return kind


def _planets_alike(block: np.ndarray, n_planets: int, still: float) -> bool:
    """Whether the mode shapes ``block`` (n_dof, g) move every planet alike: the planets'
    coordinates (the last ``n_planets`` equal blocks of the model's coordinates, planet by
    planet) differ from their mean over the planets by a squared share below ``still``."""
    total = np.sum(block**2)
    n = block.shape[0]
    per = n // (n_planets + 3)  # coordinates per member: 3 central members, then the planets
    if n_planets < 2 or per * (n_planets + 3) != n:
        return False
    planets = block[n - n_planets * per :].reshape(n_planets, per, -1)
    spread = np.sum((planets - planets.mean(axis=0)) ** 2)
    return bool(np.sum(planets**2) / total > still and spread / total < still)


# -- mesh phasing ------------------------------------------------------------------------------


def mesh_phases(z_sun: int, z_ring: int, planet_angles) -> tuple[np.ndarray, np.ndarray]:
    """The mesh phases of the 2N meshes relative to planet 1's (Parker & Lin 2004), as
    fractions of a mesh period in [0, 1).

    With the sun turning counter-clockwise relative to the carrier (and so the ring clockwise),
    the sun-planet mesh of planet n repeats planet 1's a time ``gamma_sn T_m`` later:
    ``k_sn(t) = k_s1(t - gamma_sn T_m)``, ``gamma_sn = frac(z_s psi_n / 2 pi)``; the ring-planet
    meshes ``gamma_rn = frac(-z_r psi_n / 2 pi)``. When the planets can be assembled
    (:func:`~jaxgear.planetary.check_assembly`) the two are equal. For the clockwise sense, take
    ``1 - gamma`` (mod 1). ``planet_angles`` (rad), shape ``(n_planets,)``, planet 1 the
    reference.

    Returns:
        (gamma_s, gamma_r), each shape ``(n_planets,)``.
    """
    check_integer("z_sun", z_sun, 3)
    check_integer("z_ring", z_ring, int(z_sun) + 1)
    psi = np.asarray(planet_angles, dtype=float)
    check_real("planet_angles", psi, "rad", shape=(None,), where="mesh_phases")
    turns = (psi - psi[0]) / (2.0 * np.pi)
    return _frac(z_sun * turns), _frac(-z_ring * turns)


def _frac(x):
    r = np.mod(x, 1.0)
    return np.where(np.isclose(r, 1.0, atol=1e-9) | np.isclose(r, 0.0, atol=1e-9), 0.0, r)


def phasing_excites(z_sun: int, n_planets: int, harmonic: int) -> ModeType:
    """Which modes harmonic ``harmonic`` of the mesh frequency can excite through the sun-planet
    meshes of N equally spaced planets (Parker 2000; Parker & Lin 2004): with
    ``k = mod(harmonic z_s, N)``, k = 0: ROTATIONAL (the net torque adds up, the net force
    cancels); k = 1 or N - 1: TRANSLATIONAL (net force, no net torque); otherwise PLANET (both
    cancel on the central members). In phase (z_s / N integer): k = 0 at every harmonic."""
    check_integer("z_sun", z_sun, 3)
    check_integer("n_planets", n_planets, 3)
    check_integer("harmonic", harmonic, 1)
    k = (harmonic * z_sun) % n_planets
    return _EXCITES[min(k, n_planets - k, 2)]


_EXCITES = (ModeType.ROTATIONAL, ModeType.TRANSLATIONAL, ModeType.PLANET)


# -- quasi-static load sharing -----------------------------------------------------------------


class LoadSharing(eqx.Module):
    """Quasi-static mesh loads of a stage (linear, constant mesh stiffness).

    Attributes:
        displacement: the coordinates (m), shape ``(n_dof,)``.
        sun_mesh_forces, ring_mesh_forces: force on each planet's sun-planet and ring-planet
            mesh (N, compression positive), shape ``(n_planets,)``.
        k_gamma: the mesh load factor (ISO 6336-1, AGMA 6123): the most loaded planet's
            sun-planet force over the mean, shape ``()``.
    """

    displacement: Float[Array, " n_dof"]
    sun_mesh_forces: Float[Array, " n_planets"]
    ring_mesh_forces: Float[Array, " n_planets"]
    k_gamma: Float[Array, ""]


def load_sharing(
    model: AbstractPlanetaryModel,
    stage: PlanetaryStage,
    sun_torque: Float[Array, ""],
    tangential_pin_errors: Float[Array, " n_planets"],
    radial_pin_errors: Float[Array, " n_planets"] | float = 0.0,
    travel: Float[Array, ""] | float = 0.0,
) -> LoadSharing:
    """Load sharing among the planets under a sun torque, with planet-pin position errors, from ``K q = f`` (the model's stiffness; constant mesh stiffness, every mesh assumed
    in contact: a negative mesh force means the model does not apply).

    Args:
        model: the model kind.
        stage: the stage; its ring and carrier (or whichever members react the torque) need a
            torsional stiffness, else K is singular (the result is then refused).
        sun_torque: torque on the sun (N m), positive counter-clockwise (it loads the sun-planet
            meshes in compression).
        tangential_pin_errors: position error of each planet pin along eta (m), shape
            ``(n_planets,)`` (positive counter-clockwise, the sense that unloads the planet's
            meshes under a positive sun torque).
        radial_pin_errors: position error of each planet pin along zeta, outward (m), shape
            ``(n_planets,)`` or ``()``; with equal pressure angles it leaves the shares
            unchanged to first order (its mesh offsets -eps sin a_s and +eps sin a_r cancel
            along a planet's path).
        travel: the mesh travel x (m) at which the stage's eccentricities
            (:class:`~jaxgear.planetary.Eccentricities`, turning with their members) are taken; 0 by
            default (their phases' origin). Without eccentricities the result does not depend
            on it.

    Returns:
        :class:`LoadSharing`.

    Raises:
        ValueError: an error array of the wrong shape (trace time); a sun torque not > 0 (no
            nominal load to share: K_γ is the most loaded planet's share of it) or not finite,
            a pin error or travel not finite (values not traced; one line naming the argument).
        EquinoxRuntimeError: a singular stiffness (a member free to turn).
    """
    check_real("sun_torque", sun_torque, "N m", lo=0.0, lo_open=True, shape=(),
               where="load_sharing")
    n = stage.n_planets
    check_real(
        "tangential_pin_errors",
        tangential_pin_errors,
        "m",
        shape=(n,),
        shape_text=f"({n},)",
        where="load_sharing",
    )
    check_real("radial_pin_errors", radial_pin_errors, "m", where="load_sharing")
    if jnp.size(radial_pin_errors) not in (1, n):
        raise ValueError(f"load_sharing: radial_pin_errors must have shape () or ({n},)")
    check_real("travel", travel, "m", shape=(), where="load_sharing")
    r, singular = _load_sharing(model, stage, sun_torque, tangential_pin_errors,
                                radial_pin_errors, travel)
    # under a caller's jit/vmap/grad: eqx.error_if on every output; else read on the host (an
    # eqx.error_if on concrete values compiles a program holding a Python callback, which JAX's
    # persistent compilation cache never stores: each CLI run compiled it again)
    if is_traced(singular):
        return eqx.error_if(r, jnp.any(singular), _SINGULAR)
    if bool(singular):
        raise eqx.EquinoxRuntimeError(_free_coordinates(model, stage))
    return r


_SINGULAR = (
    "load_sharing: the stiffness is singular (or too ill-conditioned for this precision): "
    "hold the ring or the carrier"
)


def _free_coordinates(model, stage) -> str:
    """The one-line refusal of a singular load-sharing stiffness on the host, naming the
    coordinates of its softest mode (the mechanism: e.g. ``theta_c``, a carrier free to turn,
    or ``x_r, y_r``, a ring without bearings in the planar model)."""
    lam, vec = np.linalg.eigh(np.asarray(model.stiffness_matrix(stage), dtype=float))
    v = np.abs(vec[:, 0])
    names = model.dof_names(stage)
    free = ", ".join(names[i] for i in np.flatnonzero(v >= 0.3 * v.max()))
    return (f"{_SINGULAR}, or give the member a support: the softest mode moves {free} "
            "(a rotation needs a torsional stiffness, a translation a bearing)")


@eqx.filter_jit
def _load_sharing(model, stage, sun_torque, tangential_pin_errors, radial_pin_errors, travel):
    """:func:`load_sharing`'s compiled body (its arguments checked): (the
    :class:`LoadSharing`, whether the stiffness is singular)."""
    e = as_float(tangential_pin_errors)
    f_err, d_s, d_r = model.error_terms(stage, e, as_float(radial_pin_errors), travel)
    k = model.stiffness_matrix(stage)
    names = model.dof_names(stage)
    f = f_err.at[names.index("u_s")].add(as_float(sun_torque) / stage.sun.base_radius)
    # K is symmetric positive semi-definite: a free member leaves an eigenvalue at rounding
    # level (or one too small for the precision), which no residual of the solve reveals
    lam = jnp.linalg.eigvalsh(k)
    eps = jnp.finfo(k.dtype).eps
    q = jnp.linalg.solve(k, f)
    singular = (lam[0] <= 100 * k.shape[0] * eps * lam[-1]) | ~jnp.all(jnp.isfinite(q))
    v_s, v_r = model.mesh_deflection_rows(stage)
    k_s, k_r = stage.mesh_stiffnesses()
    f_s = k_s * (v_s @ q + d_s)
    f_r = k_r * (v_r @ q + d_r)
    return LoadSharing(q, f_s, f_r, jnp.max(f_s) / jnp.mean(f_s)), singular
