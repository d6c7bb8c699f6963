"""Modal analysis of the time-averaged system, its Campbell coincidences with the mesh orders
(critical speeds, seed Tab. IV-8), the nodal-diameter families of a condensed wheel and their
(3.9) resonances, the modes' stiffening with speed (Southwell), and the damping models built on
the modes (seed (2.34)-(2.36)).

Every scene (torsional, lumped 3D, hybrid) goes through :func:`modal_analysis`; the CLI's sweep
summaries and Campbell diagrams read :func:`campbell_coincidences` and
:func:`nodal_diameter_resonances`.
"""

from __future__ import annotations

import math

import equinox as eqx
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Float

from .._util import compiled_when_eager
from ..scenes import DynamicScene, HybridPair
from ._settings import MAX_STEPS_PER_SPEED, MESH_ENERGY_MIN, MIN_STEPS_PER_PERIOD, STEPS_PER_MODE

__all__ = [
    "ModalAnalysis",
    "ModesAtSpeed",
    "campbell_coincidences",
    "excited_omega",
    "modal_analysis",
    "modes_at_speed",
    "gear_nodal_diameter_resonances",
    "matrix_modal_analysis",
    "nodal_diameter_modes",
    "nodal_diameter_resonances",
    "steps_for_mode",
]


class ModalAnalysis(eqx.Module):
    """Modes of the time-averaged system K̄ φ = ω² M φ, sorted by frequency.

    Attributes:
        omega: natural angular frequencies (rad/s), shape (n,) (0 for rigid-body modes).
        frequency: ω/2π (Hz), shape (n,).
        shapes: mass-normalised mode shapes Φ (columns, Φᵀ M Φ = I), shape (n, n).
        energy: share of modal strain energy per part, shape (n_parts, n), columns summing to 1
            for the elastic modes (0 for rigid modes); row 0 is the mesh, then the scene's parts.
        parts: static names of the energy rows ("mesh", then the scene's stiffness parts).
        rigid: True for rigid-body modes, shape (n,).
        mesh_stiffness: the time-averaged mesh stiffness matrix K̄_m (units of K), shape (n, n).
        kinetic: where the model groups its coordinates (a gearbox's stages, then a shared
            housing): each mode's share of kinetic energy per group, e_g = Σ_{j∈g} φ_j (M φ)_j
            (mass-normalised φ: each column sums to 1), shape (n_groups, n); None otherwise.
        groups: static names of the ``kinetic`` rows (``("stage1", "stage2", "housing")``);
            () without them.
    """

    omega: Float[Array, " n"]
    frequency: Float[Array, " n"]
    shapes: Float[Array, "n n"]
    energy: Float[Array, "n_parts n"]
    rigid: Array
    mesh_stiffness: Float[Array, "n n"]
    parts: tuple = eqx.field(static=True)
    kinetic: Float[Array, "n_groups n"] | None = None
    groups: tuple = eqx.field(static=True, default=())

    @property
    def mesh_energy(self) -> Float[Array, " n"]:
        """Share e_i of modal strain energy stored in the mesh (2.36), shape (n,)."""
        return self.energy[0]


def modal_analysis(scene: DynamicScene, mesh_stiffness: Float[Array, "n n"]) -> ModalAnalysis:
    """Modal analysis of the time-averaged system (the basis of the damping models (2.34)-(2.36)).

    Args:
        scene: the dynamic scene (M, K_s and its parts).
        mesh_stiffness: time-averaged mesh stiffness matrix K̄_m = ⟨Σ_c w_c k_c l_c V_c V_cᵀ⟩ over
            a mesh period (w_c: static contact weights), shape (n, n).

    Returns:
        :class:`ModalAnalysis` (strain-energy shares as in the seed's Tab. IV-8).
    """
    parts = {"mesh": mesh_stiffness, **scene.stiffness_parts()}
    return _modal_analysis(scene.mass(), mesh_stiffness, tuple(parts), tuple(parts.values()))


