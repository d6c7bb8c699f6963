"""The bearings of a quasi-static solution (the part of the case builders that takes a scene,
not a case): their mean forces (:func:`bearing_forces`), and the rolling bearings' operating
point, the fixed point of their loads and stiffnesses (:func:`bearings_at_operating_point`),
and their lives there (:func:`operating_lives`; under a load spectrum :func:`spectrum_lives`)."""

from __future__ import annotations

import dataclasses
import functools
import math
from typing import NamedTuple

import equinox as eqx
import jax.numpy as jnp
import numpy as np

from .._contact import ContactLaw, ExactContact
from .._quasi_static import QuasiStaticResult, quasi_static
from .._util import check_integer, check_real
from ..bearings import (
    BearingLife,
    BearingSpectrum,
    ModifiedLife,
    operating_life,
    solve_displacement,
    spectrum_life,
    spectrum_modified_life,
    spectrum_reference_life,
)
from ..scenes import Bearing, Grounded, bearing_dofs, grounded

__all__ = ["OperatingPoint", "SpectrumLife", "bearing_forces", "bearings_at_operating_point",
           "operating_lives", "spectrum_lives", "with_bearing_stiffness"]


@functools.singledispatch
def _bearing_scene(scene):
    """The scene whose bearings carry the load: the scene itself."""
    return scene


@_bearing_scene.register
def _(scene: Grounded):
    """A :class:`~jaxgear.scenes.Grounded` scene's bearings are its base's (the grounding
    spring is no bearing)."""
    return _bearing_scene(scene.base)


@functools.singledispatch
def _with_structure(scene, structure):
    """The scene with its assembled structure replaced by ``structure``."""
    return eqx.tree_at(lambda sc: sc.structure, scene, structure)


@_with_structure.register
def _(scene: Grounded, structure):
    """A :class:`~jaxgear.scenes.Grounded` scene's structure is its base's (its grounding
    spring kept as it is)."""
    return eqx.tree_at(lambda sc: sc.base, scene, _with_structure(scene.base, structure))


