"""A gearbox of stages in series as one torsional lumped model: each stage's torsional model (a
planetary stage's :class:`~jaxgear.planetary.TorsionalPlanetary`, a parallel pair's two rotations
joined by its mesh) in absolute rotations, the stages joined by the torsional stiffnesses of the
shafts that carry one stage's output member to the next stage's input member.

Coordinates: one rotation theta (rad) per member, every rotation positive in the same sense
about the common axis direction (a parallel pair's wheel and pinion included); M in kg m^2,
K in N m/rad. A planetary stage's model is :class:`~jaxgear.planetary.TorsionalPlanetary`'s, whose
coordinates are u = r theta (m) with r the member's ``base_radius`` (the carrier's: the planet
circle), so that its blocks here are R M R and R K R, R = diag(r). A parallel pair's mesh
deflection along its line of action is r_b1 theta_1 + r_b2 theta_2 (the two gears turn in
opposite senses), its mesh stiffness k: K = k [r_b1 r_b1, r_b1 r_b2; r_b1 r_b2, r_b2 r_b2].
A shaft of torsional stiffness k_t between coordinates i and j adds k_t (theta_i - theta_j)^2 / 2
to the strain energy.
"""

from __future__ import annotations

import warnings

import equinox as eqx
import jax
import jax.numpy as jnp
import jax.scipy.linalg
import numpy as np
from jaxtyping import Array, Float

from .._baseplane import CellRow, MeshModel
from .._modifications import Modifications
from .._util import as_float, check_instance
from ..dynamics import AbstractStage, DynamicModel, matrix_modal_analysis, mean_cell_stiffness
from ..planetary import (
    AbstractPlanetaryMeshes,
    AbstractPlanetaryModel,
    Central,
    ConstantMeshes,
    PlanetaryModel,
    PlanetaryRun,
    PlanetaryStage,
    TorsionalPlanetary,
)
from ..scenes import Housing, TorsionalDynamics

__all__ = [
    "GearboxModes",
    "GearboxTorsional",
    "PairGearboxStage",
    "PlanetaryGearboxStage",
    "TorsionalPairGearboxStage",
    "gearbox_modes",
]


class PlanetaryGearboxStage(PlanetaryModel):
    """A planetary stage in the chain: the :class:`~jaxgear.planetary.PlanetaryModel` of
    ``stage`` with ``input``/``output`` the central members (:class:`~jaxgear.planetary.Central`)
    the shafts join, the third held by its ``torsional_stiffness`` in ``stage`` (a thin
    constructor of the gearbox's argument order: the model is the stage,
    :class:`jaxgear.dynamics.AbstractStage`, and the same object runs alone through
    :func:`jaxgear.dynamics.simulate`). The torsional chain's view is
    :class:`~jaxgear.planetary.TorsionalPlanetary`'s (Kahraman 1994: rotations of carrier,
    ring, sun and the N planets).

    Args:
        stage: the :class:`~jaxgear.planetary.PlanetaryStage`.
        input, output: two different central members.
        meshes: the stage's meshes (:class:`~jaxgear.planetary.ContactMeshes`, ...); None:
            :class:`~jaxgear.planetary.ConstantMeshes` (constant springs, no contact cells).
        model: the planetary model kind (None: :class:`~jaxgear.planetary.TorsionalPlanetary`;
            :class:`~jaxgear.planetary.PlanarPlanetary`). Read back as :attr:`model` (the
            model's ``kind``).
        run: a :class:`~jaxgear.planetary.PlanetaryRun` (its pin errors); None: no pin errors.
        mount: a :class:`~jaxgear.scenes.HousingMount` (keyword; None: the stage on the
            ground): the stage on a condensed housing, its held member's torsional support
            (about the stage axis) joining a seat instead of the ground through the mount's
            seat coupling (:class:`~jaxgear.planetary.PlanetaryModel` ``mount=``); the
            housing's coordinates end :meth:`coordinates`, so that a gearbox-level
            :attr:`GearboxTorsional.housing` shares them with the other housed stages,
            docs/gearbox.md, "A planetary stage in the shared housing"; its damping C_h rides
            in :meth:`speed_terms`, as a lumped stage's does.

    Raises:
        ValueError: ``input`` = ``output``; ``meshes`` or ``model`` of another kind, or a model
            without contact cells; a mount that joins every support (the carrier held) whose
            carrier is the input or output member (it turns) (one line each).
    """

    def __init__(self, stage: PlanetaryStage, input: Central, output: Central,
                 meshes: AbstractPlanetaryMeshes | None = None,
                 model: AbstractPlanetaryModel | None = None,
                 run: PlanetaryRun | None = None, *, mount=None):
        if input == output:  # before Willis' relation, which has no solution then
            raise ValueError(f"PlanetaryGearboxStage: input = output = {input!r}: allowed "
                             "two different central members")
        super().__init__(TorsionalPlanetary() if model is None else model, stage,
                         ConstantMeshes() if meshes is None else meshes,
                         PlanetaryRun(0.0) if run is None else run, input=input, output=output,
                         mount=mount)

    def __check_init__(self):
        where = "PlanetaryGearboxStage"
        check_instance("meshes", self.meshes, AbstractPlanetaryMeshes,
                       "a planetary meshes kind (ContactMeshes, ConstantMeshes)", where)
        check_instance("model", self.kind, AbstractPlanetaryModel,
                       "a planetary model kind (TorsionalPlanetary, PlanarPlanetary)", where)
        self.check_stage(where)

    @property
    def model(self) -> AbstractPlanetaryModel:
        """The planetary model kind (the model's ``kind``)."""
        return self.kind


