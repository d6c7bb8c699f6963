"""Gear whine of the hybrid model (condensed FE bodies) in the frequency domain (docs/whine.md,
"Hybrid model"): the harmonic balance of :mod:`._whine` on the coordinates the hybrid Newmark
integrates.

A condensed body turns under the fixed mesh: in its frame the contact passes from one rim
station to the next, so the mesh stiffness on the body's coordinates does not repeat after a
mesh period T but moves by one station, K_m(t + T) = P K_m(t) Pᵀ, with P the cyclic shift of
the structure by one tooth (each body's rim stations one place on with their vectors turned by
the pitch, its shaft's nodes turned by the pitch, its Craig–Bampton modal coordinates turned
within each pair of a nodal diameter; the identity on a rigid member). The structure is
cyclically symmetric (P M Pᵀ = M, P K Pᵀ = K, P C Pᵀ = C, P F = F), so the steady state
obeys X(t + T) = P X(t) (a travelling pattern in the body frame; a fixed-frame quantity, the
TE, the mesh force, a bearing force, repeats every T). With P = exp(2πi Φ), Φ Hermitian with
eigenvalues ν in (−½, ½] (the nodal-diameter classes: ν = n/Z), the twisted coordinates

    z(t) = exp(−2πi Φ t/T) X(t)

repeat every T. Held on the quasi-static contact state, the vibration y = X − x_qs in them,
z = Σ_h Z_h e^{i h ω t} (ω = 2π/T), balances as

    (K + i ω C (h + Φ) − ω² M (h + Φ)²) Z_h + Σ_j K̃_{h−j} Z_j = −(i ω C (h + Φ) − ω² M (h + Φ)²) Ẑ_qs,h,

K̃(t) = exp(−2πiΦt/T) K_m(t) exp(2πiΦt/T) = Ṽ(t)ᴴ W(t) Ṽ(t), Ṽ(t) = V(t) exp(2πiΦt/T), V(t) the
cells' structure vectors at the position in the first period, W = k l w the held cells'
stiffness. The coupling is taken on the samples of the period, as the lumped balance's
Fourier coefficients of K_m: K̃_{h−j} = (1/P) Σ_p e^{−i(h−j)ωt_p} K̃(t_p), and solved on the
cells of the samples (a Woodbury identity: one n × n factorisation per harmonic and one system
of P c unknowns, c cells per position), exactly for that sampled coupling. The harmonics of
the P samples beyond H (H < |j| <= P/2) are not dropped: they are taken from the mean-stiffness
model and their coupling Σ_{|j|>H} K̃_{h−j} Y_j moved to the right-hand side (the quasi-static
motion jumps where contact lines enter and leave; dropping the vibration that cancels those
jumps left an error falling only as 1/H, :func:`_completion`).

Limits: the mesh share of the damping (Rayleigh's β K̄_m(k), the composite model's), which
the Newmark changes period by period, is taken as its mean in the twisted frame; a
Craig–Bampton mode whose partner of the same nodal diameter the condensation's mode count cut
off breaks the symmetry: its coordinate is held at zero (it couples to the rim only through
the mass, at the frequency of an interface-fixed mode); turning frames' inertia
(``rotating_frame``), trains and a condensed body's shaft in a housing's seats are refused
(a housing round the other shafts is taken: the shift is the identity on its coordinates).

Sources: the twisted (Bloch–Floquet) periodicity of a cyclic structure under a travelling
load (D. L. Thomas, Int. J. Numer. Meth. Eng. 14 (1979) 81; the rotating load of a cyclic
rim: the nodal-diameter orders of seed (3.9)); the harmonic balance as :mod:`._whine`.
"""

from __future__ import annotations

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import scipy.linalg
import scipy.sparse as sp
import scipy.sparse.csgraph as csg

from .._contact import ContactLaw, ExactContact, contact_law
from .._quasi_static import per_mesh_modifications
from .._util import check_integer, each_solve
from ._hybrid_damping import _speed_damping
from ._hybrid_mesh import SceneCells, _joined, _reference_shift, _references
from ._model import mesh_forces, mesh_te, static_mesh_forces
from ._whine import AbstractWhineMethod, WhineResponse, _one_sided, fourier_coefficients
from ._whine_methods import check_whine_speeds

