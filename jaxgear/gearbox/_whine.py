"""Gear whine of the coupled gearbox in the frequency domain (docs/whine.md, "A gearbox"): the
steady state of :func:`~jaxgear.gearbox.gearbox_dynamics`' coupled system linearised about its
quasi-static solution, each stage's meshes at their own mesh frequency.

The stages of a gearbox run at different mesh frequencies ω_k = 2π v_k / p_b,k (v_k the stage's
mesh travel speed, p_b,k its mesh period as travel), in general incommensurate: the coupled
response is quasi-periodic. Each stage with contact cells is one group of the torus of mesh
phases s_k = v_k t / p_b,k (mod 1). The static contact problem of the coupled structure (the
stages' blocks, the shafts, the output hold, the rotating frames' constant terms: the K and F
the time integration starts from) is solved at every point of the torus grid, each stage's
cells at its own phase (R_k = ``positions`` points per stage period, Π_k R_k solves), giving
x_qs(s_1..s_G) and the tangent mesh stiffness K_m(s_1..s_G) = Σ_c w_c k_c l_c V_c V_cᵀ. Their
G-dimensional Fourier coefficients enter the quasi-periodic balance of
:func:`jaxgear.dynamics.quasi_periodic_balance` over the multi-index harmonics of
:class:`~jaxgear.dynamics.QuasiPeriodicBalance`:

    (K − ν_h² M + i ν_h C) Y_h + Σ_j K̂_{h−j} Y_j = (ν_h² M − i ν_h C) X̂_h,   ν_h = Σ_k h_k ω_k,

M, K, C the coupled model's (C its modal damping on the modes of (M, K + K̄_m) plus the
stages' constant speed terms). A stage's cells must repeat every one of its mesh periods (in
its own frame: a planetary stage's carrier frame, where its speed terms are constant).

Sources: the linearisation and the quasi-periodic balance of docs/whine.md (Kim & Noah,
J. Appl. Mech. 58, 1991; Liu & Parker, J. Sound Vib. 310, 2008 for a multi-mesh system); the
coupled model's equations of motion, docs/gearbox.md.
"""

from __future__ import annotations

import dataclasses

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from .._baseplane import CellRow
from .._contact import AbstractContactLaw, ExactContact, solve_contact
from .._util import as_float, check_integer, checked_on_host, int_rows, is_traced
from ..dynamics import (
    QuasiPeriodicBalance,
    WhineResponse,
    group_positions,
    harmonic_set,
    matrix_modal_analysis,
    mesh_basis,
    quasi_periodic_balance,
    torus_coefficients,
)
from ._chain import GearboxTorsional
from ._coupled import (
    GearboxRun,
    _assemble,
    _cell_counts,
    _check,
    _flank_signs,
    _kinematics,
    _layout,
    _split_forces,
)

__all__ = ["gearbox_whine"]


def _embedded(stages, housing, sign_of, rows_of):
    """Each stage's cell rows at its grid positions embedded in the coupled coordinates (a
    shared ``housing``'s once, :func:`_layout`): per stage (V (R, c, n) signed, k, length,
    delta0, mask (R, c))."""
    idx, n = _layout(stages, housing)
    out = []
    for s, i, sign, x in zip(stages, idx, sign_of, rows_of, strict=True):
        r = jax.vmap(s.cell_row)(x)
        V = jnp.zeros(r.V.shape[:2] + (n,), r.V.dtype).at[:, :, i].set(r.V)
        out.append((sign * V, r.k, r.length, r.delta0, r.mask))
    return out


@eqx.filter_jit
def _cell_rows(stage, xs):
    """The stage's cell rows at the travels ``xs`` (m), (n,): one compiled program per kind of
    stage (the rows evaluated op by op took seconds of small compilations)."""
    return jax.vmap(stage.cell_row)(xs)