class _PairStageMeta(type(AbstractStage)):
    """Deprecated form, kept for a release: ``PairGearboxStage(...)`` with a ``mesh`` builds
    the pair's dynamic model (:class:`TorsionalPairGearboxStage`, with a DeprecationWarning
    naming it); without one, the constant-spring stage."""

    def __call__(cls, *args, **kwargs):
        mesh = kwargs.get("mesh", args[4] if len(args) > 4 else None)
        if cls is PairGearboxStage and mesh is not None:
            warnings.warn(
                "PairGearboxStage(..., mesh=) is deprecated: use "
                "jaxgear.gearbox.TorsionalPairGearboxStage(...) (the same arguments), the "
                "pair's dynamic model", DeprecationWarning, stacklevel=2)
            return TorsionalPairGearboxStage(*args, **kwargs)
        return super().__call__(*args, **kwargs)


def _check_side(input, where: str) -> int:
    if isinstance(input, bool) or input not in (0, 1):
        raise ValueError(f"{where}: input = {input!r}: out of range, allowed 0 (pinion), "
                         "1 (wheel)")
    return int(input)


class PairGearboxStage(AbstractStage, metaclass=_PairStageMeta):
    """A parallel pair in the chain as constant springs: pinion and wheel rotations (rad,
    both positive in one sense), their polar inertias (kg m^2, shape (2,)), base radii (m,
    shape (2,)) and the mean mesh stiffness along the line of action (N/m), one cell of unit
    length in the coupled model (no contact cells: it sets no time scale); ``input``: 0 when the
    pinion is driven by the previous stage, 1 the wheel (the other gear is the output).

    Given a ``mesh`` (:class:`~jaxgear.MeshModel`, drive flanks only) and its
    ``modifications``, the constructor builds the pair's own dynamic model on its contact cells
    instead, :class:`TorsionalPairGearboxStage` (a :class:`~jaxgear.dynamics.DynamicModel`;
    not an instance of this class); ``modifications`` without a mesh have no effect.

    Raises:
        ValueError: ``input`` not 0 or 1 (one line).
    """

    inertias: Float[Array, " 2"] = eqx.field(converter=as_float)
    base_radii: Float[Array, " 2"] = eqx.field(converter=as_float)
    mesh_stiffness: Float[Array, ""] = eqx.field(converter=as_float)
    input: int = eqx.field(static=True, default=1)

    def __init__(self, inertias, base_radii, mesh_stiffness, input: int = 1,
                 mesh: MeshModel | None = None, modifications: Modifications | None = None):
        del mesh, modifications  # a meshed pair is built by the metaclass; none here
        self.inertias, self.base_radii, self.mesh_stiffness = inertias, base_radii, mesh_stiffness
        self.input = _check_side(input, "PairGearboxStage")

    # -- the coupled model: its constant spring ``mesh_stiffness``, one cell of unit length,
    # on the deflection r_b1 theta_1 + r_b2 theta_2
    def dynamic_parts(self, positions):
        m, _ = self.matrices()
        k_mean = mean_cell_stiffness(self.cell_row, self.mesh_period(), positions)
        z = jnp.zeros_like(m)
        return m, z, k_mean, jnp.zeros(2, m.dtype)

    def cell_row(self, x):
        r = self.base_radii
        one = jnp.ones((1,), r.dtype)
        return CellRow(None, r[None, :], self.mesh_stiffness * one, one, 0.0 * one,
                       jnp.ones((1,), bool))

    def mesh_forces(self, forces):
        return 1.0 * jnp.sum(forces, axis=-1, keepdims=True)

    def mesh_names(self):
        return ("pair",)

    def mesh_period(self):
        return jnp.asarray(0.01, self.base_radii.dtype)  # sets no time scale (no cells)

    def excited(self):
        return False

    def kinematics(self, input_speed, input_torque):
        r_in, r_out = self.base_radii[self.input], self.base_radii[1 - self.input]
        w = as_float(input_speed)
        torque = jnp.abs(as_float(input_torque))
        return (-w * r_in / r_out, torque * r_out / r_in, r_in * jnp.abs(w),
                jnp.reshape(torque / r_in, (1,)))

    def dof_names(self):
        return ("theta_pinion", "theta_wheel")

    def matrices(self):
        r = self.base_radii
        return jnp.diag(self.inertias), self.mesh_stiffness * jnp.outer(r, r)

    def ends(self):
        return self.input, 1 - self.input


