"""Gear whine in the frequency domain: the periodic steady state of the lumped dynamics
linearised about the quasi-static operating point, by a harmonic balance over the time-varying
mesh stiffness (docs/whine.md).

Write the coordinates X(t) = x_qs(θ) + y(t) at the nominal motion θ = Ω t, x_qs the static
contact solution at each mesh position (the lumped model's static rows, on the same structure
and table as its time integration). With the active set of the static solution held, the
equations of motion (seed (2.37)) are linear and the vibration about x_qs obeys

    M ÿ + C ẏ + (K_s + K_m(θ)) y = −M ẍ_qs − C ẋ_qs,

K_m(θ) = Σ_c w_c k_c l_c V_c V_cᵀ the tangent mesh stiffness at θ (w_c the static contact
weights). Both K_m and x_qs repeat over the span (one mesh period for a pair); with ω the
span's angular frequency, y = Σ_{h=-H..H} Y_h e^{i h ω t} and the harmonic balance

    (K_s − (hω)² M + i hω C) Y_h + Σ_j K̂_{h−j} Y_j = ((hω)² M − i hω C) X̂_h,   |h| <= H,

(K̂, X̂: the Fourier coefficients of K_m and x_qs over the span) couples the harmonics through
the stiffness's (:class:`HarmonicBalance`, the multi-harmonic method); keeping only K̂_0 gives
the time-invariant model excited by the quasi-static motion, "the transmission error as a
displacement source" (:class:`TransmissionErrorSource`).

Sources: the equations of motion are the seed's (2.31)-(2.37) with the active set held; the
harmonic balance of a parametrically excited mesh: Blankenship & Kahraman, J. Sound Vib. 185
(1995); Perret-Liaudet, J. Sound Vib. 196 (1996) (solved here directly, not iterated).
"""

from __future__ import annotations

import fractions
from typing import NamedTuple

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Bool, Complex, Float, Int

from fem_prep.resources import check_memory

from .._contact import ContactLaw, ExactContact, contact_law
from .._util import check_integer, checked_on_host, each_solve, int_rows, is_traced
from ._model import (
    AbstractDynamicModel,
    MeshTable,
    _prep,
    _rigid_penalty,
    cell_stiffness,
    deviation_periods,
    mesh_table,
)
from ._whine_methods import (
    AbstractWhineMethod,
    HarmonicBalance,
    QuasiPeriodicBalance,
    TransmissionErrorSource,
    check_whine_speeds,
)
from ._whine_qp import (
    _torus_static,
    group_positions,
    harmonic_set,
    mesh_groups,
    quasi_periodic_balance,
    torus_coefficients,
    torus_grid,
)

__all__ = [
    "MAX_WHINE_GRID",
    "MAX_WHINE_WORK",
    "WHINE_WORK_PER_CPU_S",
    "AbstractWhineMethod",
    "HarmonicBalance",
    "QuasiPeriodicBalance",
    "TransmissionErrorSource",
    "WhineResponse",
    "WhineSize",
    "balance_harmonics",
    "check_whine_size",
    "fourier_coefficients",
    "group_rows",
    "harmonic_balance",
    "whine_response",
    "whine_size",
]


#: the most static solves a whine's table may hold: positions over its span (with
#: :class:`QuasiPeriodicBalance` the torus grid, the product of the groups' periods)
MAX_WHINE_GRID = 1_000_000
#: the whine's work (:func:`whine_size`) per CPU second, measured: the two-stage whine benchmark
#: (docs/bench/whine_two_stage.json) balances 200 speeds of the two-stage train (33 harmonics
#: × its 24 mesh coordinates' bound: 200 × 792³) in 10.2 CPU s on the 2-core machine
WHINE_WORK_PER_CPU_S = 200 * 792**3 / 10.2
#: the most work a whine may plan (:func:`whine_size`): speeds × the coupled balance's
#: unknowns³, its LU's cost per speed, which grows fastest: about 100 CPU s at
#: :data:`WHINE_WORK_PER_CPU_S` (more where the memory is the bound)
MAX_WHINE_WORK = 1e12


class WhineSize(NamedTuple):
    """A whine's size before any work (:func:`whine_size`): ``speeds``; ``harmonics`` the
    balance's harmonics (2H + 1; with :class:`QuasiPeriodicBalance` its multi-index set);
    ``unknowns`` the coupled system's (harmonics × the mesh coordinates; each harmonic alone
    for :class:`TransmissionErrorSource`: the n coordinates); ``static_points`` the static
    solves of its table; ``work`` speeds × unknowns³ (+ each harmonic's n³ factor) and
    ``bytes`` its peak memory (the factors, the coupled matrix, the outputs), estimated."""

    speeds: int
    harmonics: int
    unknowns: int
    static_points: int
    work: float
    bytes: float

    @property
    def seconds(self) -> float:
        """The balance's CPU seconds at the measured rate :data:`WHINE_WORK_PER_CPU_S`."""
        return self.work / WHINE_WORK_PER_CPU_S

    def line(self) -> str:
        """One printed line of the estimate."""
        return (f"whine: {self.speeds} speeds x {self.harmonics} harmonics, "
                f"{self.static_points} static positions, a balance of {self.unknowns} "
                f"unknowns per speed (about {self.seconds:.2g} CPU s, {self.bytes / 1e9:.2g} GB; "
                "estimate)")


def balance_harmonics(method: AbstractWhineMethod, groups: int = 1) -> int:
    """The harmonics the balance couples: 2H + 1; with :class:`QuasiPeriodicBalance` over G
    groups the multi-indices with one group's |h_g| <= H and the others' <= S
    (:func:`harmonic_set`'s size, counted: (2S + 1)^(G−1) ((2S + 1) + 2 G (H − S)))."""
    H = int(method.harmonics)
    if not isinstance(method, QuasiPeriodicBalance):
        return 2 * H + 1
    S, G = int(method.sidebands), int(groups)
    return (2 * S + 1) ** (G - 1) * ((2 * S + 1) + 2 * G * (H - S))