def with_bearing_stiffness(scene, shafts, changes: dict, extra_z=None):
    """The scene with bearing stiffness changes ΔK_b added where its assembly put each
    bearing, differentiably (JAX in the changes): the stiffness K + Σ_b W_bᵀ ΔK_b W_b, its
    ``bearings`` stiffness part likewise, and the bearing force rows (:attr:`~jaxgear.scenes.
    Structure.reaction`) + ΔK_b's translational rows.

    W_b is the bearing's relative motion: its shaft node's six DOFs on the ground; on a
    housing's seat (:class:`~jaxgear.scenes.HousingMount`, the joint ``bearing <k>``) the
    node's less the seat's, the coupling blocks (A, B, D) of
    :meth:`~jaxgear.scenes.HousingMount.blocks`, the node's own block ΔK_b (as the assembly
    puts it, :func:`~jaxgear.scenes._mount.couple_housing`). The assembly is linear in each
    bearing's matrix, so the result is the scene assembled on K_b + ΔK_b (NumPy) to
    round-off, here as a JAX expression of ΔK_b: a design variable of a bearing (its clearance,
    docs/bearings.md, "As a design variable") reaches the scene's stiffness through it.

    Args:
        scene: a lumped 3D scene assembled on ``shafts`` (:func:`~jaxgear.scenes.lumped_pair`,
            :class:`~jaxgear.scenes.LumpedTrain`; on the ground or with a housing), or a
            :class:`~jaxgear.scenes.Grounded` one.
        shafts: the :class:`~jaxgear.scenes.ShaftSpec` the scene was assembled on, in its
            order (their bearings' stiffness says which force rows the assembly made).
        changes: ``{(shaft index, bearing index): ΔK_b}``, each (6, 6) (SI, the node's frame;
            :class:`~jaxgear.scenes.Bearing`'s DOF order), symmetric.
        extra_z: the scene's more node positions per shaft (m), as it was assembled, or None.

    Raises:
        ValueError: a key that is not a bearing of ``shafts`` (one line).
    """
    base = _bearing_scene(scene)
    st = base.structure
    dofs = bearing_dofs(shafts, extra_z)
    mount = st.mount
    joints = {} if mount is None else {j.member: k for k, j in enumerate(mount.joints)}
    flat = [(i, j) for i, s in enumerate(shafts) for j in range(len(s.bearings))]
    for key in changes:
        if key not in flat:
            raise ValueError(f"with_bearing_stiffness: changes[{key!r}]: allowed (shaft, "
                             f"bearing) indices of the scene's bearings, {flat}")
    n = st.size
    dK = jnp.zeros((n, n), st.K.dtype)
    dR = jnp.zeros(st.reaction.shape, st.K.dtype)
    row = 0
    for k, (i, j) in enumerate(flat):
        rows = shafts[i].bearings[j].force_rows()  # the force rows the assembly gave it
        delta = changes.get((i, j))
        if delta is not None:
            delta = jnp.asarray(delta, st.K.dtype)
            a = dofs[i][j]
            node = slice(a, a + 6)
            dK = dK.at[node, node].add(delta)
            dR = dR.at[row:row + len(rows), node].add(delta[jnp.asarray(rows, int)])
            joint = joints.get(f"bearing {k}")
            if joint is not None:  # on a seat: the cross and seat blocks
                _, B, D = mount.blocks(joint, delta)
                o = st.mount_offset + 6 * mount.seat_index(joint)
                seat = slice(o, o + 6)
                dK = dK.at[node, seat].add(B).at[seat, node].add(B.T).at[seat, seat].add(D)
                dR = dR.at[row:row + len(rows), seat].add(B[jnp.asarray(rows, int)])
        row += len(rows)
    parts = st.parts_K
    if parts is not None:
        parts = parts.at[st.part_names.index("bearings")].add(dK)
    structure = eqx.tree_at(lambda s: (s.K, s.parts_K, s.reaction), st,
                            (st.K + dK, parts, st.reaction + dR),
                            is_leaf=lambda x: x is None)
    return _with_structure(scene, structure)


def bearing_forces(scene, res: QuasiStaticResult) -> dict:
    """Mean bearing force (N) per component name over the positions of ``res`` (fixed frame).

    Args:
        scene: the scene ``res`` was solved on (a lumped or hybrid scene with bearings, or one
            :func:`~jaxgear.scenes.grounded` wraps).
        res: its :class:`~jaxgear.QuasiStaticResult`, P positions.

    Returns:
        ``{reaction name: mean force (N)}`` over the P positions, in the scene's
        ``reaction_names`` order.
    """
    base = _bearing_scene(scene)
    F = np.asarray(base.bearing_forces(res.theta, res.x))  # (P, r)
    return dict(zip(base.reaction_names, F.mean(axis=0).tolist()))


#: the fixed point of the bearings' operating points: the largest relative change of a rolling
#: bearing's load between two iterations at which it stops, and the iterations allowed
OPERATING_TOLERANCE = 1e-6
OPERATING_ITERATIONS = 30
#: the linear spring a rolling bearing stands on for the first solve (N/m on the radial and, where
#: the kind carries it, the axial DOFs; no tilt, each shaft statically determinate, but on a
#: shaft whose radial bearings stand at one position: there a kind that carries a moment
#: takes the radial spring times its lever squared, N·m/rad, :func:`_start_springs`)
START_SPRING = (2e8, 1e8)


class OperatingPoint(NamedTuple):
    """The rolling bearings of a scene at their operating point
    (:func:`bearings_at_operating_point`).

    Attributes:
        shafts: the :class:`~jaxgear.scenes.ShaftSpec` of each shaft, each rolling bearing at
            its operating point (:meth:`~jaxgear.scenes.Bearing.at`), the others as given.
        loads: per shaft, per bearing, the load f = (F_x, F_y, F_z, M_x, M_y) (N, N·m) a
            rolling bearing carries (the shaft's push on it, fixed frame; ``None`` for a linear
            bearing), the mean over the quasi-static positions.
        states: per shaft, per bearing, the rolling bearing's
            :class:`~jaxgear.bearings.BearingState` at that load (``None`` for a linear one).
        iterations: quasi-static solves made (the last one confirming the fixed point).
        change: the last iteration's largest change of a rolling bearing's load, relative to
            that load (forces, and moments over the pitch radius), <= the tolerance.
    """

    shafts: tuple
    loads: tuple
    states: tuple
    iterations: int
    change: float