class TorsionalPairGearboxStage(DynamicModel):
    """A parallel pair on its contact cells in the chain: the pair's own
    :class:`~jaxgear.dynamics.DynamicModel` of the torsional scene
    :class:`~jaxgear.scenes.TorsionalDynamics` ``(mesh, *inertias)`` (pinion and wheel
    rotations, the wheel's counted in the pinion's sense in the gearbox; the scene's cell rows,
    beyond the path less their part along the pair's free drive rotation, as the pair alone
    and a lumped stage take them), built for a gearbox only
    (:func:`~jaxgear.dynamics.stage_model`: no operating torque, modes or damping), in
    :class:`PairGearboxStage`'s argument order (what ``PairGearboxStage(..., mesh=)`` builds).
    Its torsional chain's view (:meth:`matrices`) keeps the given constant spring
    ``mesh_stiffness`` on the given ``base_radii`` (a case's estimate of the mean mesh
    stiffness, not the cells' mean); everything else is the model's.

    Args:
        inertias: polar inertias (kg m^2, (2,)). base_radii: the chain view's base radii (m,
            (2,)). mesh_stiffness: the chain view's mean mesh stiffness (N/m).
        input: 0 when the pinion is driven by the previous stage, 1 the wheel.
        mesh: the :class:`~jaxgear.MeshModel` (drive flanks only).
        modifications: the pair's flank modifications (None: none).

    Raises:
        ValueError: ``mesh`` not a mesh model, one with coast flanks; ``input`` not 0 or 1;
            ``modifications`` not a :class:`~jaxgear.Modifications`; an inertia not > 0 (one
            line each).
    """

    base_radii: Float[Array, " 2"]
    mesh_stiffness: Float[Array, ""]

    def __init__(self, inertias, base_radii, mesh_stiffness, input: int = 1,
                 mesh: MeshModel | None = None, modifications: Modifications | None = None):
        where = "PairGearboxStage"
        check_instance("mesh", mesh, MeshModel, "a jaxgear.MeshModel", where)
        mods = Modifications() if modifications is None else modifications
        check_instance("modifications", mods, Modifications, "a jaxgear.Modifications", where)
        inertias = as_float(inertias)
        # the model of stage_model: no torque, damping, modes or mean stiffness (a stage's)
        super().__init__(TorsionalDynamics(mesh, inertias[0], inertias[1]), mods, None, None,
                         None, None, input=_check_side(input, where))
        self.base_radii, self.mesh_stiffness = as_float(base_radii), as_float(mesh_stiffness)

    def __check_init__(self):
        self.check_stage("PairGearboxStage")

    @property
    def inertias(self) -> Float[Array, " 2"]:
        """The pinion's and wheel's polar inertias (kg m^2, (2,))."""
        return jnp.diag(self.scene.mass())

    @property
    def modifications(self) -> Modifications:
        """The pair's flank modifications (the model's ``mods``)."""
        return self.mods

    def matrices(self):
        """(M, K): diag(inertias), ``mesh_stiffness`` r rᵀ on ``base_radii`` (kg m^2,
        N m/rad)."""
        r = self.base_radii
        return jnp.diag(self.inertias), self.mesh_stiffness * jnp.outer(r, r)


