"""Dynamics of the hybrid scene (condensed FE bodies on the cells): Newmark in the cell space.

Equations of motion (seed (2.31)–(2.37), HYBRID.md §2), in the body frames of the members that
carry condensed bodies (K, M and the centrifugal load are constant there; the rim stations pass
under the fixed mesh as the bodies turn):

    M Ẍ + C Ẋ + K X + Σ_c P_c(V_c·X − δ0_c) V_c = T f_T + Ω² f_c,

with P_c = k_c l_c φ(Δ_c) the cell forces and Ω the pinion speed (each body at its own speed,
f_c scaled accordingly; the centrifugal load is always on in dynamics). Damping: Rayleigh,
C = α M + β K̄ with K̄ = K + K̄_m, K̄_m the mesh stiffness matrix averaged over the quasi-static
positions of one mesh period (seed (2.34); the lumped model's Rayleigh damping).

Newmark average acceleration (β = 1/4, γ = 1/2). The effective stiffness K_eff = K + a₀M + a₁C
is constant at one speed: it is inverted once, G_eff = K_eff⁻¹, and every step is a contact
problem in the space of the cells (:func:`jaxgear.solve_contact_cells`, no rigid mode: M makes
K_eff definite): X* = G_eff F_eff, Δ = V_W X*_W − δ0 − C_eff P with C_eff = V_W G_eff,WW V_Wᵀ on
the window of master DOFs under the contact, then X = X* − G_eff Vᵀ P. A step costs the window
compliance (cells × window²) and a matrix-vector product with G_eff (n²), not a factorisation.

This is the first part of the hybrid dynamics: one speed (:func:`simulate_hybrid`) and a speed
sweep (:func:`hybrid_speed_sweep`); the rotating-frame outputs (nodal diameters, Campbell
diagram) and the optimisation at speed come next.
"""

from __future__ import annotations

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Float, Int

from .._contact import solve_contact_cells
from .._modifications import Modifications
from .._quasi_static import quasi_static, separation
from .._util import rms_about_mean
from ..scenes import FlexibleMember, HybridPair

__all__ = [
    "HybridDynamics",
    "hybrid_speed_sweep",
    "mean_mesh_stiffness",
    "rim_waves",
    "simulate_hybrid",
]


class HybridDynamics(eqx.Module):
    """Steady-state response of the hybrid scene at one speed (the kept steps).

    Attributes:
        speed: pinion speed Ω (rad/s). theta: pinion angles of the kept steps (rad), (S,).
        mesh_force: Σ of the cell forces (N), (S,). transmission_error: dynamic TE (m), (S,).
        static_force: the static mesh force F_n = T/(r_b1 cos β_b) (N).
        x: coordinates at the last step (n,). result: 0, or 1 where a contact loop did not
            converge, 2 for a non-finite state. iterations: most contact passes in a step.
        rim_radial, rim_axial: the wheel's rim displacement at its stations (body frame, the
            axial master plane nearest mid-face), radial and axial (m), shape (S, Z); (S, 0)
            when the wheel is rigid. Read them with :func:`rim_waves`.
        time_step: Δt (s).
    """

    speed: Float[Array, ""]
    theta: Float[Array, " S"]
    mesh_force: Float[Array, " S"]
    transmission_error: Float[Array, " S"]
    static_force: Float[Array, ""]
    x: Float[Array, " n"]
    result: Int[Array, ""]
    iterations: Int[Array, ""]
    rim_radial: Float[Array, "S Z"]
    rim_axial: Float[Array, "S Z"]
    time_step: Float[Array, ""]

    @property
    def te_rms(self) -> Float[Array, ""]:
        """RMS of the dynamic TE about its mean over the kept steps (m; per speed for a sweep)."""
        return rms_about_mean(self.transmission_error)

    @property
    def dynamic_factor(self) -> Float[Array, ""]:
        """Max dynamic mesh force / static mesh force over the kept steps (per speed for a
        sweep: shape (n_speeds,))."""
        return jnp.max(self.mesh_force, axis=-1) / self.static_force