@eqx.filter_jit
def _load(rolling, d):
    """A rolling bearing's load f(d) (N, N·m), (5,), compiled once per kind and count."""
    return rolling.load(d)


def _start(b: Bearing, tilt: bool) -> Bearing:
    """The linear spring a rolling bearing without an operating point stands on first: with
    ``tilt``, a kind that carries a moment (:meth:`~jaxgear.scenes.Bearing.holds_tilt`) on
    the radial spring times its lever squared too."""
    if b.rolling is None or b.operating is not None:
        return b
    c = b.carried()
    radial, axial = START_SPRING
    k_t = radial * _lever(b.rolling) ** 2 if tilt and b.holds_tilt() else 0.0
    return Bearing(b.z, radial=radial, axial=axial if c[2] else 0.0, tilt=k_t,
                   damping=b.damping)


def _start_springs(shaft) -> list:
    """A shaft's bearings for the first solve (:func:`_start`), statically determinate: the
    rolling ones on radial springs, and where its radial bearings stand at one position (a
    shaft held by one bearing that carries a moment, an overhung pinion on a tapered pair)
    those that carry a moment on a tilt spring too (without it the shaft would tilt freely)."""
    radial = {b.z for b in shaft.bearings if all(b.carried()[:2])}
    return [_start(b, len(radial) < 2) for b in shaft.bearings]


def _lever(rolling) -> float:
    """The lever (m) that turns a bearing's moments into forces of its size: its pitch radius
    (1 m for a kind without rolling elements)."""
    return 0.5 * float(rolling.pitch_diameter) if rolling.rolling_elements else 1.0