def whine_size(speeds: int, method: AbstractWhineMethod, static_points: int,
               coordinates: int, mesh_coordinates: int, groups: int = 1) -> WhineSize:
    """The size of a whine (:class:`WhineSize`) of ``speeds`` speeds by ``method`` on a model
    of ``coordinates`` n coordinates whose meshes span ``mesh_coordinates`` r of them (the
    mesh stiffness's basis, at most 12 per mesh of a lumped 3D scene), a table of
    ``static_points`` static solves and ``groups`` mesh-frequency groups."""
    n = int(coordinates)
    hs = balance_harmonics(method, groups)
    own = hs if isinstance(method, QuasiPeriodicBalance) else int(method.harmonics) + 1
    if method.parametric:  # the coupled balance, and each harmonic's n x n factor
        u = hs * min(int(mesh_coordinates), n)
        work = float(speeds) * (float(u) ** 3 + own * float(n) ** 3)
    else:  # each harmonic alone
        u = n
        work = float(speeds) * own * float(n) ** 3
    mem = 16.0 * (own * n * n + u * u + 3 * speeds * own * n) + 16.0 * static_points * n
    return WhineSize(int(speeds), hs, u, int(static_points), work, mem)


def check_whine_size(size: WhineSize, names: tuple[str, str, str], values: tuple) -> None:
    """Refuse, before any work, a whine over :data:`MAX_WHINE_GRID` static solves, over
    :data:`MAX_WHINE_WORK` or over half this machine's memory: one-line ``ValueError`` naming
    ``names`` (the speeds', harmonics' and positions' keys or arguments) with their
    ``values``, the estimate and the limit."""
    sp, harm, pos = (f"{k} = {v}" for k, v in zip(names, values, strict=True))
    if size.static_points > MAX_WHINE_GRID:
        raise ValueError(
            f"{pos}: out of range: {size.static_points} static solves in the whine's table, "
            f"allowed <= {MAX_WHINE_GRID:.0e}: fewer positions per period"
        )
    if size.work > MAX_WHINE_WORK:
        raise ValueError(
            f"{sp}, {harm}: out of range: {size.speeds} speeds x a balance of {size.unknowns} "
            f"unknowns ({size.harmonics} harmonics) is about {size.work:.3g} work (speeds x "
            f"unknowns^3, about {size.seconds:.2g} CPU s at the measured rate), allowed <= "
            f"{MAX_WHINE_WORK:.0e} (about {MAX_WHINE_WORK / WHINE_WORK_PER_CPU_S:.0f} CPU s): "
            "fewer speeds or harmonics"
        )
    check_memory(f"{sp}, {harm}", size.bytes,
                 f"{size.speeds} speeds x a balance of {size.unknowns} unknowns",
                 "fewer speeds or harmonics")


def fourier_coefficients(samples, harmonics: int, offset: float = 0.5) -> Complex[Array, "h ..."]:
    """The complex Fourier coefficients ĝ_h, h = −``harmonics``..``harmonics``, of a periodic
    function sampled at P equally spaced phases of its period, s_r = (r + ``offset``)/P (the
    lumped table's mid-points for the default ½): ĝ_h = (1/P) Σ_r g(s_r) e^{−2πi h s_r}, so that
    g(s) ≈ Σ_h ĝ_h e^{2πi h s}.

    Args:
        samples: (P, ...) real or complex. harmonics: H >= 0 (int), with P >= 2H + 1 (no
            aliasing of the kept harmonics).

    Returns:
        (2H + 1, ...) complex, index h + H.

    Raises:
        ValueError: P < 2H + 1.
    """
    samples = jnp.asarray(samples)
    P = samples.shape[0]
    if P < 2 * harmonics + 1:
        raise ValueError(
            f"samples: {P} per period for harmonics = {harmonics}: allowed >= 2 harmonics + 1 "
            f"= {2 * harmonics + 1}"
        )
    dtype = jnp.result_type(samples.dtype, jnp.float32)
    real = jnp.finfo(dtype).dtype
    h = jnp.arange(-harmonics, harmonics + 1, dtype=real)
    s = (jnp.arange(P, dtype=real) + offset) / P
    E = jnp.exp(-2j * jnp.pi * h[:, None] * s[None, :]) / P  # (2H+1, P)
    return jnp.tensordot(E, samples, axes=(1, 0))


