"""The dynamic model of a case: its ``[scene]`` settings turned into a scene and a
:class:`~jaxgear.dynamics.AbstractDynamicModel` (inertias default to solid discs), and the
scene of its quasi-static solve."""

from __future__ import annotations

import fractions
import functools
import math
from typing import Any, NamedTuple

import numpy as np

from fem_prep import schema as sc

from .._contact import ContactLaw, ExactContact
from .._quasi_static import QuasiStaticResult, quasi_static
from ..dynamics import (
    DynamicModel,
    HybridModel,
    OperatingPoint,
    QuasiPeriodicBalance,
    WhineSize,
    bearing_forces,
    check_whine_size,
    dynamic_model,
    group_positions,
    group_rows,
    operating_lives,
    spectrum_lives,
    whine_size,
)
from ..planetary import (
    ConstantMeshes,
    PlanetaryModel,
    PlanetaryRun,
    SpatialPlanetary,
    planetary_model_for,
)
from ..scenes import (
    HousingMount,
    Material,
    TorsionalDynamics,
    grounded,
    hybrid_pair,
    lumped_pair,
)
from ._bearings_table import bearing_life_of, pinion_speed
from ._case import Case, PairForm, TrainForm, _gear_bodies, _inertias
from ._operating import operating_point
from ._planetary_spec import InternalMeshForm, PlanetaryForm
from ._rating_table import ratings_of
from ._scene_spec import SceneSpec, load_bodies, spec_damping
from ._whine_table import WHINE_METHODS, whine_of

__all__ = ["PAIR_SCENES", "CaseBearings", "bearing_spectrum_lives", "build_dynamic_model",
           "case_bearings", "check_case_whine", "dynamic_model_kind",
           "mesh_frequency_periods", "planetary_kind", "quasi_static_scene",
           "static_scene"]


def build_dynamic_model(
    case: Case,
    spec: SceneSpec | None = None,
    *,
    slices: int | None = None,
    bodies: tuple | None = None,
):
    """The dynamic model of a case and its scene (default: ``[scene]``): a
    :class:`~jaxgear.dynamics.DynamicModel`, or a :class:`~jaxgear.dynamics.HybridModel` when
    the scene has condensed bodies (its damping ``[scene.damping]`` and ``rotating_frame``).
    The scene is built by the case's form (:attr:`Case.form`): a pair's
    (:class:`~jaxgear.io.PairForm`) as ``[scene] model`` names it (:data:`PAIR_SCENES`), a
    train's (:class:`~jaxgear.io.TrainForm`) its train (:meth:`Case.dynamic_train`: torsional
    or lumped 3D; with flexible gears :meth:`Case.hybrid_train`, a hybrid model), the input
    torque on its input gear; a planetary stage's (:class:`~jaxgear.io.PlanetaryForm`) a
    :class:`~jaxgear.planetary.PlanetaryModel` of its load-sharing stage, whose speed is the
    input member's and whose response is :class:`~jaxgear.planetary.PlanetaryDynamics`.

    Inertias default to solid discs of the tip radius and the member's face width with the case
    density. ``bodies``: the condensed bodies (pinion, gear) already loaded (default: the
    scene's, built or read from the fem_prep cache; a train's: one per gear). Returns (model,
    spec).
    """
    if spec is None:
        spec = case.scene if case.scene is not None else SceneSpec()
    return _case_model(case.form, case, spec, slices, bodies), spec


@functools.singledispatch
def _case_model(form, case: Case, spec: SceneSpec, slices: int | None, bodies: tuple | None):
    """The dynamic model of a case of ``form`` (:class:`~jaxgear.io.CaseForm`)."""
    raise TypeError(f"no dynamic model for a case of form {type(form).__name__}")


@functools.singledispatch
def dynamic_model_kind(form, case: Case):
    """The :class:`~jaxgear.dynamics.AbstractDynamicModel` kind (the class)
    :func:`build_dynamic_model` builds for a case of ``form``, without building it; None where
    the case has no dynamic model (an internal mesh)."""