def bearings_at_operating_point(
    build,
    shafts,
    modifications,
    torque,
    *,
    hold=None,
    extra_z=None,
    contact: ContactLaw = ExactContact(),
    positions_per_pitch: int = 64,
    tolerance: float = OPERATING_TOLERANCE,
    max_iterations: int = OPERATING_ITERATIONS,
) -> OperatingPoint:
    """Each rolling bearing of ``shafts`` at the operating point the quasi-static solve of its
    scene at ``torque`` gives it, iterated to a fixed point.

    A rolling bearing (:class:`~jaxgear.scenes.Bearing` with ``rolling``) stands on a linear
    spring first (:data:`START_SPRING`, no tilt stiffness: a shaft on two of them is
    statically determinate, its bearings' loads statics'; a shaft held at one position by a
    bearing that carries a moment, a tapered roller pair, stands on its tilt spring too, a
    cantilever, statically determinate as well). Each iteration builds the scene on
    each rolling bearing's tangent stiffness K_b at its current ring displacement d_b
    (:meth:`~jaxgear.scenes.Bearing.at`), the bearing's force on the shaft the affine
    −f(d_b) − K_b (u − d_b) (the constant part an external force K_b d_b − f(d_b) at its
    node), solves it quasi-statically (:func:`~jaxgear.quasi_static`, exact contact by default,
    one mesh period), takes the mean over the positions of the load the shaft puts on each
    rolling bearing, f(d_b) + K_b (u − d_b) (u its node's u_x … φ_y, fixed frame), solves the
    ring displacement that carries that load (:func:`~jaxgear.bearings.solve_displacement`)
    and moves the bearing there: to first order Newton's step on the nonlinear bearings, so
    that at the fixed point u = d_b and each bearing carries f(d_b), the shafts' equilibrium
    with the nonlinear bearings. The bearings' stiffness moves their loads only through what
    makes a shaft statically indeterminate (the bearings' axial, tilt and cross stiffness, two
    bearings sharing an axial load, three bearings on a shaft, the mesh's load over the face);
    it stops when no load changes by more than ``tolerance`` of itself (forces, and moments
    over the bearing's pitch radius) from one iteration to the next. Not differentiable
    through the iteration (NumPy); a bearing's stiffness at a given load is, through
    :func:`~jaxgear.bearings.solve_displacement`'s implicit derivative.

    Args:
        build: ``shafts ↦ scene``: the scene on the given shafts in their order,
            block-diagonally (:func:`~jaxgear.scenes.lumped_pair`,
            :meth:`~jaxgear.scenes.LumpedTrain.of`), with its external load per unit torque
            ``f_torque`` (its bearings on the ground).
        hold: ``scene ↦ DOFs`` the quasi-static solve holds (:func:`jaxgear.scenes.grounded`:
            the load's rotation, as a case's solve holds it), or None: none.
        shafts: the scene's :class:`~jaxgear.scenes.ShaftSpec` in its order.
        modifications, torque: the flank modifications and the pinion torque (N·m) of the
            solve (:func:`~jaxgear.quasi_static`'s).
        extra_z: the scene's more node positions per shaft (m; a train's wrenches), or None.
        contact, positions_per_pitch: the quasi-static solve's contact law and positions.
        tolerance: the relative change at which it stops (> 0). max_iterations: int >= 2.

    Returns:
        :class:`OperatingPoint`; without a rolling bearing, the shafts unchanged after no solve.

    Raises:
        ValueError: a load a rolling bearing cannot carry (a single-row angular contact or
            tapered bearing without its axial load, ...: :func:`solve_displacement`'s line,
            prefixed by the bearing's position), a bearing without stiffness at its operating
            point (clearance and no load), a solve that does not converge, or no fixed point in
            ``max_iterations`` (the last change and the tolerance in the line).
    """
    check_real("tolerance", tolerance, "", lo=0.0, lo_open=True, hi=1.0,
               where="bearings_at_operating_point")
    check_integer("bearings_at_operating_point: max_iterations", max_iterations, 2)
    shafts = tuple(shafts)
    rolling = [[b.rolling is not None for b in s.bearings] for s in shafts]
    none = tuple(tuple(None for _ in s.bearings) for s in shafts)
    if not any(map(any, rolling)):
        return OperatingPoint(shafts, none, none, 0, 0.0)
    dofs = bearing_dofs(shafts, extra_z)
    current = [_start_springs(s) for s in shafts]
    previous, change = None, math.inf
    T = float(torque)
    for iteration in range(1, int(max_iterations) + 1):
        specs = tuple(dataclasses.replace(s, bearings=tuple(bs))
                      for s, bs in zip(shafts, current, strict=True))
        scene = build(specs)
        bias = np.zeros(np.shape(scene.f_torque))
        for i, s in enumerate(shafts):
            for j, b in enumerate(current[i]):
                if rolling[i][j] and b.rolling is not None:  # K_b d_b − f(d_b) at its node
                    d = np.asarray(b.operating)
                    f = np.asarray(_load(b.rolling, d), float)
                    bias[dofs[i][j] : dofs[i][j] + 5] += b.stiffness_matrix()[:5, :5] @ d - f
        scene = eqx.tree_at(lambda sc: sc.f_torque, scene, scene.f_torque + bias / T)
        if hold is not None:
            scene = grounded(scene, hold(scene))
        res = quasi_static(scene, modifications, torque, contact=contact,
                           positions_per_pitch=positions_per_pitch)
        u = np.asarray(res.x).mean(axis=0)
        loads, states, updated, scaled = [], [], [], []
        for i, s in enumerate(shafts):
            row_l, row_s, row_b = [], [], []
            for j, b in enumerate(s.bearings):
                if not rolling[i][j]:
                    row_l.append(None), row_s.append(None), row_b.append(b)
                    continue
                k, now = dofs[i][j], current[i][j]
                f = now.stiffness_matrix()[:5] @ u[k : k + 6]
                if now.rolling is not None:  # f(d_b) + K_b (u − d_b)
                    d = np.asarray(now.operating)
                    f = f + np.asarray(_load(now.rolling, d), float) - now.stiffness_matrix()[
                        :5, :5] @ d
                f = np.where(b.rolling.carried(), f, 0.0)  # round-off on a free DOF
                try:
                    state = solve_displacement(b.rolling, f)
                except ValueError as err:
                    raise ValueError(f"{b.where}: {err}") from None
                if not float(state.residual) < 1e-6:
                    raise ValueError(
                        f"{b.where}: the displacement that carries the load {_shown(f)} did "
                        f"not converge (residual {float(state.residual):.3g}, allowed < 1e-6)")
                at = b.at(state.displacement)
                kd = np.diag(at.stiffness_matrix())
                if b.rolling.rolling_elements and not (kd[0] > 0 and kd[1] > 0):
                    raise ValueError(
                        f"{b.where}: no radial stiffness at its operating point (load "
                        f"{_shown(f)}): a bearing with clearance and no load; allowed a "
                        "loaded bearing or a preload (clearance < 0)")
                r = _lever(b.rolling)
                scaled.append(np.concatenate([f[:3], f[3:] / r]))
                row_l.append(f), row_s.append(state), row_b.append(at)
            loads.append(tuple(row_l)), states.append(tuple(row_s)), updated.append(row_b)
        if previous is not None:
            change = max(float(np.max(np.abs(a - p)) / max(np.max(np.abs(a)), 1e-30))
                         for a, p in zip(scaled, previous, strict=True))
        current, previous = updated, scaled
        if change <= tolerance:
            specs = tuple(dataclasses.replace(s, bearings=tuple(bs))
                          for s, bs in zip(shafts, current, strict=True))
            return OperatingPoint(specs, tuple(loads), tuple(states), iteration, change)
    raise ValueError(
        f"bearings_at_operating_point: the rolling bearings' loads did not settle in "
        f"{max_iterations} quasi-static solves (last relative change {change:.3g}, allowed "
        f"<= tolerance = {tolerance:g})"
    )