@compiled_when_eager
def _modal_analysis(M, mesh_stiffness, names: tuple, stiffness: tuple) -> ModalAnalysis:
    """:func:`modal_analysis` of the mass ``M`` and the stiffness parts ``stiffness`` named
    ``names`` (the mesh's first): one compiled program per size when called eagerly (the
    Cholesky factor, the eigen-solution and the energy shares; eagerly each of its some 20
    operations compiled on its own), traced inline under a caller's ``jit``."""
    parts = dict(zip(names, stiffness, strict=True))
    K = sum(parts.values())
    L = jnp.linalg.cholesky(M)
    Linv = jnp.linalg.inv(L)
    A = Linv @ K @ Linv.T
    A = 0.5 * (A + A.T)
    lam, Y = jnp.linalg.eigh(A)
    Phi = Linv.T @ Y
    scale = jnp.max(jnp.abs(lam))
    rigid = lam <= 1e-9 * scale
    lam = jnp.where(rigid, 0.0, lam)
    omega = jnp.sqrt(lam)
    strain = jnp.stack([jnp.einsum("in,ij,jn->n", Phi, P, Phi) for P in parts.values()])
    total = jnp.sum(strain, axis=0)
    energy = jnp.where(rigid[None, :], 0.0, strain / jnp.where(rigid, 1.0, total)[None, :])
    return ModalAnalysis(
        omega=omega,
        frequency=omega / (2 * jnp.pi),
        shapes=Phi,
        energy=energy,
        rigid=rigid,
        mesh_stiffness=mesh_stiffness,
        parts=tuple(parts),
    )


class _Matrices(eqx.Module):
    """A mass and a structure stiffness in the form :func:`modal_analysis` reads."""

    m: Array
    k: Array

    def mass(self):
        return self.m

    def stiffness_parts(self):
        return {"structure": self.k}


def matrix_modal_analysis(
    mass: Float[Array, "n n"],
    structure: Float[Array, "n n"],
    mesh_stiffness: Float[Array, "n n"],
) -> ModalAnalysis:
    """:func:`modal_analysis` of a system given by its matrices (a planetary stage's or a
    gearbox's, which are not scenes): mass M (kg or kg m²), the structure's stiffness K_s and
    the mesh-averaged stiffness K̄_m (units of K), all (n, n); energy rows ``("mesh",
    "structure")``."""
    return modal_analysis(_Matrices(mass, structure), mesh_stiffness)


class ModesAtSpeed(eqx.Module):
    """The modes of a spinning structure against speed (:func:`modes_at_speed`): each mode at
    rest followed as the speed rises, for the Campbell diagram at speed.

    Attributes:
        speeds: pinion speeds Ω of the grid (rad/s), shape (g,), from 0.
        omega: natural angular frequency of each mode at each speed (rad/s), shape (g, n),
            column i the mode i of the analysis at rest (constant for the modes outside the
            Ritz basis, 0 for rigid-body modes).
        mesh_energy: each mode's mesh strain-energy share at each speed, shape (g, n).
        error: max over the ``n_check`` lowest elastic modes of |ω_Ritz / ω_exact − 1| at the
            top speed, both in ascending order, ω_exact from the full eigen-solution (-).
        shift: max over them of |ω(top) / ω(0) − 1| in ascending order (-): how far the modes
            move by the top speed.
    """

    speeds: Float[Array, " g"]
    omega: Float[Array, "g n"]
    mesh_energy: Float[Array, "g n"]
    error: float = eqx.field(static=True)
    shift: float = eqx.field(static=True)