__all__ = ["CyclicShift", "cyclic_shift", "hybrid_whine"]


class CyclicShift(eqx.Module):
    """The shift of a hybrid pair's structure by one tooth (:func:`cyclic_shift`) and the
    twist it gives the frequency domain.

    Attributes:
        P: the shift on the kept coordinates (k, k), orthogonal: X(t + T) = P X(t).
        keep: the kept coordinates (k,) int (all but the modal coordinates of a mode whose
            nodal-diameter partner the condensation cut off).
        U: eigenvectors of P (k, k), unitary. nu: their classes ν (k,), P = U e^{2πiν} Uᴴ,
            ν in (−½, ½] (a body of Z teeth: ν = n/Z, n its nodal diameter).
        residual: max |P A Pᵀ − A| / max |A| over the kept K and M.
    """

    P: np.ndarray
    keep: np.ndarray
    U: np.ndarray
    nu: np.ndarray
    residual: float = eqx.field(static=True)

    def twist(self, s) -> jnp.ndarray:
        """exp(2πi Φ s) (k, k) at the period fraction ``s`` (scalar)."""
        e = jnp.exp(2j * jnp.pi * jnp.asarray(self.nu) * s)
        U = jnp.asarray(self.U)
        return (U * e[None, :]) @ U.conj().T


def _turn(angle):
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def cyclic_shift(scene, tol: float = 1e-8) -> CyclicShift:
    """The structure of a hybrid pair shifted by one tooth, X(θ + T) = P X(θ) (T the mesh
    period; concrete, NumPy): each condensed body's rim station k → k + 1 with its vectors
    turned by the pitch 2π/Z (the shift under which the cells' structure vectors obey
    V(θ + T) = V(θ) Pᵀ), the nodes of its shaft (6 DOFs: x, y, z and their rotations, the
    shaft along z in the body frame) turned by the pitch, and its Craig–Bampton modal
    coordinates q by the map Q that keeps the mass coupling, Q M_qb = M_qb P_b (least squares;
    a rotation within each pair of modes of one nodal diameter). A modal coordinate that no
    such map carries (its partner mode cut off by the condensation's mode count) is left out
    of ``keep``.

    Raises:
        ValueError: a member or shaft that this does not hold for (a housing, a train), or a
            structure not cyclically symmetric to ``tol`` (relative) under the shift.
    """
    K = np.asarray(scene.structure.K, dtype=float)
    M = np.asarray(scene.structure.M, dtype=float)
    n = K.shape[0]
    P = np.eye(n)
    drop: list[int] = []
    _, label = csg.connected_components(sp.csr_matrix((K != 0) | (M != 0)), directed=False)
    for member in scene.members:
        if not member.turns_frame:
            continue
        rim = np.asarray(member.rim_dofs)  # (Z, axial, 3)
        Z = rim.shape[0]
        R = _turn(float(member.pitch_angle))
        comp = np.nonzero(label == label[rim[0, 0, 0]])[0]
        shaft = comp[comp < rim.min()]
        body = np.asarray(member.body_dofs)
        modal = np.setdiff1d(np.intersect1d(comp, body), np.r_[rim.ravel(), shaft])
        if len(shaft) % 6 or np.setdiff1d(comp, np.r_[rim.ravel(), shaft, modal]).size:
            raise ValueError(
                "scene: a condensed body whose shaft is not a chain of 6-DOF nodes of its own "
                "(a housing, a shared shaft): allowed a hybrid pair on its own shafts"
            )
        for d in np.r_[rim.ravel(), shaft, modal]:
            P[d, d] = 0.0
        for k in range(Z):
            for j in range(rim.shape[1]):
                P[np.ix_(rim[(k + 1) % Z, j], rim[k, j])] = R
        for g in range(0, len(shaft), 6):
            node = shaft[g : g + 6]
            P[np.ix_(node[:3], node[:3])] = R
            P[np.ix_(node[3:], node[3:])] = R
        if modal.size:
            known = np.r_[rim.ravel(), shaft]
            Mqb = M[np.ix_(modal, known)]
            target = Mqb @ P[np.ix_(known, known)]  # (P M Pᵀ)_qb = M_qb: Q M_qb = M_qb P_b
            Q, *_ = np.linalg.lstsq(Mqb.T, target.T, rcond=None)
            Q = Q.T
            miss = np.linalg.norm(Q @ Mqb - target, axis=1) / np.maximum(
                np.linalg.norm(target, axis=1), 1e-300
            )
            bad = miss > 1e-6
            good = ~bad
            P[np.ix_(modal[good], modal[good])] = Q[np.ix_(good, good)]
            drop.extend(modal[bad].tolist())
    keep = np.setdiff1d(np.arange(n), np.asarray(drop, dtype=int))
    Pk = P[np.ix_(keep, keep)]
    res = 0.0
    for A in (K, M):
        Ak = A[np.ix_(keep, keep)]
        res = max(res, float(np.abs(Pk @ Ak @ Pk.T - Ak).max() / np.abs(Ak).max()))
    orth = float(np.abs(Pk @ Pk.T - np.eye(len(keep))).max())
    if res > tol or orth > tol:
        raise ValueError(
            f"scene: the structure is not cyclically symmetric under a one-tooth shift "
            f"(relative residual {max(res, orth):.2e}, allowed <= {tol:g}): the frequency "
            "domain of a hybrid model needs bodies with one rim station per tooth on a "
            "cyclic mesh"
        )
    T, U = scipy.linalg.schur(Pk.astype(complex), output="complex")
    lam = np.diag(T)
    nu = np.angle(lam) / (2 * np.pi)
    nu = np.where(nu <= -0.5 + 1e-9, nu + 1.0, nu)  # (−½, ½]
    return CyclicShift(Pk, keep, U, nu, res)