@dynamic_model_kind.register
def _(form: PairForm, case: Case):
    return HybridModel if case.scene is not None and case.scene.hybrid else DynamicModel


@dynamic_model_kind.register
def _(form: TrainForm, case: Case):
    return HybridModel if case.flexible else DynamicModel


@dynamic_model_kind.register
def _(form: PlanetaryForm, case: Case):
    return PlanetaryModel


@dynamic_model_kind.register
def _(form: InternalMeshForm, case: Case):
    return None


def _mesh_coordinates(case: Case, kind) -> int:
    """An upper bound of the coordinates the case's meshes span (the whine's balance basis):
    12 per mesh (two 6-DOF nodes) of a lumped 3D or hybrid scene, a planetary stage's 6 per
    member (sun, carrier, ring and planets), else (torsional) one per gear."""
    if kind is PlanetaryModel:
        return 6 * (case.form.spec.n_planets + 3)
    meshes = len(case.pairs)
    if case.scene is not None and (case.scene.lumped or case.scene.hybrid):
        return 12 * meshes
    return meshes + 1 if isinstance(case.form, TrainForm) else 2


def mesh_frequency_periods(case: Case) -> tuple[fractions.Fraction, ...]:
    """Each mesh-frequency group's period in periods of the first mesh, exact, in the order of
    the meshes, from the tooth counts alone (the case's :attr:`~Case.mesh_orders` o_k: mesh
    k's period is o_1 / o_k): what :func:`jaxgear.dynamics.mesh_groups` finds on the model."""
    orders = [fractions.Fraction(o) for o in case.mesh_orders]
    return tuple(dict.fromkeys(orders[0] / o for o in orders))


def check_case_whine(case: Case) -> WhineSize | None:
    """Check a case's ``[whine]`` against its model before any work: the method its model kind
    takes (:attr:`~jaxgear.dynamics.AbstractDynamicModel.whine_methods`), with
    ``"quasi-periodic"`` a ``positions_per_period`` list of one entry per mesh-frequency
    group and each group's period in whole steps >= 4 harmonics + 1
    (:func:`~jaxgear.dynamics.group_rows`), and its size (:func:`~jaxgear.dynamics.whine_size`,
    the mesh coordinates bounded by :func:`_mesh_coordinates`) within
    :func:`~jaxgear.dynamics.check_whine_size`'s limits. Returns the size (None without
    ``[whine]``; the size by the form: :func:`whine_size_of`).

    Raises:
        SchemaError: one line naming the ``[whine]`` key, its value and what is allowed.
    """
    inputs = whine_of(case)
    kind = dynamic_model_kind(case.form, case)
    if inputs is None or kind is None:
        return None
    method = inputs.method
    name = next(k for k, c in WHINE_METHODS.items() if isinstance(method, c))
    if not isinstance(method, kind.whine_methods):
        allowed = ", ".join(f'"{k}"' for k, c in WHINE_METHODS.items() if c in kind.whine_methods)
        what = {PlanetaryModel: "a planetary stage", HybridModel: "condensed gear bodies"}.get(
            kind, "this case's model")
        raise sc.fail("whine", "method", f"not for {what} ({kind.__name__}): allowed {allowed}",
                      name)
    return whine_size_of(case.form, case, inputs, kind)