def modes_at_speed(
    scene, modes: ModalAnalysis, speeds, *, n_basis: int = 60, n_check: int = 20
) -> ModesAtSpeed:
    """The modes of a hybrid structure at pinion speeds Ω: K̄ + Ω² S with S the condensed
    bodies' spin softening plus centrifugal stress stiffening per unit pinion speed²
    (``scene.structure.spin_stiffness``, fem_prep; a thin web's out-of-plane modes stiffen,
    Southwell's rule ω² ≈ ω₀² + s Ω², R. V. Southwell, Proc. R. Soc. A 101, 1922).

    Rayleigh-Ritz in the basis Φ of the ``n_basis`` lowest elastic modes at rest (mass-
    normalised): at each speed the eigenpairs of diag(ω₀²) + Ω² Φᵀ S Φ; each mode is followed
    from speed to speed by the largest overlap of the Ritz vectors (an assignment, SciPy's
    ``linear_sum_assignment``), so that modes of different nodal diameters cross rather than
    swap. The Coriolis coupling is left out (it splits forward and backward waves in the
    body frame; docs/hybrid.md, "Campbell diagram at speed"). Checked at the top speed against
    the eigen-solution of the full (M, K̄ + Ω² S): ``error``.

    Args:
        scene: a :class:`jaxgear.scenes.HybridPair` (anything with ``structure``).
        modes: its :func:`modal_analysis` at rest, with K̄_m.
        speeds: the grid of pinion speeds (rad/s), ascending, >= 0, concrete, shape (g,).
        n_basis: the Ritz basis size (the lowest elastic modes). n_check: modes in ``error``.

    Returns:
        :class:`ModesAtSpeed`.
    """
    from scipy.optimize import linear_sum_assignment  # lazy: SciPy's optimize loads slowly

    sp = np.asarray(speeds, dtype=float)
    if sp.ndim != 1 or sp.size < 2 or np.any(np.diff(sp) <= 0) or sp[0] < 0:
        raise ValueError(f"speeds: {sp!r}: allowed an ascending grid of >= 2 speeds >= 0 rad/s")
    S = np.asarray(scene.structure.spin_stiffness, dtype=float)
    omega0 = np.asarray(modes.omega, dtype=float)
    elastic = np.flatnonzero(~np.asarray(modes.rigid))
    basis = elastic[: int(n_basis)]
    Phi = np.asarray(modes.shapes, dtype=float)[:, basis]
    Sr = Phi.T @ S @ Phi
    Sr = 0.5 * (Sr + Sr.T)
    Kmr = Phi.T @ np.asarray(modes.mesh_stiffness, dtype=float) @ Phi
    lam0 = omega0[basis] ** 2
    omega = np.tile(omega0, (sp.size, 1))
    energy = np.tile(np.asarray(modes.mesh_energy, dtype=float), (sp.size, 1))
    Y_prev = np.eye(basis.size)
    for k, w in enumerate(sp):
        lam, Y = np.linalg.eigh(np.diag(lam0) + w**2 * Sr)
        # column j of the result follows mode j: the Ritz vector with the largest overlap
        _, col = linear_sum_assignment(-np.abs(Y_prev.T @ Y))
        lam, Y = lam[col], Y[:, col]
        Y = Y * np.sign(np.sum(Y * Y_prev, axis=0) + 1e-300)
        Y_prev = Y
        lam = np.maximum(lam, 0.0)
        omega[k, basis] = np.sqrt(lam)
        energy[k, basis] = np.einsum("ij,ik,kj->j", Y, Kmr, Y) / np.maximum(lam, 1e-300)
    top = float(sp[-1])
    exact = np.asarray(modal_analysis(scene, modes.mesh_stiffness + top**2 * S).omega)
    m = min(int(n_check), basis.size)
    ritz = np.sort(omega[-1, basis])[:m]
    ex = np.sort(exact[~np.asarray(modes.rigid)])[:m]
    return ModesAtSpeed(
        speeds=jnp.asarray(sp),
        omega=jnp.asarray(omega),
        mesh_energy=jnp.asarray(energy),
        error=float(np.max(np.abs(ritz / ex - 1))) if m else 0.0,
        shift=float(np.max(np.abs(ex / np.sort(lam0)[:m] ** 0.5 - 1))) if m else 0.0,
    )


def _first_crossing(speeds, omega, rate) -> float:
    """The lowest speed Ω > 0 where a mode's ω(Ω) (rad/s, sampled on ``speeds``, linear
    between) meets the excitation ``rate`` · Ω; inf if it does not on the grid."""
    d = np.asarray(omega, dtype=float) - rate * np.asarray(speeds, dtype=float)
    k = np.flatnonzero((d[:-1] > 0) & (d[1:] <= 0))
    if not k.size:
        return math.inf
    k = int(k[0])
    t = d[k] / (d[k] - d[k + 1])
    return float(speeds[k] + t * (speeds[k + 1] - speeds[k]))