def _repeats(stage, dtype) -> bool:
    """Whether the stage's cells repeat after one mesh period (host side): the cells' stiffness
    matrix Σ k l V Vᵀ, load Σ k l δ0 V and Σ k l δ0² (invariant under a renumbering of the
    contact lines) at 16 travels x and x + p_b."""
    p = float(stage.mesh_period())
    xs = (np.arange(16) + 0.37) * p / 16
    rows = _cell_rows(stage, jnp.asarray(np.concatenate([xs, xs + p]), dtype))
    for i in range(16):
        a, b = (jax.tree.map(lambda f, j=j: f[j], rows) for j in (i, i + 16))
        prints = []
        for r in (a, b):
            kl = np.where(np.asarray(r.mask), np.asarray(r.k * r.length), 0.0)
            V, d = np.asarray(r.V), np.asarray(r.delta0)
            prints.append((np.einsum("c,ci,cj->ij", kl, V, V), kl @ (d[:, None] * V),
                           np.sum(kl * d * d)))
        for u, v in zip(*prints, strict=True):
            scale = max(float(np.max(np.abs(u))), float(np.max(np.abs(v))), 1e-300)
            if float(np.max(np.abs(u - v))) > 1e-7 * scale:
                return False
    return True


def gearbox_whine(
    chain: GearboxTorsional,
    run: GearboxRun,
    input_speeds,
    method: QuasiPeriodicBalance = QuasiPeriodicBalance(8, 1),
    *,
    positions: int = 64,
    law: AbstractContactLaw = ExactContact(),
) -> WhineResponse:
    """Gear whine of the whole coupled gearbox (module docstring; docs/whine.md, "A gearbox"):
    every mesh's force and approach at the orders of its own stage's mesh frequency, every
    coordinate's harmonics, at each input speed, from the quasi-periodic balance on the torus of
    the stages' mesh phases.

    The system is :func:`~jaxgear.gearbox.gearbox_dynamics`' (the same M, K, F, modal damping
    of ``run.damping_ratio``, loaded flanks and clock: stage k's cells at mesh travel v_k t), so
    that its orders are that time integration's steady state where no cell changes its contact
    state about the quasi-static one (``nonlinearity`` small, no ``contact_loss``).

    Args:
        chain: the stages and shafts; each stage with contact cells (``excited``) is one
            mesh-frequency group, in stage order (group 0 the first such stage); a stage of
            constant springs is a linear element of no group (its meshes' group -1).
        run: :class:`~jaxgear.gearbox.GearboxRun` (its torque, output hold, damping ratio and
            ``mean_positions``; the time plan is not used).
        input_speeds: the first stage's input member's speed (rad/s, nonzero, finite), scalar
            or (S,).
        method: :class:`~jaxgear.dynamics.QuasiPeriodicBalance` (H each stage's own orders, S
            the sidebands of the other stages' orders).
        positions: grid points per mesh period of each excited stage: an int >= 4H + 1 for
            every stage, or a tuple of G such ints (one per excited stage, in stage order: a
            slow stage on a coarser axis); the grid has their product of points, each a static
            contact solve.
        law: the static solve's contact law (its tangent weights make K_m).

    Returns:
        :class:`~jaxgear.dynamics.WhineResponse` with ``speed`` the input speeds,
        ``frequency`` group 0's mesh frequency (Hz), ``orders`` each output's frequency over
        it, ``order_group`` / ``group_order`` (the outputs: the mean, then orders 1..H of each
        group), ``mesh_group`` (each mesh's stage group, meshes in
        :func:`~jaxgear.gearbox.mesh_names`' order), ``mesh_force`` (N, compression positive),
        ``transmission_error`` each mesh's approach along its line of action u_m·X (m; u_m
        its cells' structure vectors averaged with their stiffness over the grid: for a
        torsional pair cos β_b (r_b1 θ_1 + r_b2 θ_2) on its loaded flanks; the mean includes
        the rigid motion's share, e.g. a planetary stage's pin offsets are not subtracted),
        ``bearing_force`` with no component (r = 0: the coupled model has no bearing rows).

    Raises:
        ValueError: an argument of another kind; a speed zero or not finite; positions below
            4H + 1, or a tuple not of G positive ints; a chain without contact cells; a stage whose cells do not repeat every mesh
            period (a stepped-planet stage with z_p1 != z_p2, per-tooth deviations), named.
        TypeError: ``method`` not a QuasiPeriodicBalance.
        eqx.EquinoxRuntimeError: the static contact solve failed at some grid point.
    """
    _check(chain, run, law, "gearbox_whine")
    if not isinstance(method, QuasiPeriodicBalance):
        raise TypeError(f"gearbox_whine: method = {method!r}: allowed "
                        "jaxgear.dynamics.QuasiPeriodicBalance(harmonics, sidebands)")
    H, Sb = int(method.harmonics), int(method.sidebands)
    if not isinstance(positions, (tuple, list)):
        check_integer("positions", positions, 4)
    if not isinstance(positions, (tuple, list)) and positions < 4 * H + 1:
        raise ValueError(f"gearbox_whine: positions = {positions}: allowed >= 4 harmonics + 1 = "
                         f"{4 * H + 1} per mesh period")
    if np.ndim(input_speeds) > 1 or np.size(input_speeds) == 0:
        raise ValueError(f"gearbox_whine: input_speeds = {input_speeds!r}: allowed nonzero speeds "
                         "(rad/s), scalar or (S,)")
    if not is_traced(input_speeds):
        sp = np.asarray(input_speeds, dtype=float)
        if not np.all(np.isfinite(sp)) or np.any(sp == 0):
            raise ValueError(f"gearbox_whine: input_speeds = {input_speeds!r}: allowed finite "
                             "nonzero speeds (rad/s)")
    excited = [k for k, s in enumerate(chain.stages) if s.excited()]
    if not excited:
        raise ValueError("gearbox_whine: chain has no stage with contact cells: allowed a chain "
                         "with at least one stage's meshes on cells (a mesh frequency)")
    group_of = tuple(excited.index(k) if k in excited else -1 for k in range(len(chain.stages)))
    G = len(excited)
    R = group_positions(positions, G, "gearbox_whine: positions")
    if min(R) < 4 * H + 1:
        raise ValueError(f"gearbox_whine: positions = {positions!r}: allowed >= 4 harmonics + 1 "
                         f"= {4 * H + 1} per mesh period of each excited stage")
    # the one check that evaluates the stages' cells, after every argument's own
    dtype = run.input_torque.dtype
    for k in excited:
        s = chain.stages[k]
        for sign in (1.0, -1.0):
            if not _repeats(s.on_flanks(jnp.asarray(sign, dtype)), dtype):
                raise ValueError(
                    f"gearbox_whine: stage {k + 1} ({type(s).__name__}): its cells do not repeat "
                    "every mesh period (stepped planets of two tooth counts, per-tooth "
                    "deviations): allowed stages whose meshes repeat every mesh period")
    # the mesh basis: every cell's structure vector on both flanks at the grid positions
    xs = tuple(_travels(s, R[g] if g >= 0 else 1, dtype)
               for s, g in zip(chain.stages, group_of, strict=True))
    Vs = []
    for sign in (1.0, -1.0):
        st = [s.on_flanks(jnp.asarray(sign, dtype)) for s in chain.stages]
        for V, _, _, _, mask in _embedded(st, chain.housing, [1.0] * len(st), xs):
            Vs.append((np.asarray(V), np.asarray(mask)))
    n = Vs[0][0].shape[-1]
    basis = mesh_basis(np.concatenate([v.reshape(-1, n) for v, _ in Vs]),
                       np.concatenate([m.reshape(-1) for _, m in Vs]))
    basis = np.eye(n) if basis is None else basis
    hs = harmonic_set(G, H, Sb)
    out = np.asarray([np.zeros(G, int)] + [np.eye(G, dtype=int)[g] * k for g in range(G)
                                            for k in range(1, H + 1)])
    where = {tuple(h): i for i, h in enumerate(hs)}
    out_index = tuple(where[tuple(h)] for h in out)
    group = np.concatenate([[0], np.repeat(np.arange(G), H)])
    order = np.concatenate([[0], np.tile(np.arange(1, H + 1), G)])
    mesh_group = tuple(group_of[k] for k, s in enumerate(chain.stages) for _ in s.mesh_names())
    # the static part depends on the speed only through the rotating frames' stiffness
    per_speed = any(bool(np.any(np.asarray(s.speed_terms(as_float(1.0))[1]) != 0.0))
                    for s in chain.stages)
    spec = (R, int_rows(hs), int_rows(out), out_index, group_of, per_speed)
    speeds = jnp.atleast_1d(jnp.asarray(input_speeds, dtype))
    idx = np.stack(np.meshgrid(*[np.arange(r) for r in R], indexing="ij"), -1).reshape(-1, G)
    response, failed = _gearbox_whine(chain, run, law, spec, xs, speeds,
                                      jnp.asarray(basis, dtype), jnp.asarray(idx))
    response = dataclasses.replace(response, order_group=jnp.asarray(group),
                                   group_order=jnp.asarray(order), mesh_group=mesh_group)
    message = ("gearbox_whine: the static contact solve failed at some points of the torus grid "
               "(no contact or no convergence): check the torque and the modifications")
    return checked_on_host(response, failed, message)