def _shown(f) -> str:
    """A load (5,) in a message: (F_x, F_y, F_z) N, (M_x, M_y) N·m."""
    f = np.asarray(f, float)
    return (f"F = ({f[0]:.4g}, {f[1]:.4g}, {f[2]:.4g}) N, M = ({f[3]:.4g}, {f[4]:.4g}) N·m")


def operating_lives(point: OperatingPoint, speeds, *, viscosity=None, reliability=0.9,
                    contamination=None) -> tuple:
    """Each rolling bearing's lives at the operating point ``point``
    (:func:`bearings_at_operating_point`): :func:`jaxgear.bearings.operating_life` of its load
    and displacement there at its shaft's speed, the inner ring turning.

    Args:
        point: the :class:`OperatingPoint` of a scene's shafts.
        speeds: each shaft's speed (rad/s, > 0; its magnitude: the inner ring's relative to
            the outer), one per shaft of ``point``, or None (the lives in revolutions only).
        viscosity, reliability, contamination: ISO 281's modified life
            (:func:`jaxgear.bearings.modified_life`); ``contamination`` None: no L_nm.

    Returns:
        Per shaft, per bearing, its :class:`~jaxgear.bearings.OperatingLife`, or None for a
        linear bearing and a rolling one without ``dynamic_rating``.

    Raises:
        ValueError: ``speeds`` not one per shaft; what :func:`~jaxgear.bearings.operating_life`
            refuses (one line).
    """
    if speeds is not None and len(speeds) != len(point.shafts):
        raise ValueError(f"operating_lives: speeds has {len(speeds)} entries: allowed one per "
                         f"shaft ({len(point.shafts)})")
    out = []
    for k, (shaft, loads, states) in enumerate(zip(point.shafts, point.loads, point.states,
                                                   strict=True)):
        row = []
        for b, f, state in zip(shaft.bearings, loads, states, strict=True):
            if b.rolling is None or f is None or b.rolling.dynamic_rating is None:
                row.append(None)
                continue
            row.append(operating_life(
                b.rolling, np.asarray(f, float), np.asarray(state.displacement, float),
                None if speeds is None else abs(float(speeds[k])), viscosity=viscosity,
                reliability=reliability, contamination=contamination))
        out.append(tuple(row))
    return tuple(out)