@functools.singledispatch
def whine_size_of(form, case: Case, inputs, kind) -> WhineSize:
    """The size of a case's ``[whine]`` (``inputs``, :func:`whine_of`'s) on its model ``kind``
    before any work (:func:`check_case_whine`), dispatched on the case's form: a pair's, a
    train's or a planetary stage's from its meshes (here); a gearbox's from its stages
    (:mod:`jaxgear.io._gearbox_file`).

    Raises:
        SchemaError: one line naming the ``[whine]`` key, its value and what is allowed.
    """
    method = inputs.method
    H, P = int(method.harmonics), inputs.positions
    r = _mesh_coordinates(case, kind)
    try:
        if isinstance(method, QuasiPeriodicBalance):
            periods = mesh_frequency_periods(case)
            where = "[whine] positions_per_period"
            if isinstance(P, tuple):
                group_positions(list(P), len(periods), where)
            multiple = math.lcm(*(p.denominator for p in periods))
            rows = group_rows(P, periods, H, multiple, where)
            size = whine_size(len(inputs.speeds), method, math.prod(rows), r, r, len(periods))
        else:
            # a planetary stage (no pairs: its meshes share one mesh frequency) spans one period
            span = case.span_periods if case.pairs else 1
            size = whine_size(len(inputs.speeds), method, P * span, r, r)
        check_whine_size(size, ("[whine] speeds", "harmonics", "positions_per_period"),
                         (len(inputs.speeds), H, P if not isinstance(P, tuple) else list(P)))
    except sc.SchemaError:
        raise
    except ValueError as err:  # the dynamics' one line, in the file's words
        raise sc.SchemaError(str(err)) from None
    return size


@_case_model.register
def _pair_model(form: PairForm, case: Case, spec: SceneSpec, slices, bodies):
    """A pair case's dynamic model: the hybrid scene of its condensed bodies
    (:func:`static_scene`), or the rigid-gear scene ``[scene] model`` names (:data:`PAIR_SCENES`)
    on the case's mesh model."""
    if spec.hybrid:
        scene, _ = static_scene(case, slices=slices, bodies=bodies)
        return dynamic_model(
            scene,
            case.modifications,
            case.torque,
            spec_damping(spec),
            rotating_frame=spec.rotating_frame,
        )
    scene = PAIR_SCENES[spec.model](case, spec, case.mesh_model(slices=slices))
    # the time averages (modal analysis, damping) need a fixed grid: 64 positions per period
    # unless the scene fixes the step
    return dynamic_model(
        scene,
        case.modifications,
        case.torque,
        spec_damping(spec),
        positions_per_pitch=spec.steps_per_period or 64,
    )


@_case_model.register
def _planetary_model(form: PlanetaryForm, case: Case, spec: SceneSpec, slices, bodies):
    """A planetary case's dynamic model: the :class:`~jaxgear.planetary.PlanetaryModel` of its
    load-sharing stage (:meth:`PlanetarySpec.sharing_stage`: the sun loaded by |T_s| (Willis,
    from the input torque) and free in rotation, the ring and the carrier held), its dynamic
    meshes (:meth:`PlanetarySpec.dynamic_meshes`, ``slices`` per contact line, default 1 for a
    spur stage, else the case's), the lumped model kind
    :func:`~jaxgear.planetary.planetary_model_for` picks (a 3D model's constant springs, in
    the lumped form, at its Gauss points across the face), the case's pin errors and ring
    model (``[planetary.ring]``), the damping ratio 0.05, and with a ``[housing]`` the held
    member bolted to its seat ``[planetary] housing_seat`` (the model's ``mount``,
    :func:`planetary_mount`); its speed is the input member's
    (the carrier's and the mesh travel's per input speed from Willis). ``spec`` and
    ``bodies`` are not used (a stage has no ``[scene]``)."""
    p = form.spec
    stage = p.sharing_stage(p.stage(case))
    spur = not case.pairs or float(case.pairs[0].helix_angle) == 0.0
    meshes = p.dynamic_meshes(case, slices or (1 if spur else case.slices))
    kind = planetary_model_for(stage)
    if isinstance(kind, SpatialPlanetary) and not case.pairs:
        meshes = ConstantMeshes(meshes.base_pitch, face_points=kind.face_points)
    run = PlanetaryRun(
        abs(p.torques(case.torque)["sun"]),
        tangential_pin_errors=np.asarray(p.tangential_pin_errors),
        radial_pin_errors=np.asarray(p.radial_pin_errors),
    )
    return PlanetaryModel(
        kind,
        stage,
        meshes,
        run,
        carrier_per_input=p.speeds(1.0)["carrier"],
        mesh_speed_per_input=p.mesh_speed(1.0),
        ring=p.ring_model.dynamic_ring(),
        mount=planetary_mount(case),  # [housing]: the held member bolted to a seat
    )