def campbell_coincidences(
    omega,
    mesh_energy,
    mesh_order,
    max_speed: float = math.inf,
    *,
    n_modes: int | None = None,
    harmonics=(1, 2, 3),
    min_share: float = 0.05,
    speeds=None,
) -> list[dict]:
    """Mode × mesh-harmonic coincidences of the Campbell diagram: the pinion speeds Ω = ω/(h z)
    at which the h-th harmonic of a mesh of order z (teeth per pinion revolution: z1 for a pair)
    meets a natural frequency ω (the critical speeds of seed Tab. IV-8); with ``speeds``, the
    frequencies at speed ω(Ω) (:func:`modes_at_speed`) and Ω the first crossing of ω(Ω) with
    h z Ω (linear between the grid's speeds).

    Args:
        omega: natural angular frequencies (rad/s), shape (m,), 0 for rigid-body modes
            (:attr:`ModalAnalysis.omega`); with ``speeds``, shape (g, m) (each column a mode
            on the grid, :attr:`ModesAtSpeed.omega`).
        mesh_energy: the modes' shares of strain energy in the mesh (2.36) at rest, shape (m,).
        mesh_order: z, mesh periods per pinion revolution.
        max_speed: keep coincidences up to 1.05 × this pinion speed (rad/s).
        n_modes: the elastic modes with the largest mesh-energy shares kept (None: all of
            them); only modes with a share >= ``min_share`` count (the modes the mesh excites).
        harmonics: mesh harmonics h.
        speeds: the pinion speeds (rad/s) of ``omega``'s rows, shape (g,), or None.

    Returns:
        One dict per (mode, harmonic), by mode index then harmonic: ``mode`` (index into
        ``omega``), ``harmonic``, ``speed_rad_s`` (pinion), ``frequency_Hz`` (at that speed),
        ``mesh_energy_share``.
    """
    curves = np.asarray(omega, dtype=float)
    rest = curves[0] if speeds is not None else curves
    energy = np.asarray(mesh_energy, dtype=float)
    excited = [i for i in range(rest.size) if rest[i] > 0 and energy[i] >= min_share]
    chosen = sorted(excited, key=lambda i: -energy[i])
    modes = sorted(chosen if n_modes is None else chosen[:n_modes])
    out = []
    for i in modes:
        for h in harmonics:
            if speeds is None:
                speed, omega_at = rest[i] / (mesh_order * h), rest[i]
            else:
                speed = _first_crossing(speeds, curves[:, i], mesh_order * h)
                omega_at = mesh_order * h * speed
            if speed <= max_speed * 1.05:
                out.append(
                    {
                        "mode": int(i),
                        "harmonic": int(h),
                        "speed_rad_s": float(speed),
                        "frequency_Hz": float(omega_at / (2 * math.pi)),
                        "mesh_energy_share": float(energy[i]),
                    }
                )
    return out


def _condensed_member(scene, member: int | None, who: str) -> int:
    """``member`` checked to be a condensed body of ``scene`` (None: the wheel, member 1, when
    it is condensed, else the first condensed member); a one-line error naming ``who``."""
    flexible = [i for i, m in enumerate(scene.members) if m.rim_stations().count]
    if member is None:
        if not flexible:
            raise ValueError(f"{who}: the scene has no condensed body")
        member = 1 if 1 in flexible else flexible[0]
    if member not in flexible:
        raise ValueError(
            f"{who}: member = {member!r} is not a condensed body: allowed "
            f"{', '.join(map(str, flexible)) or 'none (every member is rigid)'}"
        )
    return member


