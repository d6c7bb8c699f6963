"""The dynamic model of a case: its ``[scene]`` settings turned into a scene and a
:class:`DynamicModel` (inertias default to solid discs)."""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from .._case import Case, TrainCase
from .._contact import ContactLaw, ExactContact
from .._quasi_static import QuasiStaticResult, quasi_static
from ..scenes import (
    Material,
    ShaftSpec,
    TorsionalDynamics,
    disc_inertia,
    grounded,
    hybrid_pair,
    lumped_pair,
)
from ._build import dynamic_model
from ._damping import (
    AbstractDamping,
    CompositeDamping,
    ModalDamping,
    NoDamping,
    RayleighDamping,
)
from ._settings import DiffraxIntegrator, ModalBasis, Newmark, SteadyState

__all__ = [
    "DAMPING_MODELS",
    "Damping",
    "SceneSpec",
    "bearing_forces",
    "build_dynamic_model",
    "load_bodies",
    "quasi_static_scene",
    "spec_damping",
    "spec_integrator",
    "spec_window",
    "static_scene",
]


@dataclasses.dataclass(frozen=True)
class SceneSpec:
    """A validated ``[scene]`` table (SI units; ``None``: derived default)."""

    model: str = "torsional"
    reduction: str = "none"
    pinion_inertia: float | None = None
    gear_inertia: float | None = None
    motor_inertia: float | None = None
    motor_shaft: float | None = None
    load_inertia: float | None = None
    load_shaft: float | None = None
    damping_model: str = "composite"
    damping_ratio: float = 0.05
    rayleigh_alpha: float = 0.0
    rayleigh_beta: float = 0.0
    mesh_ratio: float = 0.07
    structure_ratio: float = 0.01
    solver: str = "newmark"
    contact: str = "exact"
    steps_per_period: int | None = None  # None: automatic (auto_steps_per_period)
    periods: int = 60
    keep_periods: int = 4
    rtol: float = 1e-6
    atol: float = 1e-6
    rotating_frame: bool = False  # hybrid: the turning frames' inertia (HybridModel)
    modal_basis: int | None = None  # hybrid: Newmark in a modal basis of this many modes
    pinion_mass: float | None = None
    gear_mass: float | None = None
    pinion_shaft: ShaftSpec | None = None  # lumped3d
    gear_shaft: ShaftSpec | None = None
    shafts: tuple | None = None  # a lumped3d train: each shaft's ShaftSpec (TrainCase.shaft_of)
    # lumped3d with condensed FE bodies (hybrid H1/H2): an embedded fem_prep body name, a body
    # TOML path or a condensed .npz path (resolved against the case file's folder)
    pinion_body: str | None = None
    gear_body: str | None = None
    gear_bodies: tuple = ()  # a lumped3d train: each gear's body reference or None
    gear_rims: tuple = ()  # a lumped3d train: each gear's rim on its body (0 the wheel's)

    @property
    def bodies(self) -> tuple:
        """Each member's body reference or ``None``: (pinion, gear) for a pair, one per gear
        for a train."""
        return self.gear_bodies or (self.pinion_body, self.gear_body)

    @property
    def hybrid(self) -> bool:
        return any(b is not None for b in self.bodies)


def spec_integrator(spec: SceneSpec) -> Newmark | DiffraxIntegrator:
    """The integrator of a case's ``[scene.integration]`` table: ``solver = "newmark"`` →
    :class:`Newmark`, a diffrax solver name → :class:`DiffraxIntegrator` (with its
    tolerances); ``steps_per_period`` (``None``: automatic); ``modal_basis`` = m →
    ``Newmark(..., basis=ModalBasis(m))`` (hybrid models)."""
    return INTEGRATORS.get(spec.solver, _diffrax_integrator)(spec)


def _newmark_integrator(spec: SceneSpec) -> Newmark:
    basis = None if spec.modal_basis is None else ModalBasis(int(spec.modal_basis))
    return Newmark(spec.steps_per_period, basis=basis)


def _diffrax_integrator(spec: SceneSpec) -> DiffraxIntegrator:
    return DiffraxIntegrator(
        spec.solver, spec.steps_per_period, rtol=float(spec.rtol), atol=float(spec.atol)
    )


#: the integrators a case's ``[scene.integration] solver`` names (any other name: a diffrax
#: solver, :data:`~jaxgear.dynamics.DIFFRAX_SOLVERS`)
INTEGRATORS = {"newmark": _newmark_integrator}


def spec_window(spec: SceneSpec) -> SteadyState:
    """The steady-state window of a case's ``[scene.integration]`` table."""
    return SteadyState(spec.periods, spec.keep_periods)


#: the damping models a case file (``[scene.damping] model``) or :func:`Damping` names; each
#: takes the settings named as its fields
DAMPING_MODELS = {
    "rayleigh": RayleighDamping,
    "modal": ModalDamping,
    "composite": CompositeDamping,
    "none": NoDamping,
}