def _check(model, speeds, method, positions):
    if not isinstance(method, AbstractWhineMethod):
        raise TypeError(
            f"method = {method!r}: allowed HarmonicBalance(...) or TransmissionErrorSource(...)"
        )
    if model.rotating_frame:
        raise ValueError(
            "model: rotating_frame = True: the frequency domain of a hybrid model has no "
            "turning-frame terms yet (allowed rotating_frame = False)"
        )
    if len(model.scene.base_planes) != 1 or model.scene.scene_periods() != 1:
        raise ValueError(
            f"model: {len(model.scene.base_planes)} meshes: the frequency domain of a hybrid "
            "model takes a pair (allowed one mesh)"
        )
    check_integer("positions", positions, 4)
    H = int(method.harmonics)
    if positions < 4 * H + 1:
        raise ValueError(
            f"positions = {positions}: allowed >= 4 harmonics + 1 = {4 * H + 1} for harmonics = {H}"
        )
    check_whine_speeds(speeds)


def hybrid_whine(
    model,
    speeds,
    method: AbstractWhineMethod,
    *,
    positions: int = 64,
    contact: ContactLaw = ExactContact(),
) -> WhineResponse:
    """Gear whine of a hybrid model (:class:`~jaxgear.dynamics.HybridModel`, a pair) in the
    frequency domain: the periodic response linearised about the quasi-static solution at
    ``positions`` positions of the first mesh period (the static solve the hybrid Newmark
    starts from, at each speed with its centrifugal load, on the time-constant flank-gap
    reference), in the twisted coordinates of the cyclic bodies (module docstring). Reached
    through :func:`~jaxgear.dynamics.whine_response` (:meth:`HybridModel.whine`).

    Returns a :class:`~jaxgear.dynamics.WhineResponse`: the TE, mesh force and bearing forces
    (fixed frame, as :meth:`~jaxgear.scenes.HybridScene.bearing_forces_fixed_frame`) per order
    of the mesh frequency, on the clock of the Newmark records; ``coordinates`` and
    ``quasi_static`` are the harmonics of the body-frame coordinates read over the first mesh
    period (a condensed body's coordinates do not repeat after one period).

    Raises:
        TypeError: another method. ValueError: turning-frame terms, several meshes, a speed
            <= 0, too few positions, a structure that is not cyclic (:func:`cyclic_shift`).
    """
    _check(model, speeds, method, positions)
    shift = cyclic_shift(model.scene)
    dtype = model.scene.structure.K.dtype
    law = contact_law(contact, dtype)
    speeds = jnp.atleast_1d(jnp.asarray(speeds, dtype))
    null = _null_space(model.scene, shift)
    window = _window(model.scene, int(positions), shift.keep)
    parts = [_at_speed(model, w, law, int(positions), method, shift, null, window) for w in speeds]
    out = jax.tree.map(lambda *a: jnp.stack(a), *parts)
    H = int(method.harmonics)
    return WhineResponse(
        speed=speeds,
        frequency=out["frequency"],
        orders=jnp.arange(H + 1, dtype=dtype),
        coordinates=out["coordinates"],
        quasi_static=out["quasi_static"][0],
        transmission_error=out["te"],
        mesh_force=out["mesh_force"],
        bearing_force=out["bearing"],
        static_force=out["static_force"][0],
        min_mesh_force=out["fmin"],
        contact_loss=out["fmin"] <= 0.0,
        nonlinearity=out["misplaced"] / out["static_force"],
    )