def nodal_diameter_modes(
    scene: HybridPair, modes: ModalAnalysis, n_modes: int = 40, member: int | None = None
) -> dict:
    """A condensed gear's nodal-diameter families among the modes of the assembled hybrid
    structure (its condensed body with the teeth lumped on the rim, on its shafts and bearings;
    with the mesh-averaged stiffness K̄_m in ``modes``): the modal basis of the seed's (3.9)
    resonances.

    Each mode's rim displacement at the gear's stations (body frame, the axial master plane
    nearest mid-face; radial, tangential and axial) is split into circumferential harmonics;
    the mode's nodal diameter n is the harmonic with the most energy.

    Args:
        scene: a :class:`jaxgear.scenes.HybridPair` (or a hybrid train) with a condensed body.
        modes: the scene's :func:`modal_analysis` with K̄_m (:func:`mean_mesh_stiffness`; zeros
            for the structure alone), the one a sweep summary reports too.
        n_modes: the lowest elastic modes examined (the drive rotation excluded).
        member: the index of the condensed gear in ``scene.members`` (a pair: 0 the pinion,
            1 the wheel; a train: the gear's index). Default: the wheel (member 1) when it is
            condensed, else the first condensed member.

    Returns:
        dict of NumPy arrays over the modes: ``mode`` (index into ``modes``),
        ``frequency_hz``, ``nodal_diameter``, ``share``
        (energy share of that harmonic, 0..1), ``axial_share`` (share of the rim motion that is
        axial: out-of-plane modes near 1) and ``rim_share`` (share of the mode's kinetic energy
        in the wheel's body DOFs).

    Raises:
        ValueError: the chosen member is rigid, or no member is condensed.
    """
    member = _condensed_member(scene, member, "nodal_diameter_modes")
    wheel = scene.members[member]
    elastic = np.flatnonzero(~np.asarray(modes.rigid))[:n_modes]  # the drive rotation out
    omega = np.asarray(modes.omega)[elastic]
    phi = np.asarray(modes.shapes)[:, elastic]
    M = np.asarray(scene.structure.M, dtype=float)
    j_mid = int(np.argmin(np.abs(np.asarray(wheel.z_nodes))))
    rim = np.asarray(wheel.rim_dofs)[:, j_mid, :]  # (Z, 3)
    Z = rim.shape[0]
    ang = float(wheel.station0) + float(wheel.pitch_angle) * np.arange(Z)
    u = phi[rim]  # (Z, 3, modes)
    c, s = np.cos(ang)[:, None], np.sin(ang)[:, None]
    cyl = np.stack([c * u[:, 0] + s * u[:, 1], -s * u[:, 0] + c * u[:, 1], u[:, 2]], 1)
    F = np.fft.rfft(cyl, axis=0)  # (Z//2 + 1, 3, modes)
    e = np.sum(np.abs(F) ** 2, axis=1)
    nd = np.argmax(e, axis=0)
    body = np.asarray(wheel.body_dofs)
    Mphi = M @ phi
    return {
        "mode": elastic,
        "frequency_hz": omega / (2 * np.pi),
        "nodal_diameter": nd,
        "share": e[nd, np.arange(nd.size)] / np.sum(e, axis=0),
        "axial_share": np.sum(cyl[:, 2] ** 2, axis=0) / np.sum(cyl**2, axis=(0, 1)),
        "rim_share": np.einsum("im,im->m", phi[body], Mphi[body]),
    }