def harmonic_balance(
    M,
    C,
    K,
    stiffness_harmonics,
    force_harmonics,
    omega,
    *,
    parametric: bool = True,
    gauge=None,
    basis=None,
    real: bool = False,
) -> Complex[Array, "h n"]:
    """The periodic solution y = Σ_h Y_h e^{i h ω t} (h = −H..H) of M ÿ + C ẏ + (K + K_m(t)) y
    = f(t), K_m(t) = Σ_k K̂_k e^{i k ω t}, f(t) = Σ_h F̂_h e^{i h ω t}, truncated at H:

        (K − (hω)² M + i hω C) Y_h + Σ_{j=−H..H} K̂_{h−j} Y_j = F̂_h.

    With a ``basis`` B (n, r) of the mesh stiffness (K_m(t) = B K_r(t) Bᵀ, ``stiffness_harmonics``
    then K̂_r (4H + 1, r, r)), the coupling is solved on the r (2H + 1) unknowns Z_h = Bᵀ Y_h:
    with D_h = K + B K̂_r,0 Bᵀ − (hω)² M + i hω C, (I + G 𝕂) Z = Bᵀ D⁻¹ F, G_h = Bᵀ D_h⁻¹ B and
    𝕂_hj = K̂_r,h−j (h ≠ j), then Y_h = D_h⁻¹ (F_h − B Σ_j 𝕂_hj Z_j): the same solution (no
    approximation) at (2H + 1) n³ + ((2H + 1) r)³ instead of ((2H + 1) n)³ (a lumped pair's
    mesh spans r <= 12 of its n coordinates).

    Args:
        M, C, K: (n, n) mass (kg or kg·m²), damping and time-invariant stiffness (SI).
        stiffness_harmonics: K̂_k, k = −2H..2H, shape (4H + 1, n, n) (index k + 2H), or
            (4H + 1, r, r) on ``basis``.
        force_harmonics: F̂_h, shape (2H + 1, n) (index h + H).
        omega: ω (rad/s), scalar (map it over a sweep with ``jax.lax.map``: its harmonic
            solves are unbatched LUs, which a ``vmap`` would batch again).
        parametric: False keeps only K̂_0 (each harmonic alone).
        gauge: None, or an (n, n) matrix added to the h = 0 block (pins rigid-body modes of
            K + K̂_0 that the forcing does not load).
        basis: None, or B (n, r) with K_m(t) = B K_r(t) Bᵀ.
        real: the system and its forcing are real in time (M, C, K real, K̂_−k = conj K̂_k,
            F̂_−h = conj F̂_h): the harmonics h < 0 are the conjugates of h > 0, and only
            h >= 0 is factored (half the work).

    Returns:
        Y_h, shape (2H + 1, n), complex (index h + H).
    """
    F = jnp.asarray(force_harmonics)
    n_h, n = F.shape
    H = (n_h - 1) // 2
    Kh = jnp.asarray(stiffness_harmonics)
    B = jnp.eye(n, dtype=M.dtype) if basis is None else jnp.asarray(basis)
    r = B.shape[1]
    h = jnp.arange(-H, H + 1)
    # the harmonics factored: h >= 0 alone for a real system (h < 0 their conjugates)
    own = h[H:] if real else h
    wo = own * omega
    D = (
        K[None]
        - (wo**2)[:, None, None] * M[None]
        + 1j * wo[:, None, None] * C[None]
        + (B @ Kh[2 * H] @ B.T)[None]
    )  # (2H+1 or H+1, n, n)
    if gauge is not None:
        D = D.at[0 if real else H].add(gauge)

    def both_sides(x):  # the h >= 0 rows of a real system, completed with h < 0
        return jnp.concatenate([jnp.conj(x[1:][::-1]), x], axis=0) if real else x

    if not parametric:
        return both_sides(each_solve(D, F[H:] if real else F))
    # 𝕂: the stiffness harmonics K̂_{h−j} off the diagonal (the diagonal's K̂_0 is in D)
    diff = h[:, None] - h[None, :] + 2 * H  # (2H+1, 2H+1)
    coupling = jnp.where((diff == 2 * H)[..., None, None], 0.0, Kh[diff])  # (h, j, r, r)
    coupling = coupling.transpose(0, 2, 1, 3).reshape(n_h * r, n_h * r)
    n_own = own.shape[0]
    Fo = F[H:] if real else F
    rhs = jnp.concatenate([Fo[:, :, None], jnp.broadcast_to(B.astype(F.dtype), (n_own, n, r))], -1)
    # (h, n, 1 + r): D⁻¹F, D⁻¹B, one unbatched LU per harmonic (jaxgear._util.each_solve)
    sol = both_sides(each_solve(D, rhs))
    DF, DB = sol[..., 0], sol[..., 1:]
    G = jnp.einsum("nr,hns->hrs", B, DB)  # (h, r, r)
    g = (DF @ B).reshape(-1)  # (h r,)
    GK = jnp.einsum("hrs,hsx->hrx", G, coupling.reshape(n_h, r, -1)).reshape(n_h * r, -1)
    Z = jnp.linalg.solve(jnp.eye(n_h * r, dtype=GK.dtype) + GK, g)
    KZ = (coupling @ Z).reshape(n_h, r)
    return DF - jnp.einsum("hnr,hr->hn", DB, KZ)


def _mesh_basis(V, mask) -> np.ndarray | None:
    """An orthonormal basis (n, r) of the structure vectors of every cell on the flanks at
    every position (concrete; None where they are traced: the full coordinates then): the
    mesh stiffness is B K_r Bᵀ, K_r = Bᵀ K_m B, exactly."""
    if is_traced((V, mask)):
        return None
    V = np.asarray(V).reshape(-1, np.shape(V)[-1])[np.asarray(mask).reshape(-1)]
    if V.shape[0] == 0:
        return None
    _, sv, vt = np.linalg.svd(V, full_matrices=False)
    r = int(np.sum(sv > sv[0] * 1e3 * np.finfo(V.dtype).eps))
    if r >= V.shape[1]:
        return None
    return vt[:r].T


def _contact_basis(scene) -> np.ndarray | None:
    """The columns of the identity at the coordinates every cell's structure vector can reach
    (:meth:`~jaxgear.scenes.Scene.contact_dofs`, static): a basis of the mesh stiffness known
    without the cells' values (under jit or grad, where :func:`_mesh_basis` cannot see them);
    None where the scene does not know them or they are every coordinate."""
    dofs = scene.contact_dofs()
    n = scene.mass().shape[0]
    if dofs is None or len(dofs) >= n:
        return None
    return np.eye(n)[:, list(dofs)]