def planetary_mount(case: Case, where: str = "planetary_mount") -> HousingMount | None:
    """The :class:`~jaxgear.scenes.HousingMount` a planetary case's stage stands on: None
    without a ``[housing]``; with one, the case's housing (:meth:`Case.housing_body`: the box
    round the stage axis) with the held member (``[planetary] fixed``) bolted to the seat
    ``[planetary] housing_seat`` on the stage axis (a held carrier by every support: the
    mount's fixed frame, :meth:`~jaxgear.scenes.HousingMount.on_axis`). The one place a
    planetary case's stage gets its housing: the dynamic model (:func:`build_dynamic_model`,
    ``mount=``) and ``jaxgear run``'s modes, load sharing and Campbell diagram
    (:func:`planetary_kind`) all take theirs from here.

    Raises:
        TypeError: ``case`` not a planetary stage's (its form not a
            :class:`~jaxgear.io.PlanetaryForm`), in one line naming ``where``.
    """
    if not isinstance(case.form, PlanetaryForm):
        raise TypeError(f"{where}: case {case.name!r} is a "
                        f"{type(case.form).__name__} case, allowed a planetary stage's")
    if case.housing is None:
        return None
    held = case.form.spec.fixed.name.lower()
    return HousingMount.on_axis(case.housing_body().housing,
                                ((held, case.form.spec.housing_seat),),
                                fixed_frame=held == "carrier")


def planetary_kind(case: Case, kind):
    """The planetary model kind ``kind`` (:class:`~jaxgear.planetary.TorsionalPlanetary`,
    :class:`~jaxgear.planetary.PlanarPlanetary`, :class:`~jaxgear.planetary.SpatialPlanetary`) as a
    planetary case runs it: unchanged without a ``[housing]``; with one, on the case's mount
    (:func:`planetary_mount`; :meth:`~jaxgear.planetary.AbstractPlanetaryModel.on`), for the
    functional entries (modes, load sharing, Campbell diagram) that take a kind alone.

    Raises:
        TypeError: ``case`` not a planetary stage's (its form not a
            :class:`~jaxgear.io.PlanetaryForm`).
    """
    return kind.on(planetary_mount(case, "planetary_kind"))


#: a planetary stage's refusal of the scene-based static solves (:func:`static_scene`), one
#: line
PLANETARY_NO_SCENE = (
    "[planetary]: no dynamic scene of a planetary stage yet (allowed: jaxgear run, which "
    "writes its lumped models' modes, Campbell diagram and load sharing)"
)


@_case_model.register
def _internal_model(form: InternalMeshForm, case: Case, spec: SceneSpec, slices, bodies):
    raise ValueError(
        "[meshes[0]]: no dynamic scene takes an internal mesh yet (allowed: jaxgear run, the "
        "rigid mesh's quasi-static files)"
    )


@_case_model.register
def _train_model(form: TrainForm, case: Case, spec: SceneSpec, slices, bodies):
    """A train case's dynamic model: its torsional or lumped 3D train
    (:meth:`Case.dynamic_train`), or with flexible gears its hybrid train
    (:meth:`Case.hybrid_train` of the condensed ``bodies``, default the scene's; on the
    case's ``[housing]``, :meth:`Case.hybrid_housing`)."""
    if case.flexible:  # its flexible gears condensed: a hybrid model
        bodies = load_bodies(spec) if bodies is None else bodies
        return dynamic_model(
            case.hybrid_train(bodies, slices, **case.hybrid_housing()),
            case.mesh_modifications(),
            case.torque,
            spec_damping(spec),
            rotating_frame=spec.rotating_frame,
        )
    return dynamic_model(
        case.dynamic_train(slices),
        case.mesh_modifications(),
        case.torque,
        spec_damping(spec),
        positions_per_pitch=spec.steps_per_period or 64,
    )


