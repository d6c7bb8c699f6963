"""A gearbox as one dynamic model: every stage's contact cells in one Newmark run (docs/gearbox.md,
"The coupled model").

The stages of a :class:`~jaxgear.gearbox.GearboxTorsional` (their coordinates,
:meth:`~jaxgear.dynamics.AbstractStage.coordinates`: rotations in rad, a planetary stage's
translations in m in its own carrier frame) are stacked block after block; the shafts join one
stage's output rotation to the next stage's input rotation (torsional stiffness, massless); the
first stage's input member carries the input torque T and the last stage's output member is
held by a torsional spring ``output_stiffness`` to ground:

    M q'' + (C + C_Omega) q' + (K_s + K_shafts + K_hold + K_Omega) q + sum_k V_k^T P_k = F,

with stage k's cells P_k at its own mesh travel x_k = v_k t, v_k its mesh speed at the operating
point (:meth:`~jaxgear.dynamics.AbstractStage.kinematics` from the input speed, stage by
stage), C the modal damping on the modes of (M, K + K̄_m), K̄_m every mesh's cell stiffness
averaged over its own mesh period (block-diagonal). Each stage's flanks are the ones the input
torque loads: a stage whose meshes the torque would open is taken on its other flanks (its rows'
sign flipped; a spur stage's flanks are alike).

With a housing the stages share (:attr:`~jaxgear.gearbox.GearboxTorsional.housing`), the h
coordinates that end each housed stage's are one set, kept once after every stage's own
(:func:`_layout`): each stage's matrices are added on it (its bearings' seat couplings), and the
housing's own K_h, M_h and C_h, which each housed stage carries, once.
"""

from __future__ import annotations

import math

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Float

from .._baseplane import CellRow, on_the_path
from .._contact import AbstractContactLaw, ExactContact, solve_contact
from .._util import as_float, check_instance, check_integer, check_real
from ..dynamics import (
    STEPS_PER_MODE,
    LinearSystem,
    ModalAnalysis,
    StepCells,
    matrix_modal_analysis,
    newmark,
)
from ._chain import GearboxTorsional

__all__ = [
    "CoupledModes",
    "GearboxDynamics",
    "GearboxRun",
    "coordinate_names",
    "coupled_mode_table",
    "gearbox_coupled_modes",
    "mesh_names",
]