class WhineResponse(eqx.Module):
    """The frequency-domain steady state of a lumped model (:func:`whine_response`) at S speeds,
    H + 1 orders (0..H of the span's fundamental; of the mesh frequency for a pair), n
    coordinates, m meshes, r bearing-force components.

    One-sided amplitudes: a quantity q(t) ≈ Re Σ_{h=0..H} q_h e^{i h ω t} = Σ |q_h| cos(hωt +
    arg q_h), t on the clock of the nominal motion θ = Ω t (the time records of
    :func:`~jaxgear.dynamics.simulate`, ``DynamicResponse.time``); q_0 the mean.

    Attributes:
        speed: pinion speeds Ω (rad/s), (S,). frequency: the first mesh's frequency (Hz),
            (S,): q ω/2π over a span of q of its periods (ω the span's fundamental; the mesh
            frequency of a pair); an output's frequency is ``frequency * orders``.
        orders: the harmonics' orders of the first mesh's frequency, (H + 1,): h / q over a
            span of q mesh periods (h for a pair).
        coordinates: X_h (SI units of the coordinates), (S, H + 1, n), complex.
        quasi_static: the quasi-static motion's harmonics, (H + 1, n), complex.
        transmission_error: each mesh's dynamic TE (u·X − e_ref)/cos β_b (m), (S, H + 1, m).
        mesh_force: each mesh's total flank-normal force (N), (S, H + 1, m), from the force
            reconstructed over the span (the stiffness times the vibration is a product of
            periodic functions).
        bearing_force: R X (N), (S, H + 1, r).
        static_force: each mesh's static force F_s (N), (m,).
        min_mesh_force: the smallest reconstructed mesh force over the span (N), (S, m).
        contact_loss: where min_mesh_force <= 0, (S, m): the linear result does not hold there
            (the time domain finds contact loss; a cell-wise separation before it is not
            flagged).
        nonlinearity: how far the vibration leaves the held active set, (S, m): the largest
            over the span of |Σ_c k l (max(g_c, 0) − w_c g_c)| / F_s, g_c = g_qs,c + V_c·y the
            cell's total approach (the exact law's force against the linear one): the contact
            force of cells that the vibration would bring into or out of contact (relieved
            cells engaging early or late). The linear result is the time domain's to about this
            fraction of F_s in the mesh force; a few per cent and more: not linear.
        order_group, group_order: :class:`QuasiPeriodicBalance` only (else None): the
            mesh-frequency group of each output order and its order within it, (h,) ints; the
            outputs are the mean (group 0, order 0), then orders 1..H of group 0, of group 1,
            ...; :attr:`orders` their frequencies over :attr:`frequency` (the first mesh's).
        mesh_group: :class:`QuasiPeriodicBalance` only: each mesh's group (static, m ints;
            group g's meshes share one mesh period, group 0 is the first mesh's).
        mesh_angle: the P positions the balance samples (:class:`HarmonicBalance` and
            :class:`TransmissionErrorSource` of a lumped model; else None): the scene angles θ
            (rad, the first mesh's pinion), (P,), θ_r = (r + ½) Δθ over the span
            (:func:`~jaxgear.dynamics.span_periods` mesh periods, Δθ = 2π/(z1 ``positions``)),
            the quasi-static solution's of :func:`~jaxgear.quasi_static` at those angles.
        mesh_stiffness: each mesh's tangent mesh stiffness at the quasi-static solution there,
            Σ_c w_c k_c l_c over its cells (N/m, flank-normal, as
            :attr:`~jaxgear.MeshResult.mesh_stiffness`), (P, m): the scalar of K_m(θ) = Σ_c
            w_c k_c l_c V_c V_cᵀ, whose Fourier coefficients couple the harmonics. None where
            :attr:`mesh_angle` is.
        static_transmission_error: each mesh's quasi-static TE (u·x_qs − e_ref)/cos β_b (m,
            positive under load: the driven gear lags; as
            :attr:`~jaxgear.MeshResult.transmission_error`), (P, m): the excitation whose
            harmonics ``transmission_error`` tends to as the speed goes to zero. None where
            :attr:`mesh_angle` is.
    """

    speed: Float[Array, " S"]
    frequency: Float[Array, " S"]
    orders: Float[Array, " h"]
    coordinates: Complex[Array, "S h n"]
    quasi_static: Complex[Array, "h n"]
    transmission_error: Complex[Array, "S h m"]
    mesh_force: Complex[Array, "S h m"]
    bearing_force: Complex[Array, "S h r"]
    static_force: Float[Array, " m"]
    min_mesh_force: Float[Array, "S m"]
    contact_loss: Bool[Array, "S m"]
    nonlinearity: Float[Array, "S m"]
    order_group: Int[Array, " h"] | None = None
    group_order: Int[Array, " h"] | None = None
    mesh_group: tuple | None = eqx.field(static=True, default=None)
    mesh_angle: Float[Array, " P"] | None = None
    mesh_stiffness: Float[Array, "P m"] | None = None
    static_transmission_error: Float[Array, "P m"] | None = None


def _one_sided(c, H):
    """Two-sided coefficients (2H + 1, ...) → one-sided amplitudes (H + 1, ...)."""
    return jnp.concatenate([c[H : H + 1], 2.0 * c[H + 1 :]], axis=0)