def _lumped3d_pair(case: Case, spec: SceneSpec, mesh, housing=None, seats=None,
                   position=None):
    """``[scene] model = "lumped3d"``: the 3D lumped pair on its shafts and bearings;
    ``housing``, ``seats``, ``position``: a housing placed by the caller (a gearbox's, in its
    frame), each bearing's seat and the scene origin's place in that frame
    (:func:`~jaxgear.scenes.lumped_pair`'s ``housing_position``), instead of the case's
    ``[housing]``."""
    i1, i2 = _inertias(case, spec)
    masses, inertias = _gear_bodies(case, spec, i1, i2)
    shafts = (spec.pinion_shaft, spec.gear_shaft)
    if housing is None and case.housing is not None:  # [housing]: the bearings on its seats
        housing = case.housing_body(spec).housing  # (docs/housing.md)
    if spec.rolling:  # bearings from geometry: at the case's operating point (on the ground)
        shafts = operating_point(case, spec).shafts
    return lumped_pair(
        case.pair,
        mesh,
        *shafts,
        masses=masses,
        inertias=inertias,
        youngs_modulus=case.youngs_modulus,
        poisson_ratio=case.poisson_ratio,
        density=case.density,
        housing=housing,
        seats=seats,
        housing_position=position,
    )


class CaseBearings(NamedTuple):
    """A pair or train case's rolling bearings at their operating point with their lives
    (:func:`case_bearings`): ``point`` (:class:`~jaxgear.dynamics.OperatingPoint`), ``speeds``
    each shaft's speed (rad/s, magnitudes: the pinion's (input's) ``[operating]
    speed_rad_s`` times the shaft's :attr:`~jaxgear.io.BearingShafts.ratios`; None without a
    speed),
    ``lives`` per shaft per bearing (:func:`~jaxgear.dynamics.operating_lives`), ``settings``
    the ``[bearings]`` settings (:class:`~jaxgear.io.BearingLifeSettings`) or None,
    ``spectrum`` per shaft per bearing its life under the case's ``[rating.spectrum]``
    (:func:`~jaxgear.dynamics.spectrum_lives`) or None without one, ``names`` each shaft's
    table in the case file (:attr:`~jaxgear.io.BearingShafts.names`)."""

    point: OperatingPoint
    speeds: tuple | None
    lives: tuple
    settings: Any
    spectrum: tuple | None = None
    names: tuple = ("scene.pinion_shaft", "scene.gear_shaft")


def case_bearings(case: Case) -> CaseBearings | None:
    """The rolling bearings of a ``lumped3d`` pair or train case's shafts
    (:meth:`~jaxgear.io.CaseForm.bearing_shafts`) at their operating point
    (:func:`~jaxgear.io.operating_point`) and their lives there at the case's speed, with ISO 281's modified life where the case has
    ``[bearings]`` and, under the case's rating spectrum (``[rating.spectrum]``, its first
    mesh's: the input torque and speed), each bin's operating point at its torque and the
    bins' life by Palmgren–Miner (:class:`CaseBearings`); None for a case without rolling
    bearings. The pinion (input) speed: ``[operating] speed_rad_s``, else the rating's
    ``speed_rpm``."""
    found = case.form.bearing_shafts(case)
    if found is None:
        return None
    spec = case.scene
    point = operating_point(case, spec)
    ratio = found.ratios
    w = case.speed if case.speed > 0 else pinion_speed((case.raw or {}).get("operating", {}))
    speeds = tuple(w * r for r in ratio) if w > 0 else None
    settings = bearing_life_of(case)
    extra = {} if settings is None else settings._asdict()
    lives = operating_lives(point, speeds, **extra)
    spectrum = None
    rated = ratings_of(case) if case.rating is not None else None
    if rated and rated[0].spectrum is not None:
        spectrum = bearing_spectrum_lives(case, rated[0].spectrum)
    return CaseBearings(point, speeds, lives, settings, spectrum, found.names)