def nodal_diameter_resonances(
    frequency_hz,
    nodal_diameter,
    wheel_teeth: int,
    pinion_teeth: int,
    harmonics=(1,),
    speeds=None,
) -> list[dict]:
    """Pinion speeds at which the mesh excites n-nodal-diameter modes, seed (3.9) and Tab. III-11.

    In the wheel's frame the mesh, fixed in space, runs round the rim against the rotation: its
    h-th harmonic excites diameter n at the orders h Z + n (a *backward* wave, against the
    rotation) and h Z − n (*forward*) of the wheel's rotation frequency. The mode of frequency
    f_n resonates at wheel speed 2π f_n/(h Z ± n), i.e. pinion speed (Z/z1) times that. With
    the frequencies at speed f_n(Ω) (``speeds``, :func:`modes_at_speed`) the resonance is the
    first pinion speed where 2π f_n(Ω) = (h Z ± n) (z1/Z) Ω.

    Any condensed gear is a "wheel" here: Z its teeth (every mesh it is in passes Z teeth per
    turn of it, so each of its meshes excites the same orders) and z1 = Z times its turns per
    turn of the scene's pinion (a train's input): a flexible pinion z1 = Z; an idler of Z
    teeth driven by a z-tooth input z1 = z.

    Args:
        frequency_hz: the modes' frequencies (Hz), shape (m,) (:func:`nodal_diameter_modes`),
            or with ``speeds`` shape (g, m) (each column a mode on the grid).
        nodal_diameter: their nodal diameters, shape (m,).
        wheel_teeth: Z. pinion_teeth: z1. harmonics: mesh harmonics h.
        speeds: the pinion speeds (rad/s) of ``frequency_hz``'s rows, shape (g,), or None.

    Returns:
        One dict per (mode, harmonic, direction) with n >= 1 that resonates at a finite speed:
        ``frequency_hz`` (at that speed), ``frequency_rest_hz``, ``nodal_diameter``,
        ``harmonic``, ``order`` (h Z ± n), ``direction`` ("backward" or "forward"),
        ``wheel_speed_rad_s`` and ``pinion_speed_rad_s``.
    """
    from fem_prep import resonance_orders  # lazy: fem_prep's __init__ loads scikit-fem

    curves = 2 * np.pi * np.asarray(frequency_hz, dtype=float)
    rest = curves[0] if speeds is not None else curves
    ratio = pinion_teeth / wheel_teeth  # wheel turns per pinion turn
    rows = []
    for i, n in enumerate(np.asarray(nodal_diameter)):
        if n < 1:
            continue
        for h in harmonics:
            back, fwd = resonance_orders(h * wheel_teeth, int(n))
            for order, direction in ((back, "backward"), (fwd, "forward")):
                if order <= 0:
                    continue
                rate = int(order) * ratio
                if speeds is None:
                    w1, omega_at = rest[i] / rate, rest[i]
                else:
                    w1 = _first_crossing(speeds, curves[:, i], rate)
                    omega_at = rate * w1
                if not math.isfinite(w1):
                    continue
                w2 = w1 * ratio
                rows.append(
                    {
                        "frequency_hz": float(omega_at / (2 * np.pi)),
                        "frequency_rest_hz": float(rest[i] / (2 * np.pi)),
                        "nodal_diameter": int(n),
                        "harmonic": int(h),
                        "order": int(order),
                        "direction": direction,
                        "wheel_speed_rad_s": w2,
                        "pinion_speed_rad_s": w1,
                    }
                )
    return rows


def gear_nodal_diameter_resonances(
    scene,
    modes: ModalAnalysis,
    member: int,
    *,
    at: ModesAtSpeed | None = None,
    max_speed: float | None = None,
    harmonics=(1, 2),
    n_modes: int = 40,
) -> list[dict]:
    """The seed's (3.9) resonances of one condensed gear of a hybrid scene: the pinion (or
    input) speeds at which the gear's meshes excite its nodal-diameter web modes.

    The gear's web modes are those of :func:`nodal_diameter_modes` (``member``) with n >= 1 and
    more than half of their kinetic energy in its body. The gear has Z teeth (its rim
    stations) and turns ``member.ratio`` times per turn of the scene's pinion or input (its
    ``speed_ratio``, > 0, from the tooth counts); every mesh it is in passes Z teeth per turn
    of it, so all of them excite the orders h Z ± n (:func:`nodal_diameter_resonances` with
    wheel teeth Z and pinion teeth z1 = Z × speed_ratio): a pair's wheel, a flexible pinion
    (z1 = Z), an idler or a two-gear body's gears alike.

    Args:
        scene: a hybrid scene (:class:`~jaxgear.scenes.HybridPair`, a hybrid train).
        modes: its :func:`modal_analysis` (with K̄_m, or zeros for the structure alone).
        member: the condensed gear's index in ``scene.members``.
        at: the modes at speed (:func:`modes_at_speed`): each resonance is then the first
            speed where the mode's frequency at speed meets the order; None: the frequencies at
            rest.
        max_speed: keep the resonances at pinion (input) speeds up to this (rad/s); None: all.
        harmonics: the mesh harmonics h (default the first two).
        n_modes: the lowest elastic modes of the structure examined.

    Returns:
        One dict per resonance, ``member``, ``teeth`` (Z), ``speed_ratio`` and the keys of
        :func:`nodal_diameter_resonances` (``frequency_hz``, ``nodal_diameter``, ``harmonic``,
        ``order``, ``direction``, ``wheel_speed_rad_s``: the gear's speed,
        ``pinion_speed_rad_s``: the pinion's or input's).

    Raises:
        ValueError: ``member`` is not a condensed body of the scene (one line, naming the
            allowed members).
    """
    member = _condensed_member(scene, member, "gear_nodal_diameter_resonances")
    nd = nodal_diameter_modes(scene, modes, n_modes=n_modes, member=member)
    gear = scene.members[member]
    web = (nd["rim_share"] > 0.5) & (nd["nodal_diameter"] >= 1)
    if at is None:
        freqs, grid = nd["frequency_hz"][web], None
    else:
        freqs = np.asarray(at.omega)[:, nd["mode"][web]] / (2 * np.pi)
        grid = np.asarray(at.speeds)
    Z, ratio = int(gear.rim_dofs.shape[0]), float(gear.ratio)
    tag = {"member": member, "teeth": Z, "speed_ratio": ratio}
    rows = nodal_diameter_resonances(
        freqs, nd["nodal_diameter"][web], Z, Z * ratio, tuple(harmonics), speeds=grid
    )
    return [tag | r for r in rows if max_speed is None or r["pinion_speed_rad_s"] <= max_speed]