def whine_response(
    model: AbstractDynamicModel,
    speeds,
    method: AbstractWhineMethod = HarmonicBalance(),
    *,
    positions: int = 256,
    contact: ContactLaw = ExactContact(),
) -> WhineResponse:
    """Gear whine in the frequency domain (docs/whine.md): the periodic response of a lumped
    model linearised about its quasi-static solution, every coordinate, TE, mesh force and
    bearing force at each order of the mesh frequency, over speeds.

    The quasi-static solution and the tangent mesh stiffness come from the static contact
    solve at ``positions`` positions per period of the first mesh, over the model's span
    (:func:`~jaxgear.dynamics.span_periods`), on the structure the time integration uses;
    the damping is the model's. Exact for the lumped model (the time domain of
    :func:`~jaxgear.dynamics.simulate`) where no cell changes contact state about the
    quasi-static active set, up to the truncation at H harmonics and the sampling of the
    stiffness at ``positions`` points; ``contact_loss`` marks where it cannot hold.

    Each model kind states the methods it solves (its
    :attr:`~jaxgear.dynamics.AbstractDynamicModel.whine_methods`, checked here before any work)
    and solves them in its :meth:`~jaxgear.dynamics.AbstractDynamicModel.whine`: the lumped
    one as below, a hybrid pair in the twisted coordinates of its cyclic bodies, a planetary
    stage on its carrier-frame system (docs/whine.md).

    Args:
        model: a dynamic model whose kind has whine methods: a lumped
            :class:`~jaxgear.dynamics.DynamicModel` without coast flanks, a
            :class:`~jaxgear.dynamics.HybridModel` (a pair), a
            :class:`jaxgear.planetary.PlanetaryModel`.
        speeds: pinion speeds Ω (rad/s) > 0, scalar or (S,).
        method: :class:`HarmonicBalance` (default, the parametric coupling) or
            :class:`TransmissionErrorSource` (the mean stiffness alone), with its H, both over
            the span; or :class:`QuasiPeriodicBalance` (a train whose meshes run at several
            mesh frequencies: each mesh's orders of its own frequency, the static solve on the
            torus grid of the mesh phases).
        positions: positions per mesh period (int >= 4H + 1 over the span; with
            :class:`QuasiPeriodicBalance` a multiple of the model's ``steps_multiple()`` giving
            every mesh period >= 4H + 1 positions, or a tuple of one int per mesh-frequency
            group: N_g steps per first-mesh period of group g's own table, a multiple of the
            denominator of its period ratio T_g/T_1, its period N_g T_g/T_1 >= 4H + 1 steps;
            the torus grid is the product of those, e.g. (140, 35) for the two-stage: 140 × 127).
        contact: the contact law of the static solve (its tangent weights make K_m).

    Returns:
        :class:`WhineResponse` (S = 1 for a scalar speed).

    Raises:
        TypeError: a kind without gear whine, or a method it does not solve (one line, before
            any work). ValueError: coast flanks, a speed <= 0,
            too few positions; with :class:`QuasiPeriodicBalance`, manufacturing deviations or
            positions that are not a multiple of ``steps_multiple()`` (a tuple: not one
            positive int per group, or an entry not a multiple of its group's denominator).
    """
    if not isinstance(model, AbstractDynamicModel):
        raise TypeError(
            f"model: {type(model).__name__}: allowed a jaxgear.dynamics.AbstractDynamicModel "
            "(a lumped DynamicModel, a HybridModel, a jaxgear.planetary.PlanetaryModel)"
        )
    model.check_whine_method(method)  # what the model kind declares, before any work
    return model.whine(speeds, method, positions=positions, contact=contact)


def lumped_whine(
    model: AbstractDynamicModel,
    speeds,
    method: AbstractWhineMethod,
    *,
    positions: int = 256,
    contact: ContactLaw = ExactContact(),
) -> WhineResponse:
    """:func:`whine_response` of a lumped :class:`~jaxgear.dynamics.DynamicModel` (its
    :meth:`~jaxgear.dynamics.DynamicModel.whine`): the arguments, result and errors are
    :func:`whine_response`'s."""
    if not isinstance(method, AbstractWhineMethod):
        raise TypeError(
            f"method = {method!r}: allowed HarmonicBalance(...), TransmissionErrorSource(...) or "
            "QuasiPeriodicBalance(...)"
        )
    if model.coast_flanks():
        raise ValueError(
            "model: coast flanks (backlash): the linearised whine holds on the drive flanks "
            "only (allowed a scene without coast flanks)"
        )
    quasi = isinstance(method, QuasiPeriodicBalance)
    if quasi and isinstance(positions, (tuple, list)):  # one per group: checked by the method
        positions = group_positions(positions, len(mesh_groups(model)[1]))
    else:
        check_integer("positions", positions, 4)
        positions = int(positions)
    span = int(model.span_periods())
    H = int(method.harmonics)
    if isinstance(positions, int) and positions * span < 4 * H + 1:
        raise ValueError(
            f"positions = {positions}: allowed >= (4 harmonics + 1) / span periods = "
            f"{-(-(4 * H + 1) // span)} for harmonics = {H}"
        )
    check_whine_speeds(speeds)
    # the size estimated and refused before the static solves (one line)
    n, m = int(model.scene.mass().shape[0]), len(model.scene.base_planes)
    if quasi:
        periods = mesh_groups(model)[1]
        rows = group_rows(positions, periods, H, int(model.steps_multiple()))
        size = whine_size(np.size(speeds), method, int(np.prod(rows)), n, 12 * m, len(periods))
    else:
        size = whine_size(np.size(speeds), method, positions * span, n, 12 * m)
    check_whine_size(size, ("len(speeds)", "method.harmonics", "positions"),
                     (np.size(speeds), H, positions))
    law = contact_law(contact, model.dtype)
    if quasi:
        return _quasi_periodic(model, speeds, method, positions, law)
    prep = _prep(model, law, int(positions))
    speeds = jnp.atleast_1d(jnp.asarray(speeds, model.dtype))
    basis = _mesh_basis(prep.table.V, prep.table.mask)
    if basis is None and is_traced((prep.table.V, prep.table.mask)):
        basis = _contact_basis(model.scene)  # traced (under jit): the scene's static DOFs
    basis = None if basis is None else jnp.asarray(basis, model.dtype)
    return _whine(model, prep, speeds, method, basis)