def _travels(stage, R, dtype):
    """The grid's mesh travels of a stage: the mid-points x = p_b (r + ½)/R (R = 1: a stage of
    constant springs, one row)."""
    return stage.mesh_period() * (jnp.arange(R, dtype=dtype) + 0.5) / R


@eqx.filter_jit
def _gearbox_whine(chain, run, law, spec, xs, speeds, basis, idx):
    # idx (N, G): the grid's row of each group (C order, the last fastest), an argument (not a
    # constant of the program: XLA would fold the grid's exponentials at compile time)
    R, hs, out, out_index, group_of, per_speed = spec
    hs, out, out_index = np.asarray(hs), np.asarray(out), np.asarray(out_index)
    N = idx.shape[0]
    dtype = basis.dtype
    G = len(R)
    # the harmonics' places on the grid's FFT and the half-step shift of the mid-points
    # s_g = (r_g + 1/2) / R_g (the inverse of torus_coefficients)
    at_grid = tuple(np.mod(hs[:, g], R[g]) for g in range(G))
    shift = jnp.asarray(np.exp(1j * np.pi * sum(hs[:, g] / R[g] for g in range(G))))

    def on_grid(Yh):
        """Σ_h Y_h e^{2πi h·s} at every grid point, (N, ...) real, from harmonics (Nh, ...)."""
        full = jnp.zeros(tuple(R) + Yh.shape[1:], Yh.dtype)
        full = full.at[at_grid].add(Yh * shift.reshape((-1,) + (1,) * (Yh.ndim - 1)))
        return jnp.real(jnp.fft.ifftn(full, axes=tuple(range(G))) * N).reshape((N,) + Yh.shape[1:])
    diff = hs[:, None, :] - hs[None, :, :]
    counts = _cell_counts(chain)
    member = []  # each mesh's cells (m, c) over the whole row
    for s, c in zip(chain.stages, counts, strict=True):
        member.append(jax.jacobian(s.mesh_forces)(jnp.zeros(c, dtype)) != 0)
    member = jax.scipy.linalg.block_diag(*[m.astype(dtype) for m in member])

    def operating(speed):
        """The static grid and its Fourier coefficients at one speed (the rotating frames'
        stiffness), with the coupled matrices."""
        m, k, _, c_omega, f, k_mean, _, _, _ = _assemble(chain, run, speed)
        first = _embedded(chain.stages, chain.housing, [1.0] * len(chain.stages),
                          [x[:1] for x in xs])
        rows0 = [CellRow(None, V[0], kk[0], ln[0], d[0], mk[0]) for V, kk, ln, d, mk in first]
        signs = _flank_signs(chain, k, f, k_mean, rows0)
        stages = [s.on_flanks(g) for s, g in zip(chain.stages, signs, strict=True)]
        per_stage = _embedded(stages, chain.housing, signs, xs)
        cols = [idx[:, g] if g >= 0 else jnp.zeros(N, idx.dtype) for g in group_of]

        def gather(i):
            return jnp.concatenate([a[i][col] for a, col in zip(per_stage, cols, strict=True)],
                                   axis=1)

        V, kc, ln, d0, mask = (gather(i) for i in range(5))

        def solve(a):
            sol = solve_contact(k, f, *a, law)
            return sol.x, sol.weight, sol.force_density, sol.result

        # one grid point at a time: a batch would run the contact solve's LU as one batched
        # LAPACK call, which can deadlock XLA's CPU thread pool (see _util.each_solve)
        x, weight, fd, result = jax.lax.map(solve, (V, kc, ln, d0, mask))
        kl = jnp.where(mask, weight * kc * ln, 0.0)  # (N, c)
        Vb = V @ basis  # (N, c, r)
        Km = jnp.einsum("sc,sci,scj->sij", kl, Vb, Vb)
        coupling = torus_coefficients(Km, R, diff)
        Xh = torus_coefficients(x, R, hs)
        modes = matrix_modal_analysis(m, k, k_mean)
        mphi = m @ modes.shapes
        c = mphi @ ((2.0 * run.damping_ratio * modes.omega)[:, None] * mphi.T) + c_omega
        gap = jnp.where(mask, jnp.einsum("sci,si->sc", V, x) - d0, 0.0)
        kl_all = jnp.where(mask, kc * ln, 0.0)
        u = jnp.einsum("mc,sc,sci->mi", member, kl, V) / jnp.einsum("mc,sc->m", member, kl)[:, None]
        return (m, k, c, coupling, Xh, Vb, kl, kl_all, gap, fd * ln, u, jnp.any(result != 0))

    def balance(op, speed):
        m, k, c, coupling, Xh, Vb, kl, kl_all, gap, fsd, u, failed = op
        kin = _kinematics(chain, speed, run.input_torque)
        omega = jnp.stack([2 * jnp.pi * kin[j][1] / chain.stages[j].mesh_period()
                           for j, g in enumerate(group_of) if g >= 0])  # (G,) in group order
        nu = jnp.asarray(hs, dtype) @ omega
        F = (nu**2)[:, None] * (Xh @ m.T) - 1j * nu[:, None] * (Xh @ c.T)
        Y = quasi_periodic_balance(m, c, k, coupling, F, nu, basis=basis)  # (Nh, n)
        yb = on_grid(Y @ basis)  # (N, r)
        vy = jnp.einsum("scr,sr->sc", Vb, yb)
        fm = _split_forces(chain, fsd + kl * vy)  # (N, m)
        g = gap + vy
        misplaced = _split_forces(chain, kl_all * jnp.maximum(g, 0.0) - kl * g)
        fs = jnp.mean(_split_forces(chain, fsd), axis=0)
        X = Xh[out_index] + Y[out_index]
        return (omega[0], X, torus_coefficients(fm, R, out), jnp.min(fm, axis=0),
                jnp.max(jnp.abs(misplaced), axis=0) / fs, fs, Xh[out_index], u, failed)

    if per_speed:
        res = jax.lax.map(lambda sp: balance(operating(sp), sp), speeds)
        fs, qs, u, failed = res[5][0], res[6][0], res[7][0], jnp.any(res[8])
    else:
        op = operating(speeds[0])
        res = jax.lax.map(lambda sp: balance(op, sp), speeds)
        fs, qs, u, failed = res[5][0], res[6][0], res[7][0], res[8][0]
    omega0, X, fh, fmin, nonlin = res[:5]
    one_sided = jnp.concatenate([jnp.ones(1), 2.0 * jnp.ones(out.shape[0] - 1)]).astype(X.dtype)
    X = X * one_sided[None, :, None]
    fh = fh * one_sided[None, :, None]
    te = jnp.einsum("shn,mn->shm", X, u.astype(X.dtype))
    # the groups' frequency ratios (all speeds scale together)
    kin1 = _kinematics(chain, jnp.ones((), dtype), run.input_torque)
    w1 = jnp.stack([kin1[j][1] / chain.stages[j].mesh_period()
                    for j, g in enumerate(group_of) if g >= 0])
    orders = (jnp.asarray(out, dtype) @ (w1 / w1[0])).astype(dtype)
    return WhineResponse(
        speed=speeds,
        frequency=omega0 / (2 * jnp.pi),
        orders=orders,
        coordinates=X,
        quasi_static=qs * one_sided[:, None],
        transmission_error=te,
        mesh_force=fh,
        bearing_force=jnp.zeros(X.shape[:2] + (0,), X.dtype),
        static_force=fs,
        min_mesh_force=fmin,
        contact_loss=fmin <= 0.0,
        nonlinearity=nonlin,
    ), failed