def _null_space(scene, shift: CyclicShift) -> np.ndarray:
    """The structure's rigid motions without the mesh, K n = 0 on the kept coordinates,
    M-orthonormal (k, r0): pinned at h = 0 by a penalty that the balance takes back."""
    keep = shift.keep
    K = np.asarray(scene.structure.K)[np.ix_(keep, keep)]
    M = np.asarray(scene.structure.M)[np.ix_(keep, keep)]
    w, v = scipy.linalg.eigh(K, M)
    return v[:, np.abs(w) < 1e-9 * np.abs(w).max()]


def _window(scene, positions: int, keep) -> np.ndarray:
    """The kept coordinates (indices into ``keep``) that any cell of the first mesh period's
    ``positions`` reaches (the union of the windows; concrete)."""
    T = float(scene.base_planes[0].mesh_period_angle)
    theta = jnp.asarray((np.arange(positions) + 0.5) * T / positions)

    def idx(th):
        cells = scene.mesh_cells(th)
        return scene.window_row(cells, tuple(jnp.zeros_like(c.s) for c in cells)).idx

    every = np.unique(np.asarray(jax.jit(jax.vmap(idx))(theta)))
    at = np.full(scene.structure.K.shape[0], -1)
    at[np.asarray(keep)] = np.arange(len(keep))
    return at[every]