class GearboxTorsional(eqx.Module):
    """Stages in series (each a :class:`jaxgear.dynamics.AbstractStage`: a
    :class:`PairGearboxStage`, a :class:`~jaxgear.planetary.PlanetaryModel` given its input and
    output members or its :class:`PlanetaryGearboxStage` constructor, a
    :class:`~jaxgear.gearbox.CompoundPlanetaryStage`, a
    :class:`~jaxgear.gearbox.LumpedPairGearboxStage`), stage k's output member joined to stage
    k+1's input member by a shaft of torsional stiffness ``shaft_stiffnesses[k]`` (N m/rad,
    shape (n_stages - 1,)). The chain's coordinates are the stages' in order.

    ``housing``: one flexible :class:`~jaxgear.scenes.Housing` that the stages share
    (docs/gearbox.md, "One housing for several stages"), or None: placed once, in the gearbox
    frame, every housed stage's :meth:`~jaxgear.dynamics.AbstractStage.mount` holding this one
    object (``stage.mount().housing is housing``), the stages' axes parallel to the gearbox
    frame's and each stage at its place t there. A stage that sits in it is a
    :class:`~jaxgear.gearbox.LumpedPairGearboxStage` (or a pair's
    :class:`~jaxgear.dynamics.DynamicModel`) whose scene was built on it
    (``lumped_pair(..., housing=, seats=, housing_position=t)``): its bearings are joined to
    its seats by the scenes' one seat coupling; or a planetary stage
    (:class:`PlanetaryGearboxStage`, :class:`~jaxgear.planetary.PlanetaryModel`) given a
    ``mount=`` on it (``HousingMount.on_axis(housing, seats, centre=t)``, the stage axis the
    gearbox's +z through t): its held member's torsional support joined to its seat by the
    same coupling. The coupled model (:func:`gearbox_coupled_modes`, :func:`gearbox_dynamics`,
    :func:`gearbox_whine`) then keeps the housing's coordinates once, after every stage's own,
    and its K_h, M_h and damping C_h once. Stages without a housing (torsional, an unhoused
    planetary model, a grounded lumped stage) stay on the ground. The torsional chain's view
    (:meth:`matrices`, :func:`gearbox_modes`) does not take a shared housing. Deprecated: a
    stage mounted on its own copy of the housing placed in the stage's frame (the form before
    the housing was placed once) stands where the copy's K_h and M_h are ``housing``'s, with a
    DeprecationWarning (a seat's lever depends on p − c alone: the same coupling to
    round-off).

    Raises:
        ValueError: no stages; a stage not an :class:`~jaxgear.dynamics.AbstractStage`, or one
            that refuses to stand in a gearbox (:meth:`~jaxgear.dynamics.AbstractStage.
            check_stage`: a planetary model without its input and output members, ...);
            ``shaft_stiffnesses`` of another shape; ``housing`` not a
            :class:`~jaxgear.scenes.Housing`, held by no stage's mount, or a stage mounted on
            another housing (its size, stiffness or mass differ); a seat a stage's member holds
            alone (:attr:`~jaxgear.scenes.MountJoint.own_seat`: a planetary member's) that
            another stage joins too (one line each).
    """

    stages: tuple[AbstractStage, ...]
    shaft_stiffnesses: Float[Array, " n_shafts"] = eqx.field(converter=as_float)
    housing: Housing | None = None

    def __check_init__(self):
        if len(self.stages) < 1:
            raise ValueError("stages: empty, allowed at least one stage")
        for k, stage in enumerate(self.stages):
            check_instance(f"stages[{k}]", stage, AbstractStage,
                           "a gearbox stage (a jaxgear.dynamics.AbstractStage: PairGearboxStage, "
                           "PlanetaryModel, CompoundPlanetaryStage, LumpedPairGearboxStage)",
                           "GearboxTorsional")
            stage.check_stage(f"GearboxTorsional: stages[{k}]")
        if self.shaft_stiffnesses.shape != (len(self.stages) - 1,):
            raise ValueError(
                f"shaft_stiffnesses: shape {self.shaft_stiffnesses.shape}, allowed "
                f"({len(self.stages) - 1},) (one per pair of consecutive stages)"
            )
        if self.housing is not None:
            _check_housing(self.stages, self.housing)

    def offsets(self) -> tuple[int, ...]:
        """Where each stage's rotations start in the chain's coordinates."""
        out, n = [], 0
        for s in self.stages:
            out.append(n)
            n += len(s.dof_names())
        return tuple(out)

    def dof_names(self) -> tuple[str, ...]:
        """``"<k>:<name>"`` per coordinate, k the stage's index from 1."""
        return tuple(f"{k + 1}:{n}" for k, s in enumerate(self.stages) for n in s.dof_names())

    def stage_of_dof(self) -> tuple[int, ...]:
        """Each coordinate's stage index (from 0)."""
        return tuple(k for k, s in enumerate(self.stages) for _ in s.dof_names())

    @eqx.filter_jit
    def matrices(self) -> tuple[Float[Array, "n n"], Float[Array, "n n"]]:
        """(M, K) of the chain: kg m^2, N m/rad."""
        blocks = [s.matrices() for s in self.stages]
        mass = jax.scipy.linalg.block_diag(*[m for m, _ in blocks])
        stiff = jax.scipy.linalg.block_diag(*[k for _, k in blocks])
        # the shafts: twist b theta, b = e_out(k) - e_in(k + 1), strain energy k_t (b theta)^2 / 2
        offsets = self.offsets()
        b = np.zeros((len(self.stages) - 1, mass.shape[0]))
        for j in range(len(self.stages) - 1):
            b[j, offsets[j] + self.stages[j].ends()[1]] = 1.0
            b[j, offsets[j + 1] + self.stages[j + 1].ends()[0]] = -1.0
        b = jnp.asarray(b, dtype=mass.dtype)
        stiff = stiff + b.T @ (self.shaft_stiffnesses[:, None] * b)
        return mass, stiff