class GearboxRun(eqx.Module):
    """How a coupled gearbox run is loaded and integrated.

    Attributes:
        input_torque: T (N m) on the first stage's input member (its magnitude: each stage's
            loaded flanks follow from it).
        output_stiffness: the torsional spring (N m/rad, > 0) that holds the last stage's output
            member to ground (the load).
    The automatic plan is the engine's rule for every dynamic model (the gearbox's
    :class:`~jaxgear.gearbox.GearboxModel` through :func:`jaxgear.dynamics.speed_sweep`): the
    step from the highest excited mode (:func:`jaxgear.dynamics.auto_steps_per_period`), the
    span from settling (:func:`jaxgear.dynamics.settling_time`).

    Attributes:
        input_torque: T (N m) on the first stage's input member (its magnitude: each stage's
            loaded flanks follow from it).
        output_stiffness: the torsional spring (N m/rad, > 0) that holds the last stage's output
            member to ground (the load).
        steps_per_period: Newmark steps per mesh period of the fastest excited mesh (static,
            >= 8); the time step is that period over it. None: automatic, the smallest power
            of two >= max(64, ``steps_per_mode`` f_max / f_ref) at the lowest speed of the run
            or sweep (f_max the highest coupled mode whose strain energy the meshes hold
            >= 5 %, :func:`jaxgear.dynamics.excited_omega` of :func:`gearbox_coupled_modes`;
            f_ref the fastest excited mesh frequency; the spur meshes' stiffness steps ring
            every mode, and average acceleration leaves an under-resolved one undamped).
        periods: blocks integrated (static, >= 2), a block the slowest excited mesh's period
            (rounded to whole steps). None: automatic, the settling time in whole blocks at
            the highest speed of the run or sweep, then ``keep_periods`` (the run starts from
            the quasi-static state, so that the transient is the dynamic part alone).
        keep_periods: the last blocks recorded (static, 1..periods).
        damping_ratio: zeta (-), modal damping on every mode of (M, K + K̄_m).
        mean_positions: the mesh positions per period over which K̄_m is averaged (static).
        steps_per_mode: the automatic step's steps per period of the highest excited mode
            (static, >= 4; default :data:`jaxgear.dynamics.STEPS_PER_MODE`, 40).
        settle: the automatic span's settling time in time constants 1 / (zeta omega) of the
            slowest decaying mode the meshes excite (static, >= 0); None (default): the
            engine's, ln(1 / :data:`jaxgear.dynamics.SETTLE_TOL`) = 6.9 of them
            (:func:`jaxgear.dynamics.settling_time`).
    """

    input_torque: Float[Array, ""] = eqx.field(converter=as_float)
    output_stiffness: Float[Array, ""] = eqx.field(converter=as_float)
    steps_per_period: int | None = eqx.field(static=True, default=32)
    periods: int | None = eqx.field(static=True, default=40)
    keep_periods: int = eqx.field(static=True, default=2)
    damping_ratio: Float[Array, ""] = eqx.field(converter=as_float, default=0.05)
    mean_positions: int = eqx.field(static=True, default=64)
    steps_per_mode: int = eqx.field(static=True, default=STEPS_PER_MODE)
    settle: float | None = eqx.field(static=True, default=None)

    def __check_init__(self):
        if self.steps_per_period is not None:
            check_integer("steps_per_period", self.steps_per_period, 8)
        if self.periods is not None:
            check_integer("periods", self.periods, 2)
        check_integer("keep_periods", self.keep_periods, 1)
        check_integer("mean_positions", self.mean_positions, 1)
        check_integer("steps_per_mode", self.steps_per_mode, 4)
        if self.settle is not None and not (
                isinstance(self.settle, (int, float)) and math.isfinite(self.settle)
                and self.settle >= 0.0):
            raise ValueError(f"GearboxRun: settle = {self.settle!r} is out of range: allowed a "
                             "finite number of time constants >= 0, or None")
        if self.periods is not None and self.keep_periods > self.periods:
            raise ValueError(f"GearboxRun: keep_periods = {self.keep_periods} is out of range: "
                             f"allowed 1..periods = {self.periods}")
        check_real("input_torque", self.input_torque, "N m", shape=(), where="GearboxRun")
        check_real("output_stiffness", self.output_stiffness, "N m/rad", lo=0.0, lo_open=True,
                   shape=(), where="GearboxRun")
        check_real("damping_ratio", self.damping_ratio, lo=0.0, hi=1.0, shape=(),
                   where="GearboxRun")


class GearboxDynamics(eqx.Module):
    """The recorded steady state of a coupled run (the last ``keep_periods`` blocks).

    Attributes:
        time: s, (t,).
        displacement: the coupled coordinates (rad or m), (t, n).
        mesh_forces: every mesh's transverse force (N, compression positive), (t, m), stage
            after stage in :func:`mesh_names`' order.
        static_forces: each mesh's static force from the torque ratios (N), (m,).
        dynamic_factors: max over the recorded window of the mesh force / its static force (-),
            (m,).
        mesh_speeds: each stage's mesh travel speed v_k (m/s), (n_stages,).
        result: the run's result code (0: successful; :class:`~jaxgear.DynamicsResult`), ().
        steps: the Newmark steps integrated, settling and recorded window together (-), ()
            (the time plan, :class:`GearboxRun`'s ``steps_per_period`` and ``periods`` or
            their automatic values).
    """

    time: Float[Array, " t"]
    displacement: Float[Array, "t n"]
    mesh_forces: Float[Array, "t m"]
    static_forces: Float[Array, " m"]
    dynamic_factors: Float[Array, " m"]
    mesh_speeds: Float[Array, " s"]
    result: Array
    steps: Array


def mesh_names(chain: GearboxTorsional) -> tuple[str, ...]:
    """``"<k>:<mesh>"`` per mesh of the coupled model, k the stage's index from 1."""
    return tuple(f"{k + 1}:{n}" for k, s in enumerate(chain.stages) for n in s.mesh_names())