def Damping(  # noqa: N802 - the former class's spelling, kept for callers
    model: str = "composite",
    *,
    ratio=0.05,
    alpha=0.0,
    beta=0.0,
    mesh_ratio=0.07,
    structure_ratio=0.01,
) -> AbstractDamping:
    """The damping model a name gives (seed (2.34)-(2.36)), the spelling of a case file's
    ``[scene.damping]``: ``"rayleigh"`` → :class:`RayleighDamping` (``alpha`` a_R (1/s),
    ``beta`` b_R (s)), ``"modal"`` → :class:`ModalDamping` (``ratio`` ξ), ``"composite"`` →
    :class:`CompositeDamping` (``mesh_ratio`` ξ_mesh, ``structure_ratio`` ξ_structure),
    ``"none"`` → :class:`NoDamping`; the other keywords are not used.

    Raises:
        ValueError: another name (one line).
    """
    if model not in DAMPING_MODELS:
        raise ValueError(
            f"damping model = {model!r}: allowed 'rayleigh', 'modal', 'composite', 'none'"
        )
    settings = {
        "ratio": ratio,
        "alpha": alpha,
        "beta": beta,
        "mesh_ratio": mesh_ratio,
        "structure_ratio": structure_ratio,
    }
    cls = DAMPING_MODELS[model]
    return cls(**{f.name: settings[f.name] for f in dataclasses.fields(cls)})


def spec_damping(spec: SceneSpec) -> AbstractDamping:
    """The damping model of a case's ``[scene.damping]`` table (seed (2.34)–(2.36))."""
    return Damping(
        spec.damping_model,
        ratio=spec.damping_ratio,
        alpha=spec.rayleigh_alpha,
        beta=spec.rayleigh_beta,
        mesh_ratio=spec.mesh_ratio,
        structure_ratio=spec.structure_ratio,
    )


def build_dynamic_model(
    case: Case | TrainCase,
    spec: SceneSpec | None = None,
    *,
    slices: int | None = None,
    bodies: tuple | None = None,
):
    """The dynamic model of a case and its scene (default: ``[scene]``): a
    :class:`~jaxgear.dynamics.DynamicModel`, or a :class:`~jaxgear.dynamics.HybridModel` when
    the scene has condensed bodies (its damping ``[scene.damping]`` and ``rotating_frame``).
    A train case (:class:`~jaxgear.TrainCase`) gives its train
    (:meth:`~jaxgear.TrainCase.dynamic_train`: torsional or lumped 3D; with flexible gears
    :meth:`~jaxgear.TrainCase.hybrid_train`, a hybrid model), the input torque on its input
    gear.

    Inertias default to solid discs of the tip radius and the member's face width with the case
    density. ``bodies``: the condensed bodies (pinion, gear) already loaded (default: the
    scene's, built or read from the fem_prep cache; a train's: one per gear). Returns (model,
    spec).
    """
    if spec is None:
        spec = case.scene if case.scene is not None else SceneSpec()
    if isinstance(case, TrainCase):  # a torsional or lumped 3D train
        if case.flexible:  # its flexible gears condensed: a hybrid model
            bodies = load_bodies(spec) if bodies is None else bodies
            model = dynamic_model(
                case.hybrid_train(bodies, slices),
                case.mesh_modifications(),
                case.torque,
                spec_damping(spec),
                rotating_frame=spec.rotating_frame,
            )
            return model, spec
        model = dynamic_model(
            case.dynamic_train(slices),
            case.mesh_modifications(),
            case.torque,
            spec_damping(spec),
            positions_per_pitch=spec.steps_per_period or 64,
        )
        return model, spec
    if spec.hybrid:
        scene, _ = static_scene(case, slices=slices, bodies=bodies)
        model = dynamic_model(
            scene,
            case.modifications,
            case.torque,
            spec_damping(spec),
            rotating_frame=spec.rotating_frame,
        )
        return model, spec
    scene = PAIR_SCENES[spec.model](case, spec, case.mesh_model(slices=slices))
    damping = spec_damping(spec)
    # the time averages (modal analysis, damping) need a fixed grid: 64 positions per period
    # unless the scene fixes the step
    model = dynamic_model(
        scene,
        case.modifications,
        case.torque,
        damping,
        positions_per_pitch=spec.steps_per_period or 64,
    )
    return model, spec


def _inertias(case: Case, spec: SceneSpec) -> tuple[float, float]:
    """The pinion's and the gear's polar inertias (kg·m²): the case's, or solid discs."""
    pair = case.pair
    i1 = spec.pinion_inertia or disc_inertia(
        case.density, pair.tip_radii[0], pair.pinion.face_width
    )
    i2 = spec.gear_inertia or disc_inertia(case.density, pair.tip_radii[1], pair.gear.face_width)
    return i1, i2