def _check_housing(stages, housing):
    """Find ``housing`` as the one object its housed stages' mounts hold
    (``stage.mount().housing is housing``); refuse one that no stage's mount holds, a stage
    mounted on another housing, and a seat one stage's member holds alone
    (:attr:`~jaxgear.scenes.MountJoint.own_seat`) that another stage joins too (one line each).
    A stage mounted on its own copy of the housing (placed one by one, in the stage's frame) is
    deprecated: it stands where the copy's K_h and M_h are this housing's (compared where the
    arrays are concrete), with a DeprecationWarning."""
    check_instance("housing", housing, Housing, "a jaxgear.scenes.Housing or None",
                   "GearboxTorsional")
    mounts = [(k, s.mount()) for k, s in enumerate(stages)]
    mounts = [(k, m) for k, m in mounts if m is not None]
    if not mounts:
        raise ValueError("GearboxTorsional: housing is given but no stage sits in it: allowed "
                         "None, or a LumpedPairGearboxStage whose scene is built with "
                         "housing=, or a planetary stage (PlanetaryModel, PlanetaryGearboxStage) "
                         "given a mount= (torsional stages stay on the ground)")
    h = housing.size
    copies = []
    for k, mount in mounts:
        own = mount.housing
        if own is housing:
            continue
        if own.size != h:
            raise ValueError(f"GearboxTorsional: housing has {h} coordinates, stage {k + 1}'s "
                             f"mount's housing {own.size}: allowed the one housing object its "
                             "stages' mounts hold")
        concrete = not any(isinstance(a, jax.core.Tracer)
                           for a in (own.K, own.M, housing.K, housing.M))
        if concrete and not all(
                np.allclose(np.asarray(a), np.asarray(b), rtol=1e-12, atol=1e-12 * scale)
                for a, b, scale in ((own.K, housing.K, float(np.abs(housing.K).max())),
                                    (own.M, housing.M, float(np.abs(housing.M).max())))):
            raise ValueError(f"GearboxTorsional: stage {k + 1}'s mount holds another housing "
                             "(its stiffness or mass differs from housing's): allowed the one "
                             "housing object its stages' mounts hold")
        copies.append(k + 1)
    if copies:
        warnings.warn(
            f"GearboxTorsional: stage(s) {', '.join(map(str, copies))} mounted on a copy of "
            "housing placed in the stage's own frame is deprecated: place the housing once in "
            "the gearbox frame and mount every stage on that one object (lumped_pair(..., "
            "housing=, housing_position=t), HousingMount.on_axis(housing, seats, centre=t), t "
            "the stage's place)", DeprecationWarning, stacklevel=4)
    # a seat a stage's member holds alone (a planetary member bolted to it) is that member's
    for k, mount in mounts:
        for member, seat in mount.own_seats():
            for j, other in enumerate(stages):
                if j != k and seat in other.housing_seats():
                    raise ValueError(
                        f"GearboxTorsional: seat {housing.seat_names[seat]!r} ({seat}) is used "
                        f"twice, by stage {k + 1}'s {member} and by stage {j + 1}: allowed a "
                        "seat of its own for each member bolted to the housing")