def _run(
    scene: HybridPair,
    mods,
    torque,
    speed,
    n_steps,
    keep,
    spp,
    alpha,
    beta,
    mode,
    width,
    max_iterations,
):
    mesh = scene.mesh
    dtype = scene.K.dtype
    period = mesh.mesh_period_angle / speed  # time of one mesh period (s)
    dt = period / spp
    b, g = 0.25, 0.5
    a0, a1 = 1.0 / (b * dt * dt), g / (b * dt)
    M, K = scene.M, scene.K
    at_speed = eqx.tree_at(lambda s: s.speed, scene, speed)
    # the quasi-static states at the step positions of the first period: the start (row 0, at
    # speed Ω: centrifugal load on, at rest) and the loaded cells of the averaged mesh stiffness
    qs, Km = _period_statics(at_speed, mods, torque, spp, mode, width, max_iterations)
    C = alpha * M + beta * (K + Km)
    F = torque * scene.f_torque + speed**2 * scene.f_centrifugal
    G = jnp.linalg.inv(K + a0 * M + a1 * C)
    G = 0.5 * (G + G.T)
    u = scene.te
    cb = jnp.cos(mesh.base_helix_angle)
    theta0 = qs.theta[0]  # half a step: contact-line ends off the edges
    # one time-constant reference δ0 = e_ref − e (as the lumped model's mesh table): the
    # quasi-static δ0 = max_M e(t) − e moves its reference with the position, which in dynamics
    # would be a spurious kinematic excitation of the drive rotation wherever max_M e varies
    # (a tip relief); the start state moves along the drive rotation N (V·N = 1) to match
    e_max = jax.vmap(lambda th: separation(mesh, mods, th)[1])(qs.theta)
    e_ref = jnp.max(e_max)
    X0 = qs.x[0] + scene.N[:, 0] * (e_ref - e_max[0])
    zero = jnp.zeros_like(X0)

    def body(carry, n):
        X, Xd, Xdd, code, it = carry
        th = theta0 + (n + 1) * mesh.mesh_period_angle / spp
        cells, e_th, delta0 = separation(mesh, mods, th)
        delta0 = jnp.where(cells.mask, delta0 + (e_ref - e_th), 0.0)
        idx, Vw = scene.window(cells)
        c = Vw.shape[0] * Vw.shape[1]
        Vw = Vw.reshape(c, -1)
        Feff = (
            F
            + M @ (a0 * X + Xd / (b * dt) + (0.5 / b - 1.0) * Xdd)
            + C @ (a1 * X + (g / b - 1.0) * Xd + dt * (0.5 * g / b - 1.0) * Xdd)
        )
        xs = G @ Feff
        Ceff = Vw @ G[idx[:, None], idx[None, :]] @ Vw.T
        sol, P, _ = solve_contact_cells(
            Ceff,
            Vw @ xs[idx] - delta0.reshape(-1),
            jnp.zeros((c, 0), dtype),
            jnp.zeros((0,), dtype),
            cells.stiffness.reshape(-1),
            cells.length.reshape(-1),
            cells.mask.reshape(-1),
            mode,
            width,
            max_iterations,
        )
        Xn = xs - G @ jnp.zeros_like(xs).at[idx].add(Vw.T @ P)
        Xddn = a0 * (Xn - X - dt * Xd - dt * dt * (0.5 - b) * Xdd)
        Xdn = Xd + dt * ((1.0 - g) * Xdd + g * Xddn)
        new = jnp.where(sol.result == 1, 1, 0)
        new = jnp.where(jnp.all(jnp.isfinite(Xn)), new, 2)
        carry = (Xn, Xdn, Xddn, jnp.maximum(code, new), jnp.maximum(it, sol.iterations))
        te = (u @ Xn - e_ref) / cb
        return carry, (th, jnp.sum(P), te, *rim_of(Xn))

    wheel = scene.members[1]
    if isinstance(wheel, FlexibleMember):
        j_mid = jnp.argmin(jnp.abs(wheel.z_nodes))
        rim = wheel.rim_dofs[:, j_mid, :]  # (Z, 3) global DOFs
        ang = wheel.station0 + wheel.pitch_angle * jnp.arange(rim.shape[0])
    else:
        rim = jnp.zeros((0, 3), jnp.int32)
        ang = jnp.zeros((0,), dtype)

    def rim_of(X):
        u = X[rim]
        return u[:, 0] * jnp.cos(ang) + u[:, 1] * jnp.sin(ang), u[:, 2]

    init = (X0, zero, zero, jnp.array(0), jnp.array(0))
    (X, _, _, code, it), (th, fm, te, ur, uz) = jax.lax.scan(body, init, jnp.arange(n_steps))
    return HybridDynamics(
        speed=jnp.asarray(speed, dtype),
        theta=th[-keep:],
        mesh_force=fm[-keep:],
        transmission_error=te[-keep:],
        static_force=mesh.normal_load(torque),
        x=X,
        result=jnp.where(qs.result[0] != 0, jnp.maximum(code, 1), code),
        iterations=it,
        rim_radial=ur[-keep:],
        rim_axial=uz[-keep:],
        time_step=jnp.asarray(dt, dtype),
    )