def _lumped3d_pair(case: Case, spec: SceneSpec, mesh):
    """``[scene] model = "lumped3d"``: the 3D lumped pair on its shafts and bearings."""
    i1, i2 = _inertias(case, spec)
    masses, inertias = _gear_bodies(case, spec, i1, i2)
    return lumped_pair(
        case.pair,
        mesh,
        spec.pinion_shaft,
        spec.gear_shaft,
        masses=masses,
        inertias=inertias,
        youngs_modulus=case.youngs_modulus,
        poisson_ratio=case.poisson_ratio,
        density=case.density,
    )


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


def load_bodies(spec: SceneSpec, *, progress: bool = False) -> tuple:
    """The condensed bodies of a scene (pinion, gear; a train's: one per gear, the gears of a
    body with two rims sharing the one object), ``None`` for a rigid member.

    Bodies are built by :mod:`fem_prep` once and then read from its cache
    (:func:`fem_prep.condensed`).
    """
    if not spec.hybrid:
        return (None,) * len(spec.bodies)
    import fem_prep  # NumPy/scikit-fem only; loaded when a case has flexible bodies

    loaded = {}  # one object per reference: the gears of a two-rim body share it
    for ref in spec.bodies:
        if ref is not None and ref not in loaded:
            loaded[ref] = fem_prep.condensed(ref, progress=progress)
    return tuple(None if ref is None else loaded[ref] for ref in spec.bodies)


def _gear_bodies(case: Case, spec: SceneSpec, i1: float, i2: float):
    """(masses, inertias) of rigid disc gear bodies (inertias default to solid discs)."""
    pair = case.pair
    body = []
    for r, b, m, ip in (
        (pair.tip_radii[0], pair.pinion.face_width, spec.pinion_mass, i1),
        (pair.tip_radii[1], pair.gear.face_width, spec.gear_mass, i2),
    ):
        m = m or case.density * math.pi * r * r * b
        body.append((m, (ip / 2 + m * b * b / 12, ip)))  # disc: I_d = I_p/2 + m b²/12
    return (body[0][0], body[1][0]), (body[0][1], body[1][1])


def static_scene(
    case: Case,
    *,
    slices: int | None = None,
    bodies: tuple | None = None,
):
    """The scene of the case's quasi-static solve with shafts, bearings and condensed bodies.

    ``lumped3d`` without bodies: the lumped scene with the load rotation grounded. With
    ``[scene.pinion_body]``/``[scene.gear_body]``: the hybrid scene (:func:`jaxgear.scenes.hybrid_pair`),
    its flexible members' tooth stiffness without the foundation term. The scene holds no
    operating point: pass the torque and the pinion speed (the case's ``torque``/``speed``) to
    the solvers.

    Returns:
        (scene, bodies): the scene and the condensed bodies (pinion, gear) or ``None``.

    Raises:
        ValueError: the case has no ``lumped3d`` scene; slices that do not nest in the body's
            axial rim faces; body/gear mismatch (see :func:`jaxgear.scenes.hybrid_pair`).
    """
    spec = case.scene
    if spec is None or spec.model != "lumped3d":
        raise ValueError("a quasi-static scene needs a case with [scene] model = 'lumped3d'")
    if not spec.hybrid:
        model, _ = build_dynamic_model(case, slices=slices)
        return grounded(model.scene, (model.scene.torque_dofs[1],)), (None, None)
    bodies = load_bodies(spec) if bodies is None else bodies
    flexible = tuple(b is not None for b in bodies)
    mesh = case.mesh_model(slices=slices, flexible=flexible)
    pair = case.pair
    i1 = spec.pinion_inertia or disc_inertia(
        case.density, pair.tip_radii[0], pair.pinion.face_width
    )
    i2 = spec.gear_inertia or disc_inertia(case.density, pair.tip_radii[1], pair.gear.face_width)
    masses, inertias = _gear_bodies(case, spec, i1, i2)
    scene = hybrid_pair(
        pair,
        mesh,
        spec.pinion_shaft,
        spec.gear_shaft,
        bodies=bodies,
        masses=masses,
        inertias=inertias,
        material=Material(case.youngs_modulus, case.poisson_ratio, case.density),
    )
    return scene, bodies


def bearing_forces(scene, res: QuasiStaticResult) -> dict:
    """Mean bearing force (N) per component name over the positions of ``res`` (fixed frame)."""
    base = getattr(scene, "base", scene)  # a Grounded scene's own
    F = np.asarray(base.bearing_forces(res.theta, res.x))  # (P, r)
    return dict(zip(base.reaction_names, F.mean(axis=0).tolist()))


def quasi_static_scene(
    case: Case,
    *,
    slices: int | None = None,
    contact: ContactLaw = ExactContact(),
    speed: float | None = None,
    bodies: tuple | None = None,
) -> tuple[QuasiStaticResult, dict]:
    """Quasi-static TE of the case's scene: shafts and bearings (``lumped3d``) and condensed FE
    bodies when the scene has them, with the case's modifications.

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
        case.modifications,
        case.torque,
        speed=case.speed if speed is None else speed,
        contact=contact,
        positions_per_pitch=case.positions_per_pitch,
    )
    return res, bearing_forces(scene, res)