class GearboxModes(eqx.Module):
    """The chain's natural modes: ``frequencies`` (Hz, ascending, shape (n,)), ``shapes``
    (rad, (n, n), column j mass-normalised: phi^T M phi = I) and ``stage_energy`` ((n_stages, n):
    each mode's kinetic energy share per stage, columns summing to 1)."""

    frequencies: Float[Array, " n"]
    shapes: Float[Array, "n n"]
    stage_energy: Float[Array, "s n"]


@eqx.filter_jit
def gearbox_modes(chain: GearboxTorsional) -> GearboxModes:
    """The undamped natural modes of the chain, ``K phi = omega^2 M phi``, through
    :func:`jaxgear.dynamics.modal_analysis` (the one modal solve: Cholesky factor of M,
    ``jnp.linalg.eigh``); a free chain (no member held) has one rigid-body mode at 0 Hz.

    Raises:
        ValueError: ``chain`` not a :class:`GearboxTorsional` (one line)."""
    check_instance("chain", chain, GearboxTorsional, "a jaxgear.gearbox.GearboxTorsional",
                   "gearbox_modes")
    if chain.housing is not None:
        raise ValueError("gearbox_modes: chain.housing is set: the torsional chain's view "
                         "condenses each stage alone and cannot share a housing; allowed a "
                         "chain without one (the coupled modes: gearbox_coupled_modes)")

    m, k = chain.matrices()
    modes = matrix_modal_analysis(m, k, jnp.zeros_like(k))
    shapes = modes.shapes
    energy = shapes * (m @ shapes)  # each coordinate's share (M diagonal per stage block)
    owner = np.asarray(chain.stage_of_dof())  # static: the indicator of each stage's rotations
    belongs = jnp.asarray(owner[None, :] == np.arange(len(chain.stages))[:, None], energy.dtype)
    per_stage = belongs @ energy
    per_stage = per_stage / per_stage.sum(axis=0, keepdims=True)
    return GearboxModes(modes.frequency, shapes, per_stage)