def coordinate_names(chain: GearboxTorsional) -> tuple[str, ...]:
    """``"<k>:<coordinate>"`` per coordinate of the coupled model; with a shared housing
    (:attr:`~jaxgear.gearbox.GearboxTorsional.housing`) its coordinates last, once, named by
    :meth:`~jaxgear.scenes.Housing.coordinate_names` (``"housing <seat> <dof>"``, 6 per seat,
    then ``"housing mode <j>"``: no stage prefix)."""
    h = _shared(chain.stages, chain.housing)
    own = tuple(f"{k + 1}:{n}" for k, s in enumerate(chain.stages)
                for n in s.coordinates()[:len(s.coordinates()) - h[k]])
    if chain.housing is None:
        return own
    return own + chain.housing.coordinate_names()


def _shared(stages, housing) -> list[int]:
    """Per stage, how many of its last coordinates are the shared housing's (0 without)."""
    if housing is None:
        return [0] * len(stages)
    return [0 if s.housing() is None else housing.size for s in stages]


def _layout(stages, housing=None):
    """(per stage, the coupled coordinate of each of its coordinates (NumPy ints), n): the
    stages' own coordinates block after block, then a shared housing's once (the h
    coordinates that end each housed stage's, :meth:`~jaxgear.dynamics.AbstractStage.housing`)."""
    h = _shared(stages, housing)
    widths = [len(s.coordinates()) - hk for s, hk in zip(stages, h, strict=True)]
    n_own = sum(widths)
    starts = np.cumsum([0, *widths[:-1]])
    idx = [np.concatenate([np.arange(a, a + w), n_own + np.arange(hk)]).astype(int)
           for a, w, hk in zip(starts, widths, h, strict=True)]
    return idx, n_own + (0 if housing is None else housing.size)


def _offsets(chain):
    idx, n = _layout(chain.stages, chain.housing)
    return [int(i[0]) for i in idx], n


def _kinematics(chain, input_speed, input_torque):
    """Per stage: (input speed, mesh speed, static mesh forces); the speeds carried stage by
    stage through the shafts (a shaft's two ends turn alike)."""
    w, t = as_float(input_speed), as_float(input_torque)
    out = []
    for s in chain.stages:
        w_out, t_out, v, f = s.kinematics(w, t)
        out.append((w, v, f))
        w, t = w_out, t_out
    return out


def _assemble(chain, run, input_speed):
    """The coupled system's parts at one input speed: (M, K (structure, shafts, hold, rotating
    frame), C_Omega, F, K̄_m, the stages' kinematics (:func:`_kinematics`), the stages' mesh
    speeds, the static forces)."""
    idx, n = _layout(chain.stages, chain.housing)
    blocks = [s.dynamic_parts(run.mean_positions) for s in chain.stages]
    dtype = blocks[0][0].dtype
    if chain.housing is None:  # the stages' blocks one after the other
        embed = lambda mats: jax.scipy.linalg.block_diag(*mats)
        f = jnp.concatenate([b[3] for b in blocks])
    else:  # a shared housing's coordinates are several stages' at once
        def embed(mats):
            out = jnp.zeros((n, n), dtype)
            for a, i in zip(mats, idx, strict=True):
                out = out.at[np.ix_(i, i)].add(a)
            return out

        f = jnp.zeros(n, dtype)
        for b_k, i in zip(blocks, idx, strict=True):
            f = f.at[i].add(b_k[3])
    m = embed([b[0] for b in blocks])
    k_s = embed([b[1] for b in blocks])
    k_mean = embed([b[2] for b in blocks])
    kin = _kinematics(chain, input_speed, run.input_torque)
    c_w, k_w = [], []
    for s, (w, _, _) in zip(chain.stages, kin, strict=True):
        c_k, k_k = s.speed_terms(s.carrier_speed(w))
        c_w.append(c_k)
        k_w.append(k_k)
    c_omega, k_omega = embed(c_w), embed(k_w)
    if chain.housing is not None:  # each housed stage brought the housing's own parts: once
        extra = 1 - sum(1 for s in chain.stages if s.housing() is not None)
        hh = np.arange(n - chain.housing.size, n)
        at = np.ix_(hh, hh)
        m = m.at[at].add(extra * chain.housing.M)
        k_s = k_s.at[at].add(extra * chain.housing.K)
        c_omega = c_omega.at[at].add(extra * chain.housing.C)
    b = _joints(chain, idx, n, dtype)
    springs = jnp.concatenate([chain.shaft_stiffnesses, run.output_stiffness[None]])
    k_joint = b.T @ (springs[:, None] * b)
    i_in = idx[0][chain.stages[0].coordinate_ends()[0]]
    f = f.at[i_in].add(jnp.abs(run.input_torque))
    k = k_s + k_joint + k_omega
    speeds = jnp.stack([v for _, v, _ in kin])
    static = jnp.concatenate([fk for _, _, fk in kin])

    return m, k, k_s + k_joint, c_omega, f, k_mean, kin, speeds, static