def bearing_spectrum_lives(case: Case, spectrum) -> tuple:
    """The lives of a ``lumped3d`` pair or train case's rolling bearings under a load spectrum
    of its pinion (input): ``spectrum`` (:class:`jaxgear.rating.LoadSpectrum`, k bins of
    the pinion's torque (N·m), speed (rad/s) and time (s)); each bin's operating point at its
    torque (:func:`~jaxgear.io.operating_point`; a bin without torque: no load, no damage),
    each shaft at the bin's speed times its :attr:`~jaxgear.io.BearingShafts.ratios`, the
    bins' damage summed by Palmgren–Miner (:func:`~jaxgear.dynamics.spectrum_lives`, ISO 281
    and ISO/TS 16281; ISO 281's modified life with the case's ``[bearings]``). A pair case's
    own ``[rating.spectrum]`` (:func:`case_bearings`) and a gearbox's ``[load_spectrum]``
    carried to its stage (:meth:`~jaxgear.io.GearboxForm.stage_spectrum`) both come here.

    Returns:
        Per shaft, per bearing, its :class:`~jaxgear.dynamics.SpectrumLife` or None (a
        bearing without ratings).

    Raises:
        ValueError: a case without rolling bearings from their geometry; no loaded bin (one
            line).
    """
    found = case.form.bearing_shafts(case)
    if found is None:
        raise ValueError(f"bearing_spectrum_lives: case {case.name!r} has no rolling bearings "
                         "from their geometry: allowed a lumped3d pair or train case with them")
    settings = bearing_life_of(case)
    extra = {} if settings is None else settings._asdict()
    torques = np.asarray(spectrum.torque, float)
    points = [operating_point(case, case.scene, t) if t > 0 else None for t in torques]
    shaft_speeds = np.asarray(spectrum.speed, float)[:, None] * np.asarray(found.ratios)[None, :]
    return spectrum_lives(points, shaft_speeds, np.asarray(spectrum.duration, float), **extra)


def _torsional_pair(case: Case, spec: SceneSpec, mesh):
    """``[scene] model = "torsional"``: the torsional pair, with a motor and a load where the
    case gives them, reduced to the relative approach with ``reduction = "relative"``."""
    i1, i2 = _inertias(case, spec)
    has_m, has_l = spec.motor_inertia is not None, spec.load_inertia is not None
    scene = TorsionalDynamics(
        mesh,
        i1,
        i2,
        spec.motor_inertia or 1.0,
        spec.load_inertia or 1.0,
        spec.motor_shaft or 1.0,
        spec.load_shaft or 1.0,
        has_motor=has_m,
        has_load=has_l,
    )
    return scene.reduced() if spec.reduction == "relative" else scene


#: the rigid-gear pair scenes a case's ``[scene] model`` names: (case, spec, mesh model) ↦ scene
PAIR_SCENES = {"lumped3d": _lumped3d_pair, "torsional": _torsional_pair}