@eqx.filter_jit
def _whine(model, prep, speeds, method, basis) -> WhineResponse:
    H = method.harmonics
    scene, table = model.scene, prep.table
    S = table.span
    steps = jnp.arange(S)
    V = table.take(table.V, steps)  # (S, c, n)
    mask = table.take(table.mask, steps)
    k, length = table.take(table.k, steps), table.take(table.length, steps)
    kl = jnp.where(mask, prep.static_weight * k * length, 0.0)  # (S, c)
    Km = jax.vmap(cell_stiffness)(V, kl)  # tangent mesh stiffness (S, n, n)
    x_qs = prep.static_x  # (S, n)
    gap = jnp.where(mask, jnp.einsum("sci,si->sc", V, x_qs) - table.take(table.delta0, steps), 0.0)
    if basis is not None:  # the mesh stiffness on the span of the structure vectors
        Km = basis.T @ Km @ basis
    Kh = fourier_coefficients(Km, 2 * H)  # (4H+1, n, n) or (4H+1, r, r)
    Xh = fourier_coefficients(x_qs, H)  # (2H+1, n)
    M, Ks, C = scene.mass(), scene.stiffness(), model.damping
    k_ref = jnp.trace(jnp.real(Kh[2 * H])) / Kh.shape[1]
    gauge = _rigid_penalty(scene, k_ref)
    span_angle = table.period_angle * (S / table.step_count)
    h = jnp.arange(-H, H + 1)

    def at(speed):
        omega = 2 * jnp.pi * speed / span_angle
        w = (h * omega)[:, None]
        F = (w**2) * (Xh @ M.T) - 1j * w * (Xh @ C.T)  # ((hω)² M − i hω C) X̂_h
        Y = harmonic_balance(
            M,
            C,
            Ks,
            Kh,
            F,
            omega,
            parametric=method.parametric,
            gauge=gauge,
            basis=basis,
            real=True,
        )  # (2H+1, n)
        # the vibration at the span's positions, and the mesh force there
        s = (steps.astype(x_qs.dtype) + 0.5) / S
        E = jnp.exp(2j * jnp.pi * s[:, None] * h[None, :])  # (S, 2H+1)
        y = jnp.real(E @ Y)  # (S, n)
        vy = jnp.einsum("sci,si->sc", V, y)
        f, _ = table.mesh_forces(prep.static_force_density * length + kl * vy)  # (S, m)
        # the force the held active set misplaces: the exact law's k l max(g, 0) against the
        # linear w k l g, at the total gap g = g_s + V·y
        g = gap + vy
        kl_all = jnp.where(mask, k * length, 0.0)
        wrong = kl_all * jnp.maximum(g, 0.0) - kl * g
        misplaced, _ = table.mesh_forces(wrong)
        return omega, Y, f, jnp.max(jnp.abs(misplaced), axis=0)

    # one speed at a time: vmapped, every LU of the balance would run as one batched LAPACK
    # call, which can deadlock XLA's CPU thread pool (jaxgear._util.each_solve)
    omega, Y, f, misplaced = jax.lax.map(at, speeds)
    X = jax.vmap(lambda y: _one_sided(Xh + y, H))(Y)  # (S_sp, H+1, n)
    fh = jax.vmap(lambda ff: _one_sided(fourier_coefficients(ff, H), H))(f)
    te, bearing = _te_and_bearings(scene, table, X)
    cb = jnp.stack([jnp.cos(p.base_helix_angle) for p in scene.base_planes])
    te_qs = (x_qs @ scene.te_vectors().T - table.e_max[0][None, :]) / cb[None, :]  # (S, m)
    k_mesh, _ = table.mesh_forces(kl)  # (S, m): Σ w k l of each mesh
    fm_qs, _ = table.mesh_forces(prep.static_force_density * length)
    fs = jnp.mean(fm_qs, axis=0)
    if fm_qs.shape[1] == 1:
        fs = scene.base_planes[0].normal_load(model.torque)[None]
    fmin = jnp.min(f, axis=1)
    q = S / table.step_count  # the span in first-mesh periods
    orders = jnp.arange(H + 1, dtype=model.dtype) / q
    return WhineResponse(
        speed=speeds,
        frequency=q * omega / (2 * jnp.pi),  # the first mesh's: frequency x orders in Hz
        orders=orders,
        coordinates=X,
        quasi_static=_one_sided(Xh, H),
        transmission_error=te,
        mesh_force=fh,
        bearing_force=bearing,
        static_force=fs,
        min_mesh_force=fmin,
        contact_loss=fmin <= 0.0,
        nonlinearity=misplaced / fs[None, :],
        mesh_angle=table.angle(steps),
        mesh_stiffness=k_mesh,
        static_transmission_error=te_qs,
    )


def _te_and_bearings(scene, table, X):
    """Each mesh's dynamic TE (u·X − e_ref)/cos β_b (m), (S, h, m), and the bearing forces R X
    (N), (S, h, r), of the one-sided coordinate harmonics X (S, h, n; h = 0 the mean)."""
    U = scene.te_vectors()
    cb = jnp.stack([jnp.cos(p.base_helix_angle) for p in scene.base_planes])
    te = jnp.einsum("shn,mn->shm", X, U.astype(X.dtype)) / cb[None, None, :]
    te = te.at[:, 0, :].add(-table.e_max[0] / cb)
    return te, jnp.einsum("shn,rn->shr", X, scene.reaction_matrix().astype(X.dtype))