@eqx.filter_jit
def _at_speed(model, speed, law, positions: int, method, shift: CyclicShift, null, window):
    scene, mods = model.scene, model.mods
    planes = scene.base_planes
    H = method.harmonics
    dtype = scene.structure.K.dtype
    n = scene.structure.K.shape[0]
    keep = jnp.asarray(shift.keep)
    Pn = positions
    T_angle = planes[0].mesh_period_angle
    qs, block, damp = _speed_damping(model, speed, law, Pn)
    e_ref, e_max = _references(scene, mods, qs.theta)
    x_qs = qs.x + jax.vmap(lambda d: _reference_shift(scene, d))(e_ref[None] - e_max)  # (P, n)
    cells = SceneCells(scene, per_mesh_modifications(mods, len(planes)), e_ref, law)
    rows = jax.vmap(cells.at)(qs.theta)

    def full(idx, Vw):
        return jnp.zeros((Vw.shape[0], n), Vw.dtype).at[:, idx].add(Vw)

    V = jax.vmap(full)(rows.idx, rows.V)  # (P, c, n)
    w = _joined(qs, "line_load") > 0  # the static contact state (exact law)
    kl_all = jnp.where(rows.mask, rows.k * rows.length, 0.0)
    kl = jnp.where(w, kl_all, 0.0)  # (P, c)
    gap = jnp.where(rows.mask, jnp.einsum("pcn,pn->pc", V, x_qs) - rows.delta0, 0.0)
    f_static = jnp.where(rows.mask, _joined(qs, "line_load") * rows.length, 0.0)

    # the twisted frame on the kept coordinates
    U = jnp.asarray(shift.U)
    nu = jnp.asarray(shift.nu)
    Phi = (U * nu[None, :]) @ U.conj().T
    s = (jnp.arange(Pn, dtype=dtype) + 0.5) / Pn
    tw = jnp.exp(2j * jnp.pi * s[:, None] * nu[None, :])  # (P, k)
    Vk = V[:, :, keep]
    outside = jnp.sum(jnp.abs(Vk)) - jnp.sum(jnp.abs(Vk[:, :, window]))
    Vk = eqx.error_if(Vk, outside > 1e-9 * jnp.sum(jnp.abs(Vk)), "cells outside the window")
    xk = x_qs[:, keep]
    zqs = jnp.einsum("kl,pl,ml,pm->pk", U, tw.conj(), U.conj(), xk)  # e^{−2πiΦs} x_qs
    Xh = fourier_coefficients(zqs, H)  # (2H+1, k)

    Mk = scene.structure.M[keep][:, keep]
    Kk = scene.structure.K[keep][:, keep]
    Ck = damp.C[keep][:, keep].astype(U.dtype)
    if damp.c_m is not None:  # the mesh share of period 0, its mean in the twisted frame
        Uw, B, _ = block(0)
        W = jnp.eye(n, dtype=dtype)[Uw] if damp.R is None else damp.R[Uw]
        Cm = (damp.c_m * (W.T @ B @ W))[keep][:, keep]
        avg = jnp.mean(tw.conj()[:, :, None] * tw[:, None, :], axis=0)
        Ck = Ck + U @ ((U.conj().T @ Cm @ U) * avg) @ U.conj().T

    kref = jnp.mean(jnp.sum(kl, axis=1)) * jnp.max(jnp.abs(Vk)) ** 2
    Mr = scene.structure.M @ scene.rigid_modes()
    Mr = Mr[keep]
    gauge = kref * (Mr @ Mr.T) / jnp.maximum(jnp.sum(Mr * Mr), 1e-300)
    MN = Mk @ jnp.asarray(null)
    h = jnp.arange(-H, H + 1)
    omega = speed * 2 * jnp.pi / T_angle  # mesh frequency (rad/s): T = T_angle / Ω
    eye = jnp.eye(Kk.shape[0], dtype=dtype)

    def inertia(hh):  # C S + M S², S = iω(h + Φ): the twisted frame's d/dt
        S = 1j * omega * (hh * eye + Phi)
        return Ck @ S + Mk @ S @ S

    dyn = jax.vmap(inertia)(h)  # (2H+1, k, k)
    D = (Kk[None] + dyn).at[H].add(gauge + kref * MN @ MN.T)
    F = -jnp.einsum("hkl,hl->hk", dyn, Xh)  # −(C S + M S²) Ẑ_qs
    y_high = jnp.zeros_like(xk)
    if method.parametric:  # the harmonics beyond H (mean stiffness) and their coupling back
        y_high, F = _completion(F, Kk, Ck, Mk, Phi, omega, zqs, Vk, kl, s, U, tw, H)
    Y = _balance(D, F, Vk, kl / Pn, s, U, nu, window, MN, kref, method.parametric, H)

    # the vibration at the samples, on every coordinate (the dropped ones held at 0)
    ph = jnp.exp(2j * jnp.pi * h[:, None] * s[None, :])  # (2H+1, P)
    zy = jnp.einsum("hp,hk->pk", ph, Y)
    y = jnp.real(jnp.einsum("kl,pl,ml,pm->pk", U, tw, U.conj(), zy)) + y_high
    y = jnp.zeros((Pn, n), dtype).at[:, keep].set(y)
    X = x_qs + y
    sizes = tuple((p.n_lines, p.n_slices) for p in planes)
    vy = jnp.einsum("pcn,pn->pc", V, y)
    f, _ = mesh_forces(f_static + kl * vy, sizes)  # (P, m)
    g = gap + vy
    misplaced, _ = mesh_forces(kl_all * jnp.maximum(g, 0.0) - kl * g, sizes)
    te = jax.vmap(mesh_te(scene, e_ref))(X)
    bearing = scene.bearing_forces_fixed_frame(qs.theta, X @ scene.reaction_matrix().T)
    fs_qs, _ = mesh_forces(f_static, sizes)
    fs = static_mesh_forces(scene, model.torque, fs_qs)

    def orders(q):
        return _one_sided(fourier_coefficients(q, H), H)

    return {
        "frequency": omega / (2 * jnp.pi),
        "coordinates": orders(X),
        "quasi_static": orders(x_qs),
        "te": orders(te),
        "mesh_force": orders(f),
        "bearing": orders(bearing),
        "static_force": fs,
        "fmin": jnp.min(f, axis=0),
        "misplaced": jnp.max(jnp.abs(misplaced), axis=0),
    }


