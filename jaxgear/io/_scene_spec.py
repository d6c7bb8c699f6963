"""A case's ``[scene]`` settings (:class:`SceneSpec`) and the objects their names give: the
integrator, the damping model, the steady-state window, the condensed bodies."""

from __future__ import annotations

import dataclasses

import fem_prep  # NumPy/scikit-fem only: the condensed bodies of a scene

from ..dynamics import (
    AbstractDamping,
    CompositeDamping,
    DiffraxIntegrator,
    ModalBasis,
    ModalDamping,
    Newmark,
    NoDamping,
    RayleighDamping,
    SteadyState,
)
from ..scenes import (
    HybridScene,
    LumpedPair,
    LumpedTrain,
    RelativeApproach,
    ShaftSpec,
    TorsionalDynamics,
    TorsionalTrain,
)

__all__ = [
    "DAMPING_MODELS",
    "INTEGRATORS",
    "Damping",
    "SceneSpec",
    "load_bodies",
    "spec_damping",
    "spec_integrator",
    "spec_window",
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
    periods: int | None = None  # None: automatic (settled sweeps, docs/dynamics.md)
    keep_periods: int = 4
    rtol: float = 1e-6
    atol: float = 1e-6
    rotating_frame: bool = False  # hybrid: the turning frames' inertia (HybridModel)
    modal_basis: int | None = None  # hybrid: Newmark in a modal basis of this many modes
    pinion_mass: float | None = None
    gear_mass: float | None = None
    pinion_shaft: ShaftSpec | None = None  # lumped3d
    gear_shaft: ShaftSpec | None = None
    shafts: tuple | None = None  # a lumped3d train: each shaft's ShaftSpec (Case.shaft_of)
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

    @property
    def rolling(self) -> bool:
        """A shaft stands on a rolling bearing from its geometry (its stiffness at the
        operating point of the case's quasi-static solve: docs/bearings.md)."""
        shafts = (self.pinion_shaft, self.gear_shaft, *(self.shafts or ()))
        return any(b.rolling is not None for s in shafts if s is not None for b in s.bearings)

    @property
    def lumped(self) -> bool:
        """The scene is lumped 3D (``model = "lumped3d"``: shafts on bearings)."""
        return self.model == "lumped3d"

    def kind(self, pair: bool = True) -> type:
        """The scene kind (its class) the table builds for a pair (``pair``) or a train:
        condensed bodies a :class:`~jaxgear.scenes.HybridScene`; ``model = "lumped3d"`` a
        :class:`~jaxgear.scenes.LumpedPair` or :class:`~jaxgear.scenes.LumpedTrain`;
        ``"torsional"`` a :class:`~jaxgear.scenes.TorsionalDynamics` (with ``reduction =
        "relative"`` a :class:`~jaxgear.scenes.RelativeApproach`) or a
        :class:`~jaxgear.scenes.TorsionalTrain`. What the kind supports is read from it (its
        :attr:`~jaxgear.scenes.Scene.takes_housing`)."""
        if self.hybrid:
            return HybridScene
        if self.lumped:
            return LumpedPair if pair else LumpedTrain
        if not pair:
            return TorsionalTrain
        return RelativeApproach if self.reduction == "relative" else TorsionalDynamics


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


#: the periods a run integrates before its kept ones where ``periods = "auto"`` and the run is
#: not a settled sweep (:func:`jaxgear.dynamics.settled_sweep`: a hybrid model's sweep, one
#: speed from the static equilibrium): the former default span, 60 with 4 kept
FIXED_TRANSIENT_PERIODS = 56


def spec_window(spec: SceneSpec) -> SteadyState:
    """The steady-state window of a case's ``[scene.integration]`` table (``periods =
    "auto"``: :data:`FIXED_TRANSIENT_PERIODS` before the kept ones)."""
    periods = spec.periods
    if periods is None:
        periods = spec.keep_periods + FIXED_TRANSIENT_PERIODS
    return SteadyState(periods, spec.keep_periods)


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


def load_bodies(spec: SceneSpec, *, progress: bool = False) -> tuple:
    """The condensed bodies of a scene (pinion, gear; a train's: one per gear, the gears of a
    body with two rims sharing the one object), ``None`` for a rigid member.

    Bodies are built by :mod:`fem_prep` once and then read from its cache
    (:func:`fem_prep.condensed`).
    """
    if not spec.hybrid:
        return (None,) * len(spec.bodies)
    loaded = {}  # one object per reference: the gears of a two-rim body share it
    for ref in spec.bodies:
        if ref is not None and ref not in loaded:
            loaded[ref] = fem_prep.condensed(ref, progress=progress)
    return tuple(None if ref is None else loaded[ref] for ref in spec.bodies)