def mean_mesh_stiffness(scene: HybridPair, mods, torque, spp, mode, width):
    """K̄_m = ⟨Σ_c w_c k_c l_c V_c V_cᵀ⟩ over the ``spp`` quasi-static positions of one mesh
    period (n, n), w_c = 1 on the loaded cells (line load > 0), 0 elsewhere: the mesh part of K̄
    in Rayleigh damping (2.34)."""
    return _period_statics(scene, mods, torque, spp, mode, width)[1]


def _period_statics(scene: HybridPair, mods, torque, spp, mode, width, max_iterations=100):
    """Quasi-static result at the ``spp`` step positions of one mesh period, and K̄_m there."""
    mesh = scene.mesh
    theta = (jnp.arange(spp) + 0.5) * mesh.mesh_period_angle / spp
    qs = quasi_static(
        scene,
        mods,
        torque,
        theta,
        contact=mode,
        width=width,
        max_iterations=max_iterations,
        throw=False,
    )
    n = scene.K.shape[0]

    def add(Km, p):
        cells = mesh.cells(theta[p])
        idx, Vw = scene.window(cells)
        Vw = Vw.reshape(-1, Vw.shape[-1])
        kl = jnp.where(cells.mask, cells.stiffness * cells.length, 0.0).reshape(-1)
        w = (qs.line_load[p].reshape(-1) > 0).astype(Km.dtype)
        block = Vw.T @ ((kl * w)[:, None] * Vw)
        return Km.at[idx[:, None], idx[None, :]].add(block), None

    Km, _ = jax.lax.scan(add, jnp.zeros((n, n), scene.K.dtype), jnp.arange(spp))
    return qs, Km / spp


def simulate_hybrid(
    scene: HybridPair, modifications: Modifications | None, torque, speed, **settings
) -> HybridDynamics:
    """Integrate the hybrid scene at one pinion speed Ω (rad/s) > 0 from the quasi-static state
    (Newmark with the contact loop in the cell space, see the module docstring).

    ``settings`` and the errors are those of :func:`hybrid_speed_sweep`; the result has no
    speed axis."""
    dtype = scene.K.dtype
    res = hybrid_speed_sweep(
        scene, modifications, torque, jnp.reshape(jnp.asarray(speed, dtype), (1,)), **settings
    )
    return jax.tree.map(lambda x: x[0], res)