def _joints(chain, idx, n, dtype):
    """b (n_stages, n): the shafts' twists b q, b = e_out(k) - e_in(k + 1), then the hold's (the
    last output member)."""
    b = np.zeros((len(chain.stages), n))
    for j in range(len(chain.stages) - 1):
        b[j, idx[j][chain.stages[j].coordinate_ends()[1]]] = 1.0
        b[j, idx[j + 1][chain.stages[j + 1].coordinate_ends()[0]]] = -1.0
    b[-1, idx[-1][chain.stages[-1].coordinate_ends()[1]]] = 1.0
    return jnp.asarray(b, dtype)


def _cells(stages, kin, housing=None):
    """The cells' function of time (s): each stage's cell row at its own mesh travel v_k t, on
    the coupled coordinates (``housing``: the chain's shared housing, :func:`_layout`)."""
    idx, n = _layout(stages, housing)

    def cells(t):
        rows = []
        for s, i, (_, v, _) in zip(stages, idx, kin, strict=True):
            r = s.cell_row(v * t)
            V = jnp.zeros((r.V.shape[0], n), r.V.dtype).at[:, i].set(r.V)
            rows.append(r._replace(V=V))
        return rows

    return cells


def _flank_signs(chain, k, f, k_mean, rows):
    """+1 or -1 per stage: the sign of the stage's mesh deflections under the static load with
    the mean mesh stiffness (its loaded flanks)."""
    q = jnp.linalg.solve(k + k_mean, f)
    signs = []
    for r in rows:
        kl = jnp.where(r.mask, r.k * r.length, 0.0)
        signs.append(jnp.where(jnp.sum(kl * (r.V @ q)) < 0, -1.0, 1.0))
    return signs


def _signed(rows, signs):
    return CellRow(None, *(jnp.concatenate(f) for f in zip(
        *[r._replace(V=s * r.V, idx=None)[1:] for r, s in zip(rows, signs, strict=True)],
        strict=True)))


def _split_forces(chain, P):
    out, c0 = [], 0
    for s, c in zip(chain.stages, _cell_counts(chain), strict=True):
        out.append(s.mesh_forces(P[..., c0:c0 + c]))
        c0 += c
    return jnp.concatenate(out, axis=-1)


def _cell_counts(chain):
    return [int(s.cell_row(jnp.zeros(())).k.shape[0]) for s in chain.stages]



def _excited_periods(chain: GearboxTorsional) -> tuple[float, float]:
    """(fast, slow): the periods of the fastest and the slowest excited mesh (a stage with
    contact cells, :meth:`~jaxgear.dynamics.AbstractStage.excited`; without one, the first stage's) per
    unit of 1 / input speed, i.e. the input member's rotation over them (rad), host side (the
    periods' ratios do not depend on the speed)."""
    kin = _kinematics(chain, 1.0, 1.0)
    periods = [float(s.mesh_period() / v) for s, (_, v, _) in zip(chain.stages, kin, strict=True)
               if s.excited()]
    if not periods:
        periods = [float(chain.stages[0].mesh_period() / kin[0][1])]
    return min(periods), max(periods)