def _quasi_periodic(model, speeds, method, positions, law) -> WhineResponse:
    """:func:`whine_response` with :class:`QuasiPeriodicBalance`: checks, the table over each
    group's own period, the torus grid, the basis; then :func:`_whine_torus`. ``positions``:
    an int (every group's steps per first-mesh period), or one int per group."""
    of_mesh, periods = mesh_groups(model)
    if deviation_periods(model.mods) > 1:
        raise ValueError(
            "model: manufacturing deviations: QuasiPeriodicBalance needs each mesh to repeat "
            "every mesh period (allowed mods without Deviations)"
        )
    H, Sb = int(method.harmonics), int(method.sidebands)
    multiple = int(model.steps_multiple())
    R = group_rows(positions, periods, H, multiple)  # refused here, before the table
    if isinstance(positions, tuple):  # one per group: each a multiple of its own denominator
        Ns = positions
        table = _group_table(model, of_mesh, periods, Ns)
    else:
        Ns = (int(positions),) * len(periods)
        table = mesh_table(model.scene, model.mods, positions, int(model.scene.scene_periods()))
        R = []
        for p in periods:
            k = of_mesh.index(periods.index(p))
            R.append(int(table.rows[k]))
            if fractions_of(positions, p) != R[-1] or R[-1] < 4 * H + 1:
                raise ValueError(
                    f"positions = {positions}: allowed a multiple of {multiple} giving every "
                    f"mesh period >= 4 harmonics + 1 = {4 * H + 1} steps (a period {p} of the "
                    f"first mesh's has {R[-1]})"
                )
    idx, rows = torus_grid(table, of_mesh, R)
    basis = _mesh_basis(table.V, table.mask)
    if basis is None:
        basis = _contact_basis(model.scene)
    n = model.scene.mass().shape[0]
    basis = np.eye(n) if basis is None else basis
    hs = harmonic_set(len(R), H, Sb)
    out = [np.zeros(len(R), int)] + [
        np.eye(len(R), dtype=int)[g] * k for g in range(len(R)) for k in range(1, H + 1)
    ]
    out = np.asarray(out)
    where = {tuple(h): i for i, h in enumerate(hs)}
    out_index = np.asarray([where[tuple(h)] for h in out])
    group = np.concatenate([[0], np.repeat(np.arange(len(R)), H)])
    order = np.concatenate([[0], np.tile(np.arange(1, H + 1), len(R))])
    spec = (tuple(R), int_rows(hs), int_rows(out), tuple(int(i) for i in out_index),
            tuple(int(g) for g in group), tuple(int(o) for o in order), tuple(of_mesh),
            tuple(Ns))
    response, failed = _whine_torus(model, table, law, spec, jnp.asarray(rows),
                                    jnp.asarray(idx),
                                    jnp.atleast_1d(jnp.asarray(speeds, model.dtype)),
                                    jnp.asarray(basis, model.dtype))
    message = ("whine_response: the static contact solve failed at some points of the torus "
               "grid (no contact or no convergence): check the load and the modifications")
    return checked_on_host(response, failed, message)


def _group_table(model, of_mesh, periods, Ns) -> MeshTable:
    """One table whose group-g meshes hold their rows at N_g = ``Ns[g]`` steps per first-mesh
    period (mesh k uses its first R_g = N_g T_g/T_1 rows, :attr:`MeshTable.rows`): each group's
    meshes from the table of its own N_g over a span of the numerator of T_g/T_1 first-mesh
    periods (whole periods of the group; the other meshes of that table are not read). Its
    ``theta`` and ``steps_per_period`` are group 0's (the step differs by group)."""
    tables = {g: mesh_table(model.scene, model.mods, Ns[g], periods[g].numerator)
              for g in range(len(periods))}
    R = [fractions_of(Ns[g], periods[g]) for g in range(len(periods))]
    top = max(R)

    def rows(a):  # a table's first ``top`` rows (its last repeated where it has fewer: unread)
        a = a[:top]
        return jnp.concatenate([a, jnp.repeat(a[-1:], top - a.shape[0], axis=0)], axis=0)

    sizes = tables[0].sizes
    start = np.cumsum([0] + [L * N for L, N in sizes])
    fields = {}
    for name in ("V", "k", "length", "delta0", "mask", "flank"):
        if getattr(tables[0], name) is None:
            fields[name] = None
            continue
        fields[name] = jnp.concatenate(
            [rows(getattr(tables[g], name))[:, start[k]:start[k + 1]] for k, g in
             enumerate(of_mesh)], axis=1)
    e_max = jnp.stack([rows(tables[g].e_max)[:, k] for k, g in enumerate(of_mesh)], axis=1)
    return MeshTable(rows(tables[0].theta), fields["V"], fields["k"], fields["length"],
                     fields["delta0"], fields["mask"], e_max, tables[0].period_angle,
                     sizes=sizes, rows=tuple(R[g] for g in of_mesh),
                     steps_per_period=Ns[0], flank=fields["flank"])


def group_rows(positions, periods, harmonics: int, multiple: int,
               where: str = "positions") -> list[int]:
    """The steps of each mesh-frequency group's own period (:class:`QuasiPeriodicBalance`),
    checked before any table is built: ``positions`` an int (steps per first-mesh period for
    every group: a multiple of ``multiple``, the model's ``steps_multiple()``) or one int per
    group (each a multiple of the denominator of its group's period ``periods[g]``, in
    first-mesh periods); every group's period >= 4 ``harmonics`` + 1 steps. One-line
    ValueError naming ``where`` otherwise."""
    H = int(harmonics)
    if isinstance(positions, tuple):
        R = []
        for g, (N, p) in enumerate(zip(positions, periods, strict=True)):
            R.append(fractions_of(N, p))
            if R[-1] < 0 or R[-1] < 4 * H + 1:
                raise ValueError(
                    f"{where} = {list(positions)!r}: group {g}'s (period {p} of the first "
                    f"mesh's) allowed a multiple of {p.denominator} giving its period >= 4 "
                    f"harmonics + 1 = {4 * H + 1} steps"
                )
        return R
    if positions % multiple:
        raise ValueError(
            f"{where} = {positions}: QuasiPeriodicBalance needs every mesh's period in "
            f"whole steps: allowed a multiple of {multiple}"
        )
    R = [fractions_of(positions, p) for p in periods]
    if min(R) < 4 * H + 1:
        g = R.index(min(R))
        raise ValueError(
            f"{where} = {positions}: allowed a multiple of {multiple} giving every mesh period "
            f">= 4 harmonics + 1 = {4 * H + 1} steps (a period {periods[g]} of the first "
            f"mesh's has {R[g]})"
        )
    return R