def _completion(F, Kk, Ck, Mk, Phi, omega, zqs, Vk, kl, s, U, tw, H: int):
    """The harmonics H < |j| <= P/2 of the vibration from the mean-stiffness model,
    Y_j = −(K + K̃_0 + C S_j + M S_j²)⁻¹ (C S_j + M S_j²) Ẑ_qs,j, S_j = iω(j + Φ), and their
    coupling back into the kept harmonics through the sampled stiffness. Returns y_high (P, k)
    (real, body frame, at the samples) and F_h − Σ_{|j|>H} K̃_{h−j} Y_j (2H+1, k), the forcing
    of the kept ones.

    Why: the quasi-static motion jumps where a contact line enters or leaves (Ẑ_qs,j ~ 1/j),
    while the true motion is smooth (its acceleration jumps, X_j ~ 1/j³). Above the structure's
    modes Y_j ≈ −Ẑ_qs,j: the vibration cancels the jumps. Holding Y_j = 0 beyond H leaves them in
    X = x_qs + y, and the stiffness's own jumps carry them back into the low orders, an error
    that falls only as 1/H (order 2 of the test pair: −1.5 % at H = 32 on 256 positions, −2.7 %
    on 384). With the completion the error is that of the high harmonics' own parametric terms,
    which are smaller by the same 1/j (docs/whine.md, "Hybrid model"). At low speed Y_j → 0 and
    the balance is the one without it."""
    Pn = zqs.shape[0]
    j = jnp.asarray([q for q in range(-(Pn // 2) + 1, Pn // 2 + 1) if abs(q) > H])
    E = jnp.exp(-2j * jnp.pi * j[:, None] * s[None, :])  # (J, P)
    Zj = E @ zqs / Pn  # (J, k)
    Vt = jnp.einsum("pck,kl,pl,ml->pcm", Vk, U, tw, U.conj())  # Ṽ_p
    K0 = jnp.einsum("pck,pc,pcl->kl", Vt.conj(), kl / Pn, Vt)  # K̃_0
    # C S_j + M S_j² = iω(j C + CΦ) − ω²(j² M + 2j MΦ + MΦ²): no product per harmonic
    CPhi, MPhi = Ck @ Phi, Mk @ Phi
    MPhi2 = MPhi @ Phi
    Kc = Kk + K0

    def one(jz):  # (), (k,) -> Y_j (k,)
        jj, z = jz
        jf = jj.astype(Kc.dtype)
        A = 1j * omega * (jf * Ck + CPhi) - omega**2 * (jf**2 * Mk + 2 * jf * MPhi + MPhi2)
        return -jnp.linalg.solve(Kc + A, A @ z)

    Yj = jax.lax.map(one, (j, Zj))  # (J, k): one unbatched solve per harmonic (each_solve)
    zy = E.conj().T @ Yj  # (P, k), twisted
    yb = jnp.real(jnp.einsum("kl,pl,ml,pm->pk", U, tw, U.conj(), zy))  # body frame
    f = jnp.einsum("pck,pc,pcl,pl->pk", Vk, kl, Vk, yb)  # K_m(s_p) y_high(s_p)
    ft = jnp.einsum("kl,pl,ml,pm->pk", U, tw.conj(), U.conj(), f)  # twisted
    h = jnp.arange(-H, H + 1)
    Eh = jnp.exp(-2j * jnp.pi * h[:, None] * s[None, :])
    return yb, F - Eh @ ft / Pn


def _balance(D, F, Vk, G, s, U, nu, window, MN, kappa, parametric: bool, H: int):
    """Z_h of D_h Z_h + Σ_j K̃_{h−j} Z_j − [h = 0] κ MN MNᵀ Z_0 = F_h, K̃_{h−j} = Σ_p
    e^{−2πi(h−j)s_p} Ṽ_pᴴ G_p Ṽ_p (G already over P), Ṽ_p = V_p e^{2πiΦs_p}: the coupling
    through the cells of the samples (their approach q, and the penalty's coordinates), by
    Woodbury. D_h commutes with the twist, so the cells' dynamic compliance between samples p
    and p' is V_p [Σ_h e^{2πih(s_p − s_p')} D_h⁻¹ e^{2πiΦ(s_p − s_p')}] V_p'ᵀ: a w × w matrix
    per sample offset on the ``window`` (w coordinates every cell of the period reaches)."""
    Pn, c, k = Vk.shape
    h = jnp.arange(-H, H + 1)
    cdt = D.dtype
    g = G.reshape(-1)
    U = U.astype(cdt)
    tw = jnp.exp(2j * jnp.pi * s[:, None] * nu[None, :])  # (P, k)

    def untwist(x, sign):  # e^{±2πiΦs_p} x_p for x (P, k)
        e = tw if sign > 0 else tw.conj()
        return jnp.einsum("kl,pl,ml,pm->pk", U, e, U.conj(), x)

    if not parametric:  # the mean stiffness alone: K̃_0 on each harmonic
        Vt = jnp.einsum("pck,kl,pl,ml->pcm", Vk, U, tw, U.conj())
        K0 = jnp.einsum("pck,pc,pcl->kl", Vt.conj(), G, Vt)
        K0 = K0[None] - kappa * (MN @ MN.T)[None] * (h == 0)[:, None, None]
        return each_solve(D + K0, F)
    r0 = MN.shape[1]
    w = window.shape[0]
    Vw = Vk[:, :, window]  # (P, c, w)
    Bw = jnp.eye(k, dtype=cdt)[:, window]  # (k, w)
    DF = each_solve(D, F)  # (h, k)
    XU = (
        jnp.swapaxes(
            each_solve(jnp.swapaxes(D, 1, 2), jnp.broadcast_to(Bw, (h.size, k, w))),
            1,
            2,
        )
        @ U
    )  # Bᵀ D_h⁻¹ U (h, w, k)
    Y = U.conj().T @ Bw  # (k, w)
    delta = jnp.arange(-(Pn - 1), Pn) / Pn  # the sample offsets s_p − s_p'

    def compliance(d):  # Σ_h e^{2πihΔ} Bᵀ D_h⁻¹ e^{2πiΦΔ} B (w, w)
        X = jnp.einsum("h,hwk->wk", jnp.exp(2j * jnp.pi * h * d), XU)
        return (X * jnp.exp(2j * jnp.pi * nu * d)[None, :]) @ Y

    S = jax.lax.map(compliance, delta)[::-1]  # index P − 1 − p + p'

    def row(p):
        Sp = jax.lax.dynamic_slice(S, (Pn - 1 - p, 0, 0), (Pn, w, w))
        return jnp.einsum("ca,qab,qdb->cqd", Vw[p].astype(cdt), Sp, Vw.astype(cdt))

    Acc = jax.lax.map(row, jnp.arange(Pn)).reshape(Pn * c, Pn * c)
    D0N = jnp.linalg.solve(D[H], MN.astype(cdt))  # (k, r0); the ν = 0 class: untwisted
    Acn = jnp.einsum("pck,kr->pcr", Vk, D0N).reshape(Pn * c, r0)
    D0tN = jnp.linalg.solve(D[H].T, MN.astype(cdt))  # D_0⁻ᵀ MN
    Anc = jnp.einsum("kr,pck->rpc", D0tN, Vk).reshape(r0, Pn * c)
    Ann = MN.T @ D0N
    A = jnp.block([[Acc, Acn], [Anc, Ann]])
    weights = jnp.concatenate([g.astype(cdt), -kappa * jnp.ones(r0, cdt)])
    ph = jnp.exp(2j * jnp.pi * h[:, None] * s[None, :])  # (2H+1, P)
    zF = untwist(jnp.einsum("hp,hk->pk", ph, DF), +1)  # e^{2πiΦs_p} Σ_h e^{2πihs_p} D_h⁻¹F_h
    rhs = jnp.concatenate([jnp.einsum("pck,pk->pc", Vk, zF).reshape(-1), MN.T @ DF[H]])
    q = jnp.linalg.solve(jnp.eye(A.shape[0], dtype=cdt) + A * weights[None, :], rhs)
    wq = weights * q
    f = untwist(jnp.einsum("pck,pc->pk", Vk, wq[: Pn * c].reshape(Pn, c)), -1)  # Ṽ_pᴴ (g q)_p
    fh = jnp.einsum("hp,pk->hk", ph.conj(), f)
    Z = DF - each_solve(D, fh)
    return Z.at[H].add(-D0N @ wq[Pn * c :])