def static_scene(
    case: Case,
    *,
    slices: int | None = None,
    bodies: tuple | None = None,
):
    """The scene of the case's quasi-static solve with shafts, bearings and condensed bodies,
    by the case's form (:attr:`Case.form`).

    A pair's: ``lumped3d`` without bodies, the lumped scene with the load rotation grounded;
    with ``[scene.pinion_body]``/``[scene.gear_body]``, the hybrid scene
    (:func:`jaxgear.scenes.hybrid_pair`), its flexible members' tooth stiffness without the
    foundation term, with ``[housing]`` its shafts on the housing's seats
    (:meth:`Case.hybrid_housing`). A train's: :meth:`Case.static_train` (the lumped 3D train,
    the output shaft's rotation held; with ``[scene.bodies]`` its hybrid train, the bodies
    default to the scene's), the scene ``jaxgear run`` solves. The scene holds no operating
    point: pass the torque and the input speed (the case's ``torque``/``speed``) to the
    solvers.

    Returns:
        (scene, bodies): the scene and the condensed bodies (a pair's (pinion, gear), a train's
        one per gear) or ``None`` each.

    Raises:
        ValueError: the case has no ``lumped3d`` scene; slices that do not nest in the body's
            axial rim faces; body/gear mismatch (see :func:`jaxgear.scenes.hybrid_pair`).
    """
    spec = case.scene
    if spec is None or spec.model != "lumped3d":
        raise ValueError("a quasi-static scene needs a case with [scene] model = 'lumped3d'")
    return _static_scene(case.form, case, slices, bodies)


@functools.singledispatch
def _static_scene(form, case: Case, slices: int | None, bodies: tuple | None):
    """:func:`static_scene` of a case of ``form`` (:class:`~jaxgear.io.CaseForm`)."""
    raise TypeError(f"no quasi-static scene for a case of form {type(form).__name__}")


@_static_scene.register
def _pair_static_scene(form: PairForm, case: Case, slices, bodies):
    spec = case.scene
    if not spec.hybrid:  # the dynamic model's scene, without its modes and damping
        scene = PAIR_SCENES[spec.model](case, spec, case.mesh_model(slices=slices))
        return grounded(scene, (scene.torque_dofs[1],)), (None, None)
    bodies = load_bodies(spec) if bodies is None else bodies
    flexible = tuple(b is not None for b in bodies)
    mesh = case.mesh_model(slices=slices, flexible=flexible)
    masses, inertias = _gear_bodies(case, spec, *_inertias(case, spec))
    scene = hybrid_pair(
        case.pair,
        mesh,
        spec.pinion_shaft,
        spec.gear_shaft,
        bodies=bodies,
        masses=masses,
        inertias=inertias,
        material=Material(case.youngs_modulus, case.poisson_ratio, case.density),
        **case.hybrid_housing(),  # [housing]: the shafts on its seats
    )
    return scene, bodies


@_static_scene.register
def _planetary_static_scene(form: PlanetaryForm, case: Case, slices, bodies):
    raise ValueError(PLANETARY_NO_SCENE)


@_static_scene.register
def _train_static_scene(form: TrainForm, case: Case, slices, bodies):
    rigid = (None,) * case.n_gears
    bodies = (load_bodies(case.scene) if case.flexible else rigid) if bodies is None else bodies
    return case.static_train(slices, bodies), bodies


def quasi_static_scene(
    case: Case,
    *,
    slices: int | None = None,
    contact: ContactLaw = ExactContact(),
    speed: float | None = None,
    bodies: tuple | None = None,
) -> tuple[QuasiStaticResult, dict]:
    """Quasi-static TE of the case's scene (:func:`static_scene`): shafts and bearings
    (``lumped3d``) and condensed FE bodies when the scene has them, with the case's
    modifications (each mesh's).

    Args:
        case: a case with ``[scene] model = "lumped3d"``.
        slices: slices per contact line (default the case's). contact: the contact law
            (:class:`~jaxgear.ExactContact` by default).
        speed: pinion speed (rad/s) of the centrifugal load of the bodies (default the case's).
        bodies: condensed bodies (pinion, gear) already loaded (default: the scene's, built or
            read from the fem_prep cache).

    Returns:
        (result, mean bearing force (N) per bearing-force component name, fixed frame).

    Raises:
        ValueError: the case has no ``lumped3d`` scene.
    """
    scene, _ = static_scene(case, slices=slices, bodies=bodies)
    res = quasi_static(
        scene,
        case.mesh_modifications(),
        case.torque,
        speed=case.speed if speed is None else speed,
        contact=contact,
        positions_per_pitch=case.positions_per_pitch,
    )
    return res, bearing_forces(scene, res)