def fractions_of(positions: int, period) -> int:
    """The steps of a mesh period of ``period`` first-mesh periods at ``positions`` steps per
    first-mesh period (a whole number: checked by the caller)."""
    steps = positions * period
    return int(steps) if steps.denominator == 1 else -1


@eqx.filter_jit
def _whine_torus(model, table, law, spec, rows, idx, speeds, basis):
    R, hs, out, out_index, group, order, of_mesh, Ns = spec
    hs, out, out_index = np.asarray(hs), np.asarray(out), np.asarray(out_index)
    scene = model.scene
    N = rows.shape[0]
    x, weight, force_density, result = _torus_static(model.scene, table, model.torque, law, rows)
    cells = jnp.arange(table.V.shape[1])

    def take(f):
        return f[rows, cells]

    k, length, mask = take(table.k), take(table.length), take(table.mask)
    kl = jnp.where(mask, weight * k * length, 0.0)  # (N, c)
    Vb = table.V @ basis  # (rows, c, r)
    Vg = take(Vb)  # (N, c, r)
    Km = jax.vmap(cell_stiffness)(Vg, kl)  # (N, r, r)
    diff = hs[:, None, :] - hs[None, :, :]
    coupling = torus_coefficients(Km, R, diff)  # (Nh, Nh, r, r)
    Xh = torus_coefficients(x, R, hs)  # (Nh, n)
    M, Ks, C = scene.mass(), scene.stiffness(), model.damping
    k_ref = jnp.trace(jnp.real(coupling[(len(hs) - 1) // 2, (len(hs) - 1) // 2])) / basis.shape[1]
    gauge = _rigid_penalty(scene, k_ref)
    dtheta = table.period_angle / jnp.asarray(Ns, x.dtype)  # (G,) each group's step
    s = (idx.astype(x.dtype) + 0.5) / jnp.asarray(R, x.dtype)[None, :]  # (N, G) grid phases
    E = jnp.exp(2j * jnp.pi * (s @ jnp.asarray(hs.T, x.dtype)))  # (N, Nh)
    Eo = jnp.conj(E[:, out_index]).T / N  # (h_out, N): the coefficients at the outputs
    # V x one grid point at a time: take(table.V) would be (N, c, n), 15 GB for the housed
    # two-stage at 140 positions (71 120 points, 180 cells, 152 coordinates)
    vx = jax.lax.map(lambda a: table.V[a[0], cells] @ a[1], (rows, x))
    gap = jnp.where(mask, vx - take(table.delta0), 0.0)
    fs_density = force_density * length

    def at(speed):
        omega = 2 * jnp.pi * speed / (dtheta * jnp.asarray(R, x.dtype))  # (G,)
        nu = jnp.asarray(hs, x.dtype) @ omega  # (Nh,)
        F = (nu**2)[:, None] * (Xh @ M.T) - 1j * nu[:, None] * (Xh @ C.T)
        Y = quasi_periodic_balance(M, C, Ks, coupling, F, nu, gauge=gauge, basis=basis)  # (Nh, n)
        yb = jnp.real(E @ (Y @ basis))  # (N, r) the vibration on the basis over the grid
        vy = jnp.einsum("scr,sr->sc", Vg, yb)
        f, _ = table.mesh_forces(fs_density + kl * vy)  # (N, m)
        g = gap + vy
        kl_all = jnp.where(mask, k * length, 0.0)
        misplaced, _ = table.mesh_forces(kl_all * jnp.maximum(g, 0.0) - kl * g)
        return omega[0], Y[out_index], Eo @ f.astype(E.dtype), jnp.min(f, axis=0), jnp.max(
            jnp.abs(misplaced), axis=0)

    omega, Y, fh, fmin, misplaced = jax.lax.map(at, speeds)
    mean = jnp.concatenate([jnp.ones(1), 2.0 * jnp.ones(out.shape[0] - 1)]).astype(Xh.dtype)
    X = (Xh[out_index][None] + Y) * mean[None, :, None]  # (S, h, n) one-sided
    fh = fh * mean[None, :, None]
    te, bearing = _te_and_bearings(scene, table, X)
    fm_qs, _ = table.mesh_forces(fs_density)
    fs = jnp.mean(fm_qs, axis=0)
    # T_1/T_g = (R_1/N_1)/(R_g/N_g): each group's frequency over group 0's
    ratio = jnp.asarray([float(fractions.Fraction(R[0] * n, Ns[0] * r))
                         for r, n in zip(R, Ns, strict=True)], x.dtype)
    orders = (out @ ratio).astype(x.dtype)
    return WhineResponse(
        speed=speeds,
        frequency=omega / (2 * jnp.pi),
        orders=orders,
        coordinates=X,
        quasi_static=Xh[out_index] * mean[:, None],
        transmission_error=te,
        mesh_force=fh,
        bearing_force=bearing,
        static_force=fs,
        min_mesh_force=fmin,
        contact_loss=fmin <= 0.0,
        nonlinearity=misplaced / fs[None, :],
        order_group=jnp.asarray(group),
        group_order=jnp.asarray(order),
        mesh_group=of_mesh,
    ), jnp.any(result != 0)