@eqx.filter_jit
def _run(chain, run, input_speed, law, S, block, fast, B):

    m, k, _, c_omega, f, k_mean, kin, speeds, static = _assemble(chain, run, input_speed)
    modes = matrix_modal_analysis(m, k, k_mean)
    phi, w = modes.shapes, modes.omega
    mphi = m @ phi
    c = mphi @ ((2.0 * run.damping_ratio * w)[:, None] * mphi.T)
    dt = fast / (S * jnp.abs(as_float(input_speed)))
    signs = _flank_signs(chain, k, f, k_mean,
                         _cells(chain.stages, kin, chain.housing)(0.5 * dt))
    # each stage's cells for its loaded flanks (a planetary stage whose planets drive the sun:
    # its sun-ring phase, ContactMeshes.other_flanks), the rows' sign flipped below
    cells = _cells([s.on_flanks(g) for s, g in zip(chain.stages, signs, strict=True)], kin,
                   chain.housing)

    def row(i):
        return _signed(cells((i + 0.5) * dt), signs)

    r0 = row(jnp.zeros_like(dt))
    start = solve_contact(k, f, r0.V, r0.k, r0.length, r0.delta0, r0.mask, law)
    system = LinearSystem(K=k, M=m, C=c + c_omega, F=f)
    steps = (jnp.arange(B * block, dtype=dt.dtype) + 1.0).reshape(B, block)
    zero = jnp.zeros_like(start.x)
    code = (jnp.array(0, jnp.int32), jnp.array(0, jnp.int32))

    def record(X, Xd, P, i):
        return X, _split_forces(chain, P), i

    final, (X, forces, i) = newmark(system, dt, (start.x, zero, zero, *code), steps,
                                    StepCells(row, law), record, keep_blocks=run.keep_periods)
    return GearboxDynamics(
        time=(i + 0.5) * dt,
        displacement=X,
        mesh_forces=forces,
        static_forces=static,
        dynamic_factors=jnp.max(forces, axis=0) / static,
        mesh_speeds=speeds,
        result=final[-2],
        steps=jnp.asarray(B * block, jnp.int32),
    )


@eqx.filter_jit
def _sweep(chain, run, speeds, law, S, block, fast, B):
    return jax.vmap(lambda w: _run(chain, run, w, law, S, block, fast, B))(speeds)


def _check(chain, run, law, where):
    check_instance("chain", chain, GearboxTorsional, "a jaxgear.gearbox.GearboxTorsional", where)
    check_instance("run", run, GearboxRun, "a jaxgear.gearbox.GearboxRun", where)
    check_instance("law", law, AbstractContactLaw, "a jaxgear contact law", where)


class CoupledModes(eqx.Module):
    """The coupled gearbox's modes on (M, K + K̄_m) (:func:`gearbox_coupled_modes`).

    Attributes:
        analysis: :class:`~jaxgear.dynamics.ModalAnalysis` (``frequency`` Hz, ``shapes``
            mass-normalised, ``energy`` rows ("mesh", "structure")).
        mesh_energy: each mesh's share of each mode's strain energy (-), (m, n).
        joint_energy: each shaft's (then the output hold's) share (-), (n_stages, n).
        stage_energy: each stage's share of each mode's kinetic energy (-), (n_stages, n).
        housing_energy: with a shared housing (:attr:`~jaxgear.gearbox.GearboxTorsional.housing`)
            its coordinates' share of each mode's kinetic energy (-), (n,) (the stages' shares
            then sum to 1 minus it); None without one.
    """

    analysis: ModalAnalysis  # jaxgear.dynamics.ModalAnalysis
    mesh_energy: Float[Array, "m n"]
    joint_energy: Float[Array, "j n"]
    stage_energy: Float[Array, "s n"]
    housing_energy: Float[Array, " n"] | None = None


def _coupled_modes(chain, run):
    # the modal solve reads the torque, the hold, the damping and the mean positions only: the
    # time plan (static fields) is set to GearboxRun's defaults so that runs with different
    # plans share one compiled modal solve
    return _modes_compiled(chain, GearboxRun(
        input_torque=run.input_torque, output_stiffness=run.output_stiffness,
        damping_ratio=run.damping_ratio, mean_positions=run.mean_positions))