class SpectrumLife(NamedTuple):
    """A rolling bearing's life under a load spectrum (:func:`spectrum_lives`): ``spectrum``
    its :class:`~jaxgear.bearings.BearingSpectrum` (each bin's F_r, F_a, shaft speed and time),
    ``basic`` ISO 281's :class:`~jaxgear.bearings.BearingLife` by Palmgren–Miner,
    ``modified`` its :class:`~jaxgear.bearings.ModifiedLife` (None without the settings) and
    ``reference`` ISO/TS 16281's reference life of each bin's element loads (balls, or the
    rollers' laminae) by Palmgren–Miner (:func:`~jaxgear.bearings.spectrum_reference_life`, a
    :class:`~jaxgear.bearings.BearingLife` whose load is P_ref)."""

    spectrum: BearingSpectrum
    basic: BearingLife
    modified: ModifiedLife | None
    reference: BearingLife | None = None


def spectrum_lives(points, speeds, durations, *, viscosity=None, reliability=0.9,
                   contamination=None) -> tuple:
    """Each rolling bearing's life under a load spectrum of k bins, each bin's loads those of
    its operating point (:func:`bearings_at_operating_point` at the bin's torque): ISO 281's
    :func:`~jaxgear.bearings.spectrum_life` and, with ``contamination``,
    :func:`~jaxgear.bearings.spectrum_modified_life` of the bins' F_r = √(F_x² + F_y²) and
    F_a = F_z, and ISO/TS 16281's
    :func:`~jaxgear.bearings.spectrum_reference_life` of the bins' ring displacements.

    Args:
        points: (k,) the bins' :class:`OperatingPoint` (the same shafts and bearings), None
            for an unloaded bin (no torque: no load, no damage).
        speeds: (k, n) each bin's speed of each of the n shafts (rad/s, magnitudes).
        durations: (k,) the time run in each bin (s).
        viscosity, reliability, contamination: as :func:`operating_lives`.

    Returns:
        Per shaft, per bearing, its :class:`SpectrumLife`, or None (a linear bearing, a rolling
        one without ``dynamic_rating``).

    Raises:
        ValueError: no loaded bin; ``speeds`` or ``durations`` not shaped by the bins; what
            the bearing package refuses (one line).
    """
    loaded = [p for p in points if p is not None]
    if not loaded:
        raise ValueError("spectrum_lives: points has no loaded bin: allowed at least one "
                         "OperatingPoint")
    k, ref = len(points), loaded[0]
    speeds, durations = np.asarray(speeds, float), np.asarray(durations, float)
    if speeds.shape != (k, len(ref.shafts)) or durations.shape != (k,):
        raise ValueError(f"spectrum_lives: speeds {speeds.shape} and durations "
                         f"{durations.shape}: allowed ({k}, {len(ref.shafts)}) and ({k},)")
    out = []
    for s, shaft in enumerate(ref.shafts):
        row = []
        for i, b in enumerate(shaft.bearings):
            if b.rolling is None or b.rolling.dynamic_rating is None:
                row.append(None)
                continue
            f = np.array([np.zeros(5) if p is None else np.asarray(p.loads[s][i], float)
                          for p in points])
            spectrum = BearingSpectrum(np.hypot(f[:, 0], f[:, 1]), f[:, 2], speeds[:, s],
                                       durations)
            modified = None
            if contamination is not None:
                modified = spectrum_modified_life(b.rolling, spectrum, viscosity=viscosity,
                                                  reliability=reliability,
                                                  contamination=contamination)
            d = np.array([np.zeros(5) if p is None
                          else np.asarray(p.states[s][i].displacement, float)
                          for p in points])
            reference = spectrum_reference_life(b.rolling, d, speeds[:, s], durations)
            row.append(SpectrumLife(spectrum, spectrum_life(b.rolling, spectrum), modified,
                                    reference))
        out.append(tuple(row))
    return tuple(out)