def excited_omega(modes: ModalAnalysis) -> Float[Array, ""]:
    """Highest natural frequency (rad/s) among the modes the mesh excites: elastic modes with a
    mesh strain-energy share >= ``MESH_ENERGY_MIN`` (5 %; the highest elastic one if none): the
    mode the automatic time step resolves (docs/dynamics.md, "Time step and accuracy")."""
    elastic = ~modes.rigid
    excited = elastic & (modes.mesh_energy >= MESH_ENERGY_MIN)
    excited = jnp.where(jnp.any(excited), excited, elastic)
    return jnp.max(jnp.where(excited, modes.omega, 0.0))


def steps_for_mode(
    omega_max,
    mesh_period_angle,
    speeds,
    mesh_rate: float = 1.0,
    multiple: int = 1,
    per_mode: int = STEPS_PER_MODE,
) -> np.ndarray:
    """N_s = the smallest ``multiple`` × 2^j >= max(64 r, 40 · f_max / f_mesh) at each pinion
    speed (rad/s, concrete): the rule of :func:`~jaxgear.dynamics.auto_steps_per_period` for
    the highest excited mode ``omega_max`` (rad/s), with f_mesh = Ω / θ_m (Hz), θ_m =
    ``mesh_period_angle`` = 2π/z1, r = ``mesh_rate`` the periods of the fastest mesh per
    period of the first (1 for a pair; a train's later stage may pass teeth faster) and
    ``multiple`` D (1: powers of two; a train: the steps that divide every mesh's period);
    ``per_mode`` the steps per period of that mode (default :data:`STEPS_PER_MODE`, 40)."""
    sp = np.asarray(speeds, dtype=float)
    if np.any(~(sp > 0)):
        raise ValueError("speeds must be > 0 rad/s")
    ratio = float(omega_max) * float(mesh_period_angle) / (2 * np.pi * sp)  # f_max / f_mesh
    n = np.maximum(MIN_STEPS_PER_PERIOD * float(mesh_rate), np.ceil(int(per_mode) * ratio))
    if np.any(n > MAX_STEPS_PER_SPEED):
        low = (
            int(per_mode)
            * float(omega_max)
            * float(mesh_period_angle)
            / (2 * np.pi * MAX_STEPS_PER_SPEED)
        )
        raise ValueError(
            f"speeds: {sp.min():.6g} rad/s would need {n.max():.3g} time steps per mesh period "
            f"to resolve the highest mode the mesh excites ({omega_max / (2 * np.pi):.6g} Hz): "
            f"allowed >= {low:.3g} rad/s (a slower pinion is quasi-static: jaxgear run)"
        )
    doublings = np.maximum(0.0, np.ceil(np.log2(n / int(multiple))))
    return (int(multiple) * 2**doublings).astype(int)