@eqx.filter_jit
def _modes_compiled(chain, run):
    speed = jnp.ones(())
    m, _, k, _, _, k_mean, _, _, _ = _assemble(chain, run, speed)
    # the per-mesh mean stiffness: each stage's rows over its own mesh period
    idx, n = _layout(chain.stages, chain.housing)
    modes = matrix_modal_analysis(m, k, k_mean)
    phi = modes.shapes
    strain = jnp.einsum("in,ij,jn->n", phi, k + k_mean, phi)
    strain = jnp.where(modes.rigid, 1.0, strain)
    mesh_e = []
    for s, i in zip(chain.stages, idx, strict=True):
        P = run.mean_positions
        x = s.mesh_period() * (jnp.arange(P) + 0.5) / P
        rows = jax.vmap(on_the_path(s).cell_row)(x)  # K̄_m's cells (on the path)
        kl = jnp.where(rows.mask, rows.k * rows.length, 0.0)  # (p, c)
        d = jnp.einsum("pci,in->pcn", rows.V, phi[i])
        cell_e = jnp.mean(kl[..., None] * d**2, axis=0)  # (c, n)
        member = jax.jacobian(s.mesh_forces)(jnp.zeros(kl.shape[1], kl.dtype)) != 0  # (m, c)
        mesh_e.append(member.astype(kl.dtype) @ cell_e)
    mesh_e = jnp.concatenate(mesh_e) / strain[None]
    # joints: the shafts and the hold, b q twist
    b = _joints(chain, idx, n, phi.dtype)
    springs = jnp.concatenate([chain.shaft_stiffnesses, run.output_stiffness[None]])
    joint_e = springs[:, None] * (b @ phi) ** 2 / strain[None]
    owner = np.full(n, -1)  # a shared housing's coordinates belong to no stage
    for k, i in enumerate(idx):
        owner[i[:len(i) - _shared(chain.stages, chain.housing)[k]]] = k
    belongs = jnp.asarray(owner[None, :] == np.arange(len(chain.stages))[:, None], phi.dtype)
    energy = phi * (m @ phi)
    kinetic = belongs @ energy
    if chain.housing is None:
        return CoupledModes(modes, mesh_e, joint_e, kinetic / kinetic.sum(axis=0, keepdims=True))
    total = energy.sum(axis=0)
    housing_e = jnp.sum(jnp.where(owner[:, None] < 0, energy, 0.0), axis=0) / total
    return CoupledModes(modes, mesh_e, joint_e, kinetic / total[None], housing_e)


def gearbox_coupled_modes(chain: GearboxTorsional, run: GearboxRun) -> CoupledModes:
    """The natural modes of the coupled gearbox (the system a :func:`gearbox_dynamics` run's
    modal damping takes): (M, K + K̄_m) with the shafts, the output hold ``run.output_stiffness``
    and every mesh's cell stiffness averaged over its mesh period, through
    :func:`jaxgear.dynamics.modal_analysis` (one modal solve), with each mesh's and joint's share
    of the strain energy (seed (2.36)) and each stage's share of the kinetic energy. The rotating
    frame's terms are left out (the modes at rest).

    Raises:
        ValueError: an argument of another kind (one line)."""
    _check(chain, run, ExactContact(), "gearbox_coupled_modes")
    return _coupled_modes(chain, run)


def coupled_mode_table(chain: GearboxTorsional, modes: CoupledModes) -> list[dict]:
    """One row per mode (host side): ``frequency_Hz``, ``type`` ("rigid body", ``"mesh"`` where
    the meshes hold most of its strain energy, ``"shaft <k>-<k+1>"`` or ``"output hold"``
    where a joint does, else ``"structure"``), ``mesh`` (the mesh holding most strain energy,
    :func:`mesh_names`), ``mesh_energy`` (its share), ``mesh_total`` (every mesh's), ``stage``
    (the stage holding most kinetic energy, from 1); with a shared housing a mode of neither
    rigid, mesh nor joint type whose kinetic energy lies mostly (> 1/2) in the housing's
    coordinates is ``"housing"``."""
    names = mesh_names(chain)
    joints = [f"shaft {j + 1}-{j + 2}" for j in range(len(chain.stages) - 1)] + ["output hold"]
    f = np.asarray(modes.analysis.frequency)
    rigid = np.asarray(modes.analysis.rigid)
    me, je = np.asarray(modes.mesh_energy), np.asarray(modes.joint_energy)
    ke = np.asarray(modes.stage_energy)
    rows = []
    for j in range(f.size):
        mesh_total, joint_best = me[:, j].sum(), int(np.argmax(je[:, j]))
        if rigid[j]:
            kind = "rigid body"
        elif mesh_total >= max(je[joint_best, j], 1.0 - mesh_total - je[:, j].sum()):
            kind = "mesh"
        elif je[joint_best, j] >= 1.0 - mesh_total - je[:, j].sum():
            kind = joints[joint_best]
        elif modes.housing_energy is not None and float(modes.housing_energy[j]) > 0.5:
            kind = "housing"
        else:
            kind = "structure"
        best = int(np.argmax(me[:, j]))
        rows.append({
            "frequency_Hz": float(f[j]),
            "type": kind,
            "mesh": names[best],
            "mesh_energy": float(me[best, j]),
            "mesh_total": float(mesh_total),
            "stage": int(np.argmax(ke[:, j])) + 1,
        })
    return rows