def hybrid_speed_sweep(
    scene: HybridPair,
    modifications: Modifications | None,
    torque,
    speeds,
    *,
    steps_per_period: int = 64,
    periods: int = 20,
    keep_periods: int = 4,
    rayleigh: tuple[float, float] = (25.0, 2.5e-6),
    contact: str = "exact",
    width=1e-7,
    max_iterations: int = 50,
) -> HybridDynamics:
    """Integrate the hybrid scene at each pinion speed from the quasi-static state, one speed
    after the other (``jax.lax.map``: one effective compliance of n² in memory at a time).

    Args:
        scene: a :class:`jaxgear.scenes.HybridPair` (its ``speed`` is ignored: each Ω sets the
            centrifugal load). modifications: flank modifications (``None``: none).
        torque: pinion torque (N·m) > 0. speeds: pinion speeds Ω (rad/s) > 0, shape (S,).
        steps_per_period: time steps per mesh period (the seed uses 64, IV-27).
        periods, keep_periods: mesh periods integrated, and kept at the end.
        rayleigh: (α (1/s), β (s)) of C = α M + β K̄; default the seed's D1 = (25, 2.5e-6).
        contact, width, max_iterations: as :func:`jaxgear.quasi_static`.

    Returns:
        :class:`HybridDynamics` whose leaves have a leading speed axis (read ``result``: 0
        converged).

    Raises:
        ValueError: speeds or step counts out of range (before any computation).
    """
    dtype = scene.K.dtype
    speeds = jnp.asarray(speeds, dtype)
    if speeds.ndim != 1 or speeds.size == 0 or not bool(jnp.all(speeds > 0)):
        raise ValueError("speeds must be a non-empty 1-D array of pinion speeds > 0 (rad/s)")
    if int(steps_per_period) != steps_per_period or steps_per_period < 4:
        raise ValueError(
            f"steps_per_period = {steps_per_period!r} is out of range: allowed an integer >= 4"
        )
    if int(periods) != periods or periods < 2 or not 1 <= keep_periods <= periods:
        raise ValueError(
            f"periods = {periods!r}, keep_periods = {keep_periods!r}: allowed integers with "
            "1 <= keep_periods <= periods, periods >= 2"
        )
    mods = Modifications() if modifications is None else modifications
    return _sweep(
        scene,
        mods,
        jnp.asarray(torque, dtype),
        speeds,
        jnp.asarray(rayleigh[0], dtype),
        jnp.asarray(rayleigh[1], dtype),
        jnp.asarray(width, dtype),
        int(steps_per_period),
        int(periods),
        int(keep_periods),
        contact,
        int(max_iterations),
    )


@eqx.filter_jit
def _sweep(scene, mods, torque, speeds, alpha, beta, width, spp, periods, keep, mode, max_it):
    return jax.lax.map(
        lambda w: _run(
            scene, mods, torque, w, spp * periods, spp * keep, spp, alpha, beta, mode, width, max_it
        ),
        speeds,
    )


def rim_waves(u, time_step, spin: float = -1.0) -> dict:
    """Nodal-diameter content of a rim field (the seed's (3.2) Fourier series in the angle, then
    in time): which diameters vibrate, at what frequency, travelling which way.

    Args:
        u: rim displacement at Z equally spaced stations (body frame, station k at angle
            2πk/Z), over equally spaced steps, shape (S, Z) (:class:`HybridDynamics` ``rim_radial``
            or ``rim_axial``, NumPy).
        time_step: Δt (s). spin: the body's rotation sense about z (−1 for the wheel, +1 for the
            pinion): a wave travelling the same way is *forward*.

    Returns:
        dict of NumPy arrays over the nodal diameters n = 0 … Z/2: ``nodal_diameter``,
        ``amplitude`` (m, the largest travelling-wave amplitude of that diameter),
        ``frequency_hz`` (of that wave, in the body frame) and ``direction`` (+1 forward,
        −1 backward, 0 for n = 0 or a standing pattern). The mean over time is removed.
    """
    u = np.asarray(u, dtype=float)
    S, Z = u.shape
    if S < 4 or Z < 3:
        raise ValueError(f"rim field of shape {u.shape}: need >= 4 steps and >= 3 stations")
    u = u - u.mean(axis=0, keepdims=True)
    # spatial harmonics U_n(t) = (2/Z) Σ_k u_k e^{−i n φ_k}: a wave A cos(nφ − ωt) (towards +φ)
    # gives U_n = A e^{−iωt}, one towards −φ gives A e^{+iωt}
    U = np.fft.fft(u, axis=1)[:, : Z // 2 + 1] * (2.0 / Z)
    spec = np.fft.fft(U, axis=0) / S  # (S, n): frequency bins ν_j, e^{+i 2π ν t} convention
    freq = np.fft.fftfreq(S, time_step)
    j = np.argmax(np.abs(spec), axis=0)
    amp = np.abs(spec[j, np.arange(spec.shape[1])])
    f = freq[j]
    # e^{−iωt} (towards +φ) appears at negative ν: direction +φ when ν < 0
    towards_plus = np.where(f < 0, 1.0, np.where(f > 0, -1.0, 0.0))
    direction = towards_plus * np.sign(spin)
    direction[0] = 0.0
    return {
        "nodal_diameter": np.arange(spec.shape[1]),
        "amplitude": amp,
        "frequency_hz": np.abs(f),
        "direction": direction,
    }
