"""A case in SI units: one type, :class:`Case`, for a gear pair and a gear train alike (a pair is a
train of two gears and one mesh): geometry, modifications, material, operating point, mesh model
settings (:class:`MeshSettings`, written once), and optionally a dynamic scene, deviations and
optimisation settings.

Cases are read from TOML files (units in key names) by :func:`jaxgear.io.load_case`, which
validates the whole file first; this module holds only the validated, SI-unit result. How the
file wrote its gears, a pair's ``[pair]``/``[pinion]``/``[gear]`` or a train's ``[[gears]]`` and
``[[meshes]]``, is the case's :class:`CaseForm` (:class:`PairForm`, :class:`TrainForm`): it names
the meshes in the outputs and chooses the scene builders of ``[scene]``.
"""

from __future__ import annotations

import abc
import dataclasses
import fractions
import math
import warnings
from typing import Any, NamedTuple

from .._baseplane import MeshModel
from .._contact import ContactLaw
from .._contact_geometry import AbstractContactGeometry, TheoreticalPath
from .._geometry import GearPair
from .._modifications import Modifications
from .._stiffness_models import FE2D, AbstractStiffness, MeshConditions, stiffness_table
from ..scenes import (
    TrainSpec,
    Wrench,
    bearing_positions,
    disc_inertia,
    grounded,
    hybrid_train,
    line_of_action,
    lumped_pair,
    lumped_train,
    torsional_train,
    train_layout,
)
from ._names import contact_geometry_from_key, contact_law_from_name
from ._operating import operating_point
from ._scene_spec import SceneSpec
from ._sections import Section

__all__ = ["BearingShafts", "Case", "CaseForm", "MeshSettings", "PairForm", "TrainCase",
           "TrainForm", "mesh_teeth_per_turn", "teeth_span"]


def mesh_teeth_per_turn(pairs, gears, shaft_of) -> tuple[fractions.Fraction, ...]:
    """Each mesh's teeth per turn of the input (exact): its driving gear's (``pair.pinion``)
    teeth times the turns its shaft makes per turn of the first gear's shaft, the input; the
    mesh's frequency is this times the input speed Ω / 2π (the magnitudes: an internal mesh's
    sense is not kept). ``pairs``, ``gears`` ((driving, driven) per mesh, the meshes from the
    input outwards) and ``shaft_of`` (each gear's shaft) as :class:`Case`'s."""
    ratio = {shaft_of[0]: fractions.Fraction(1)}
    out = []
    for pair, (g, h) in zip(pairs, gears, strict=True):
        rg = ratio[shaft_of[g]]
        ratio[shaft_of[h]] = rg * pair.pinion.teeth / pair.gear.teeth
        out.append(rg * pair.pinion.teeth)
    return tuple(out)


def teeth_span(teeth) -> int:
    """Periods of the first mesh after which meshes of ``teeth`` (each one's teeth per input
    turn, exact: :func:`mesh_teeth_per_turn`) repeat together: the least common multiple of
    the numerators of t_0 / t_k."""
    return math.lcm(*((teeth[0] / t).numerator for t in teeth))


def _contact_changes(changes: dict) -> dict:
    """``changes`` with the deprecated ``extended_contact`` (a bool, a DeprecationWarning) given
    as the ``contact_geometry`` it stands for."""
    if "extended_contact" in changes:
        warnings.warn(
            "replace(extended_contact=...) is deprecated: pass contact_geometry="
            "jaxgear.BeyondPath() (True) or jaxgear.TheoreticalPath() (False)",
            DeprecationWarning,
            stacklevel=3,
        )
        changes["contact_geometry"] = contact_geometry_from_key(changes.pop("extended_contact"))
    return changes


@dataclasses.dataclass(frozen=True, kw_only=True)
class MeshSettings:
    """The material and mesh-model settings of a case (:class:`Case`), written once, for every
    mesh (each mesh's one-mesh case, :meth:`Case.mesh_case`, takes them).

    Attributes:
        youngs_modulus: Young's modulus (Pa); ``poisson_ratio`` (-); ``density`` (kg/m³).
        stiffness: the mesh-stiffness model (:class:`~jaxgear.AbstractStiffness`:
            :class:`~jaxgear.Uniform`, :class:`~jaxgear.ISO6336`, :class:`~jaxgear.Weber`,
            :class:`~jaxgear.FE2D`, default ``FE2D()``; the case file's ``[mesh] stiffness``
            names it, :mod:`jaxgear.io` builds it).
        slices: slices per contact line; positions_per_pitch: positions per mesh period.
        smooth_width: smoothing width of the smooth contact law (m).
        contact_geometry: where the teeth can touch (:class:`~jaxgear.TheoreticalPath`, or
            :class:`~jaxgear.BeyondPath`: contact beyond the theoretical path of contact,
            premature engagement and late disengagement at the tip corners;
            :meth:`jaxgear.MeshModel.from_pair`, docs/extended-contact.md).
            ``TheoreticalPath()`` for a case built in Python; a case file's ``[mesh]
            extended_contact`` defaults to true, ``BeyondPath()`` (false with backlash).
            ``extended_contact`` (a bool, read or given to :meth:`replace`) is its deprecated
            spelling.
    """

    youngs_modulus: float = 210e9
    poisson_ratio: float = 0.3
    density: float = 7800.0
    stiffness: AbstractStiffness = FE2D()
    slices: int = 40
    positions_per_pitch: int = 64
    smooth_width: float = 1e-7
    contact_geometry: AbstractContactGeometry = TheoreticalPath()

    @property
    def extended_contact(self) -> bool:
        """Deprecated (a DeprecationWarning): whether :attr:`contact_geometry` reaches beyond the
        theoretical path."""
        warnings.warn(
            "Case.extended_contact is deprecated: read case.contact_geometry "
            "(jaxgear.TheoreticalPath or jaxgear.BeyondPath)",
            DeprecationWarning,
            stacklevel=2,
        )
        return self.contact_geometry.reaches_beyond_path

    def mesh_settings(self) -> dict:
        """These settings as keywords (``{field: value}``), for another case that shares them."""
        return {f.name: getattr(self, f.name) for f in dataclasses.fields(MeshSettings)}

    def contact_law(self, mode: str) -> ContactLaw:
        """The contact law a case file names: ``"exact"`` → :class:`~jaxgear.ExactContact`,
        ``"smooth"`` → :class:`~jaxgear.SmoothContact` of the case's ``smooth_width`` (m).

        Raises:
            ValueError: another name.
        """
        return contact_law_from_name(mode, self.smooth_width)

    @property
    def lumped(self) -> bool:
        """The scene is lumped 3D (``[scene] model = "lumped3d"``: shafts on bearings)."""
        return self.scene is not None and self.scene.lumped

    @property
    def stiffness_model(self) -> str:
        """The stiffness model's name (``"weber"``, ``"fe2d"``, ...), for summaries."""
        return self.stiffness.name

    def replace(self, **changes):
        """A copy with ``changes`` (field names as keywords)."""
        return dataclasses.replace(self, **_contact_changes(changes))


def _inertias(case: Case, spec: SceneSpec) -> tuple[float, float]:
    """The pinion's and the gear's polar inertias (kg·m²): the case's, or solid discs."""
    pair = case.pair
    i1 = spec.pinion_inertia or disc_inertia(
        case.density, pair.tip_radii[0], pair.pinion.face_width
    )
    i2 = spec.gear_inertia or disc_inertia(case.density, pair.tip_radii[1], pair.gear.face_width)
    return i1, i2


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


class BearingShafts(NamedTuple):
    """The shafts of a case that stand on rolling bearings from their geometry
    (:meth:`CaseForm.bearing_shafts`): ``shafts`` each shaft's :class:`~jaxgear.scenes.ShaftSpec`
    as given (its rolling bearings without an operating point), ``names`` each shaft's table in
    the case file (``scene.pinion_shaft``, ``scene.shafts.idler``: a bearing's name is
    ``<name>.bearings[i]``), ``ratios`` each shaft's speed per pinion (input) speed
    (magnitudes: a pair's 1 and z1/z2, a train's its first gear's speed ratio)."""

    shafts: tuple
    names: tuple
    ratios: tuple


class CaseForm(abc.ABC):
    """How a case file wrote its gears, which the case keeps (:attr:`Case.form`): it names the
    case's meshes in the outputs and gives each mesh as a one-mesh case; :mod:`jaxgear.io`
    builds the ``[scene]`` of a case by its form (``io/_case_model.py``), the command line
    writes a case's summary by it (``cli/run.py``, ``cli/cases.py``)."""

    @abc.abstractmethod
    def mesh_name(self, case: Case, k: int) -> str:
        """Mesh ``k``'s name."""

    @abc.abstractmethod
    def mesh_label(self, case: Case, k: int) -> str:
        """What tells mesh ``k`` apart in the outputs ("": nothing, the case's own values)."""

    @abc.abstractmethod
    def mesh_case(self, case: Case, k: int) -> Case:
        """Mesh ``k`` as a one-mesh case (a :class:`PairForm` case)."""

    def own_housing_size(self):
        """The sizes of a ``[housing]`` this form lays out itself (a gearbox's, round its
        housed stages), else None: the case lays it out round its scene's bearings
        (:meth:`Case.housing_size`)."""
        return None

    def bearing_shafts(self, case: Case) -> BearingShafts | None:
        """The case's shafts that stand on rolling bearings from their geometry
        (:class:`BearingShafts`), or None: a form whose scenes take none (a planetary stage, an
        internal mesh; a gearbox, whose lumped 3D stages' cases hold their own at the chain's
        operating point), or a case without a rolling bearing."""
        return None

    def bearing_scene(self, case: Case, spec: SceneSpec) -> tuple:
        """(build, shafts, extra_z): what :func:`jaxgear.dynamics.bearings_at_operating_point`
        takes of the case's lumped 3D scene with rolling bearings (its ``[scene]``, or ``spec``):
        ``build(shafts)`` its scene on the ground on those shafts, the shafts as given, the
        shafts' more node positions (:func:`jaxgear.io.operating_point`).

        Raises:
            TypeError: a form whose scenes take no rolling bearings from their geometry.
        """
        raise TypeError(f"no rolling bearings from geometry in a case of form "
                        f"{type(self).__name__}")


@dataclasses.dataclass(frozen=True)
class PairForm(CaseForm):
    """A pair case file (``[pair]``, ``[pinion]``, ``[gear]``): gears ``pinion`` and ``gear``,
    one mesh that is the case itself: named by the case, unlabelled in the outputs (its values
    are the summary's own, its files and titles the case's); its ``[scene]`` a pair's
    (:data:`jaxgear.io.PAIR_SCENES`, condensed pinion and gear bodies)."""

    def mesh_name(self, case: Case, k: int) -> str:
        return case.name

    def mesh_label(self, case: Case, k: int) -> str:
        return ""

    def bearing_shafts(self, case: Case) -> BearingShafts | None:
        """A ``lumped3d`` pair's pinion and gear shafts (a hybrid pair refuses rolling bearings
        at load)."""
        spec = case.scene
        if spec is None or not spec.lumped or not spec.rolling:
            return None
        return BearingShafts((spec.pinion_shaft, spec.gear_shaft),
                             ("scene.pinion_shaft", "scene.gear_shaft"),
                             (1.0, case.pair.pinion.teeth / case.pair.gear.teeth))

    def bearing_scene(self, case: Case, spec: SceneSpec) -> tuple:
        """The pair's :func:`~jaxgear.scenes.lumped_pair` (rigid disc gear bodies) on given
        shafts."""
        i1, i2 = _inertias(case, spec)
        masses, inertias = _gear_bodies(case, spec, i1, i2)
        mesh = case.mesh_model()

        def build(shafts):
            return lumped_pair(case.pair, mesh, *shafts, masses=masses, inertias=inertias,
                               youngs_modulus=case.youngs_modulus,
                               poisson_ratio=case.poisson_ratio, density=case.density)

        return build, (spec.pinion_shaft, spec.gear_shaft), None

    def mesh_case(self, case: Case, k: int) -> Case:
        return case


@dataclasses.dataclass(frozen=True)
class TrainForm(CaseForm):
    """A train case file (``[[gears]]``, ``[[meshes]]``): each mesh named and labelled by its
    gears, ``"driving-driven"``; its ``[scene]`` a train's (torsional, lumped 3D on
    ``[[scene.shafts]]``, flexible gears)."""

    def mesh_name(self, case: Case, k: int) -> str:
        g, h = case.gears[k]
        return f"{case.gear_names[g]}-{case.gear_names[h]}"

    def mesh_label(self, case: Case, k: int) -> str:
        return self.mesh_name(case, k)

    def bearing_shafts(self, case: Case) -> BearingShafts | None:
        """A ``lumped3d`` train's ``[[scene.shafts]]`` (a train with ``[scene.bodies]`` refuses
        rolling bearings at load), each at its first gear's speed ratio."""
        spec = case.scene
        if spec is None or not spec.lumped or case.flexible or not spec.rolling:
            return None
        names = case.shaft_names or tuple(f"shaft{i}" for i in range(len(spec.shafts)))
        ratios = case.layout().ratios
        first = [case.shaft_of.index(i) for i in range(len(spec.shafts))]
        return BearingShafts(tuple(spec.shafts), tuple(f"scene.shafts.{n}" for n in names),
                             tuple(abs(float(ratios[g])) for g in first))

    def bearing_scene(self, case: Case, spec: SceneSpec) -> tuple:
        """The train's :func:`~jaxgear.scenes.lumped_train` (:meth:`Case.train_spec`, its mesh
        models built once) on given shafts, its wrenches' nodes (``TrainSpec.wrench_z``)."""
        train = case.train_spec()

        def build(shafts):
            return lumped_train(dataclasses.replace(train, shafts=tuple(shafts)))

        return build, tuple(spec.shafts), train.wrench_z

    def mesh_case(self, case: Case, k: int) -> Case:
        g, h = case.gears[k]
        return Case(
            name=f"{case.name}-{self.mesh_name(case, k)}",
            pairs=(case.pairs[k],),
            gear_modifications=(case.gear_modifications[g], case.gear_modifications[h]),
            torque=case.mesh_torques[k],
            speed=case.speed * case.layout().ratios[g],
            form=PairForm(),
            **case.mesh_settings(),
        )


@dataclasses.dataclass(frozen=True, kw_only=True)
class Case(MeshSettings):
    """A validated case (SI units, keywords only): gears, the meshes between them and their
    layout, the mesh settings, material and operating point. A gear pair is a train of two gears
    (``pinion``, ``gear``) and one mesh (:meth:`of_pair`); its views :attr:`pair`,
    :attr:`modifications` and :meth:`replace` of ``pair=``/``modifications=`` hold for a case of
    one mesh (else a ``ValueError``).

    Attributes:
        name: case name. gear_names: each gear's name, (n,), gear 0 the input.
        pairs: the :class:`~jaxgear.GearPair` of each mesh, (m,), its pinion the mesh's driving
            gear.
        gears: each mesh's (driving, driven) gear indices, listed from the input outwards.
        angles: each mesh's direction of the driven gear's centre seen from the driving one
            (rad, fixed frame).
        gear_modifications: each gear's :class:`~jaxgear.MemberModification`, (n,) (every flank
            it loads; :meth:`mesh_modifications` per mesh).
        torque: the input gear's torque (N·m); the balancing output takes what the loads
            leave.
        loads: ((gear, torque (N·m)), ...): the torques of the loaded gears other than the
            balancing output, each in its gear's direction of motion (< 0: it takes power), at
            the case's input torque; the model keeps their shares of the input power
            (:meth:`shares`), so another input torque scales them all.
        speed: the input gear's speed (rad/s).
        youngs_modulus: with ``poisson_ratio``, ``density``, ``stiffness``, ``slices``,
            ``positions_per_pitch``, ``smooth_width``: the mesh settings
            (:class:`MeshSettings`; keywords only), every
            mesh's.
        inertias: each gear's polar inertia (kg·m²), (n,); None: a solid disc of its tip radius
            and face width.
        shafts: each gear's shaft (n,) (default: a shaft each, numbered in gear order): gears
            on one shaft turn together (a compound gear: the wheel of one stage and the pinion
            of the next), one rotation of the torsional train, shaft 0 the input's.
        clockings: each gear's tooth angle on its shaft less that of the shaft's first gear
            (rad, in the direction of motion; default 0).
        hands: each gear's given helix hand, +1 right, −1 left, 0 by default (n,)
            (:func:`jaxgear.scenes.train_hands`).
        masses: each gear body's mass (kg), (n,), the lumped 3D scene's; None: a solid disc of
            its tip radius and face width.
        wrenches: ((shaft, z (m), force (N) (3,), moment (N·m) (3,)), ...): forces and tilting
            moments on shaft nodes at the case's input torque (lumped 3D; fixed frame), scaled
            with the input torque as the loads are.
        shaft_names: each shaft's name (a gear's ``shaft`` in the case file; default the name of
            its first gear), (shafts,).
        scene: the validated ``[scene]`` (:class:`jaxgear.io.SceneSpec`) or None.
        raw: the parsed TOML, as read (for reference; the fields above are what the code uses).
        deviations: manufacturing deviations per tooth of a pair (:class:`~jaxgear.Deviations`,
            ISO 1328-1) or None; deviation_settings: the ``[deviations]`` run settings (grade,
            seed, revolutions, positions per pitch; docs/deviations.md) or None.
        coast: model the coast flanks with the pair's backlash (:meth:`mesh_model`; the case
            file sets it when a ``tooth_thickness_allowance_um`` is given; docs/backlash.md).
        optimise: the validated ``[optimise]`` table (a dict in case-file units) or None.
        form: how the case file wrote its gears (:class:`CaseForm`: :class:`TrainForm` by
            default, :class:`PairForm` a pair file's): the meshes' names and labels in the
            outputs, and the scene builders.
        rating_standard: the rating standard every mesh of ``[rating]`` is rated to, an object
            (:class:`jaxgear.rating.AbstractRatingStandard`), given in Python
            (``case.replace(rating_standard=...)``); None: the one ``[rating] edition`` names
            (:func:`jaxgear.io.ratings_of`).
        whine, acoustics, lubricant, rating: the case file's ``[whine]``, ``[acoustics]``,
            ``[lubricant]`` and ``[rating]`` as typed sections, checked whole
            (:class:`jaxgear.io.WhineSection`, :class:`jaxgear.io.AcousticsSection`,
            :class:`jaxgear.io.LubricantSection`, :class:`jaxgear.io.RatingSection`, each a
            :class:`jaxgear.io.Section`: the file's keys, in file units),
            or None where the file has no such table; :func:`jaxgear.io.whine_of`,
            :func:`~jaxgear.io.acoustics_of`, :func:`~jaxgear.io.tribology_of` and
            :func:`~jaxgear.io.ratings_of` give their SI inputs.
        bearings: the case file's ``[bearings]`` (:class:`jaxgear.io.BearingsSection`: the
            rolling bearings' modified life settings), or None;
            :func:`~jaxgear.io.bearing_life_of` gives them in SI.
        input_files: the files the case was read from, absolute paths: its case file and the
            files it names (body files, a ring body file, a housing's ``mesh_file``, a
            gearbox's stage case files and theirs), set by :func:`jaxgear.io.load_case`; () for
            an embedded case or one built in Python. No command writes over one of them
            (:func:`jaxgear.cli._paths.check_case_outputs`).
    """

    name: str
    pairs: tuple
    gear_modifications: tuple
    gear_names: tuple = ("pinion", "gear")
    gears: tuple = ((0, 1),)
    angles: tuple = (0.0,)
    torque: float = 100.0
    loads: tuple = ()
    speed: float = 0.0
    inertias: tuple = ()
    shafts: tuple = ()
    clockings: tuple = ()
    hands: tuple = ()
    masses: tuple = ()
    wrenches: tuple = ()
    shaft_names: tuple = ()
    scene: Any = None
    housing: Any = None  # [housing]: a HousingSpec (docs/housing.md), lumped 3D scenes
    raw: dict = dataclasses.field(default_factory=dict, repr=False, compare=False)
    deviations: Any = None
    deviation_settings: dict | None = None
    coast: bool = False
    optimise: dict | None = None
    form: CaseForm = TrainForm()
    rating_standard: Any = None
    input_files: tuple = dataclasses.field(default=(), repr=False, compare=False)
    whine: Section | None = None
    acoustics: Section | None = None
    lubricant: Section | None = None
    rating: Section | None = None
    bearings: Section | None = None

    @classmethod
    def of_pair(cls, *, name: str, pair: GearPair, modifications: Modifications, **fields) -> Case:
        """A pair case: gears ``pinion`` and ``gear``, the one mesh ``pair`` with the
        ``modifications`` of its two members (:class:`PairForm`); ``fields``: the other
        attributes (keywords)."""
        return cls(
            name=name,
            pairs=(pair,),
            gear_modifications=(modifications.pinion, modifications.gear),
            form=PairForm(),
            **fields,
        )

    def _one_mesh(self, what: str) -> None:
        """Refuse a view of a one-mesh case on a case of several meshes, in one line."""
        if len(self.pairs) != 1:
            raise ValueError(
                f"case {self.name!r}: {what} is a one-mesh case's (a pair's); this case has "
                f"{len(self.pairs)} meshes: use pairs, mesh_modifications() or mesh_case(k)"
            )

    @property
    def pair(self) -> GearPair:
        """Its one mesh's :class:`~jaxgear.GearPair` (a pair case's).

        Raises:
            ValueError: a case of several meshes."""
        self._one_mesh("case.pair")
        return self.pairs[0]

    @property
    def modifications(self) -> Modifications:
        """Its one mesh's :class:`~jaxgear.Modifications` (pinion, gear; a pair case's).

        Raises:
            ValueError: a case of several meshes."""
        self._one_mesh("case.modifications")
        return self.mesh_modifications()[0]

    def replace(self, **changes) -> Case:
        """A copy with ``changes`` (field names as keywords); on a one-mesh case also ``pair``
        (its one mesh's :class:`~jaxgear.GearPair`) and ``modifications`` (its
        :class:`~jaxgear.Modifications`).

        Raises:
            ValueError: ``pair`` or ``modifications`` on a case of several meshes."""
        if "pair" in changes:
            self._one_mesh("replace(pair=...)")
            changes["pairs"] = (changes.pop("pair"),)
        if "modifications" in changes:
            self._one_mesh("replace(modifications=...)")
            m = changes.pop("modifications")
            changes["gear_modifications"] = (m.pinion, m.gear)
        return dataclasses.replace(self, **_contact_changes(changes))

    @property
    def n_gears(self) -> int:
        return len(self.gear_names)

    def mesh_name(self, k: int) -> str:
        """Mesh ``k``'s name: ``"driving-driven"``, the names of its gears (a pair's one mesh:
        the case's; :attr:`form`)."""
        return self.form.mesh_name(self, k)

    def mesh_label(self, k: int) -> str:
        """What tells mesh ``k`` apart in the outputs (file names, titles, per-mesh keys and
        warnings): a train's :meth:`mesh_name` (a pair case's one mesh has none, "")."""
        return self.form.mesh_label(self, k)

    @property
    def shaft_of(self) -> tuple:
        """Each gear's shaft index (n,): the rotation of the torsional train it turns with."""
        return tuple(self.shafts) if self.shafts else tuple(range(self.n_gears))

    @property
    def n_shafts(self) -> int:
        return max(self.shaft_of) + 1

    def shares(self) -> dict:
        """``{shaft: share}``: the share of the input power each loaded shaft takes, −T_j ω_j /
        (T ω_0) (:func:`jaxgear.scenes.torsional_train`); the balancing output takes the rest."""
        ratios = self.layout().ratios
        out = {}
        for g, t in self.loads:
            s = self.shaft_of[g]
            out[s] = out.get(s, 0.0) - t * ratios[g] / (self.torque * ratios[0])
        return out

    @property
    def span_periods(self) -> int:
        """Periods of the first mesh after which every mesh's cells repeat together (exact,
        from the tooth counts): 1 when every mesh passes teeth at the first's rate (an idler
        train); a two-stage train's span (:meth:`jaxgear.scenes.Scene.scene_periods`)."""
        return teeth_span(self.mesh_orders)

    @property
    def mesh_orders(self) -> tuple:
        """Each mesh's order: the teeth its driving gear passes per turn of the input (the first
        mesh's driving gear), z_g ω_g / ω_0, exact (:class:`fractions.Fraction`, (m,)), from the
        tooth counts (:func:`mesh_teeth_per_turn`): its mesh frequency is order × ω_0 / 2π (a
        pair's: the pinion's teeth)."""
        return mesh_teeth_per_turn(self.pairs, self.gears, self.shaft_of)

    @property
    def output(self) -> int:
        """The balancing output's shaft: the one shaft that drives no other and has no load."""
        drivers = {self.shaft_of[g] for g, _ in self.gears}
        shares = self.shares()
        free = [s for s in range(self.n_shafts) if s not in drivers and s not in shares]
        return free[0]

    @property
    def mesh_torques(self) -> tuple:
        """Each mesh's torque on its driving gear (N·m): the power the shafts beyond the mesh
        take (their shares; the balancing output the rest) over the driving gear's speed,
        T S_k ω_0 / ω_g (S_k: the shares of the driven gear's shaft and every shaft it drives,
        directly or not). In a chain with no load on its way the force is passed on: T_h =
        T_g r_b,h / r_b,g."""
        ratios = self.layout().ratios
        share = dict(self.shares())
        share[self.output] = 1.0 - sum(share.values())
        children = {}
        for g, h in self.gears:
            children.setdefault(self.shaft_of[g], []).append(self.shaft_of[h])

        def beyond(s):  # the share taken at shaft s and beyond it
            return share.get(s, 0.0) + sum(beyond(c) for c in children.get(s, ()))

        return tuple(
            self.torque * beyond(self.shaft_of[h]) * ratios[0] / ratios[g] for g, h in self.gears
        )

    def mesh_case(self, k: int) -> Case:
        """Mesh ``k`` as a one-mesh (pair) case: its pair (the driving gear as pinion), its
        driving gear's torque (:attr:`mesh_torques`) and speed, and the case's mesh settings; a
        pair case's one mesh is the case itself (:attr:`form`)."""
        return self.form.mesh_case(self, k)

    def mesh_modifications(self) -> tuple:
        """Each mesh's :class:`~jaxgear.Modifications` (its driving gear's, its driven gear's)."""
        m = self.gear_modifications
        return tuple(Modifications(m[g], m[h]) for g, h in self.gears)

    def layout(self):
        """The train laid out in the plane (:func:`jaxgear.scenes.train_layout`)."""
        return train_layout(
            self.pairs,
            self.gears,
            self.angles,
            self.n_gears,
            self.shaft_of,
            self.clockings or None,
            self.hands or None,
        )

    def members(self) -> tuple:
        """Each gear's :class:`~jaxgear.Member` (from the first mesh it takes part in)."""
        out = [None] * self.n_gears
        for pair, (g, h) in zip(self.pairs, self.gears, strict=True):
            out[g] = out[g] or pair.pinion
            out[h] = out[h] or pair.gear
        return tuple(out)

    def tip_radii(self) -> tuple:
        """Each gear's tip radius (m)."""
        out = [None] * self.n_gears
        for pair, (g, h) in zip(self.pairs, self.gears, strict=True):
            out[g] = out[g] or pair.tip_radii[0]
            out[h] = out[h] or pair.tip_radii[1]
        return tuple(out)

    def gear_inertias(self) -> tuple:
        """Each gear's polar inertia (kg·m²): the case's, or a solid disc of the tip radius and
        face width at the case's density."""
        members, radii = self.members(), self.tip_radii()
        return tuple(
            disc_inertia(self.density, radii[i], members[i].face_width) if j is None else j
            for i, j in enumerate(self.inertias or (None,) * self.n_gears)
        )

    def gear_masses(self) -> tuple:
        """Each gear body's mass (kg): the case's, or a solid disc ρ π r_a² b."""
        members, radii = self.members(), self.tip_radii()
        return tuple(
            self.density * math.pi * radii[i] ** 2 * members[i].face_width if m is None else m
            for i, m in enumerate(self.masses or (None,) * self.n_gears)
        )

    def mesh_models(self, slices: int | None = None, flexible: tuple = ()) -> tuple:
        """Each mesh's :class:`~jaxgear.MeshModel` (:meth:`mesh_model` of :meth:`mesh_case`);
        ``flexible``: which gears are condensed FE bodies (their tooth stiffness leaves out the
        foundation term), (n,) (default none)."""
        flex = tuple(flexible) or (False,) * self.n_gears
        return tuple(
            self.mesh_case(k).mesh_model(slices, flexible=(flex[g], flex[h]))
            for k, (g, h) in enumerate(self.gears)
        )

    def torsional_train(self, slices: int | None = None):
        """The train's torsional scene (:func:`jaxgear.scenes.torsional_train`): one rotation
        per shaft (:attr:`shaft_of`) with the inertia of its gears (:meth:`gear_inertias`), each
        mesh at its layout's phase, the loads' :meth:`shares`."""
        planes = self.mesh_models(slices)
        inertias = [0.0] * self.n_shafts
        for g, j in enumerate(self.gear_inertias()):
            inertias[self.shaft_of[g]] += j
        links = tuple((self.shaft_of[g], self.shaft_of[h]) for g, h in self.gears)
        return torsional_train(
            tuple(zip(planes, links, strict=True)),
            inertias,
            tuple(float(p) for p in self.layout().phases),
            self.shares(),
        )

    @property
    def flexible(self) -> bool:
        """The lumped 3D scene has condensed FE bodies (``[scene.bodies]``)."""
        return self.lumped and self.scene.hybrid

    def _lumped_args(self) -> dict:
        """The keyword arguments of :func:`~jaxgear.scenes.lumped_train` and
        :func:`~jaxgear.scenes.hybrid_train` from the case."""
        members = self.members()
        bodies = [
            (m, (j / 2 + m * members[i].face_width ** 2 / 12, j))
            for i, (m, j) in enumerate(zip(self.gear_masses(), self.gear_inertias(), strict=True))
        ]
        return dict(
            masses=[b[0] for b in bodies],
            inertias=[b[1] for b in bodies],
            shares=self.shares(),
            wrenches=tuple(
                Wrench(s, z, tuple(f / self.torque for f in F), tuple(m / self.torque for m in M))
                for s, z, F, M in self.wrenches
            ),
            shaft_names=self.shaft_names or None,
            youngs_modulus=self.youngs_modulus,
            poisson_ratio=self.poisson_ratio,
            density=self.density,
        )

    def lumped_train(self, slices: int | None = None, *, housing=None, seats=None,
                     housing_position=None):
        """The train's lumped 3D scene (:func:`jaxgear.scenes.lumped_train`): each shaft of
        ``[[scene.shafts]]`` on its bearings (a rolling bearing from its geometry at the
        case's operating point, :func:`jaxgear.io.operating_point`) with its gears (rigid discs of
        :meth:`gear_masses` and :meth:`gear_inertias`, diametral inertia I_p/2 + m b²/12), each
        mesh on its line of action with the layout's hands and phase, the loads' shares and the
        wrenches per unit input torque; on the case's ``[housing]`` if it has one.

        Args:
            slices: slices per contact line (None: the case's).
            housing: a :class:`jaxgear.scenes.Housing` placed by the caller, instead of the
                case's ``[housing]`` (None: the case's, if it has one).
            seats, housing_position: each bearing's seat and the scene origin's place in the
                housing's frame (m), as :func:`~jaxgear.scenes.lumped_train`'s.

        Raises:
            ValueError: the case has no lumped 3D scene, or what
                :func:`~jaxgear.scenes.lumped_train` refuses.
        """
        if not self.lumped:
            raise ValueError("a lumped 3D train needs [scene] model = 'lumped3d'")
        shafts = self.scene.shafts
        if self.scene.rolling:  # bearings from geometry: at the case's operating point
            shafts = operating_point(self).shafts  # (on the ground; docs/bearings.md)
        if housing is None and self.housing is not None:
            housing = self.housing_body().housing
        return lumped_train(self.train_spec(slices, shafts), housing, seats,
                            housing_position=housing_position)

    def train_spec(self, slices: int | None = None, shafts: tuple | None = None) -> TrainSpec:
        """The :class:`~jaxgear.scenes.TrainSpec` of the case's lumped 3D train
        (:meth:`lumped_train`'s) on ``shafts`` (each shaft's
        :class:`~jaxgear.scenes.ShaftSpec`, shaft order; None: ``[[scene.shafts]]`` as
        given, a rolling bearing without its operating point); ``slices`` per contact line
        (None: the case's)."""
        return TrainSpec(
            tuple(zip(self.mesh_models(slices), self.gears, strict=True)),
            self.layout(),
            self.scene.shafts if shafts is None else tuple(shafts),
            self.shaft_of,
            **self._lumped_args(),
        )

    def build_housing(self, shafts, centres, gear_z, *, cache=True):
        """The case's ``[housing]`` (:attr:`housing`) as a :class:`jaxgear.scenes.Housing`
        round the bearings of ``shafts`` (axes through ``centres``, the first gears at
        ``gear_z`` along them; :func:`jaxgear.scenes.bearing_positions`): meshed, condensed
        (cached) and damped (docs/housing.md)."""
        from ._housing_table import build_housing

        positions = bearing_positions(shafts, centres, gear_z)
        return build_housing(self.housing, shafts, positions, cache=cache)

    def housing_body(self, scene=None, *, cache=True):
        """The case's ``[housing]`` (:attr:`housing`) round the bearings of its lumped 3D scene
        (a pair's ``scene``, default ``[scene]``: its two shafts' axes through the line of
        action's centres; a train's ``[[scene.shafts]]``, each axis through its first gear's
        layout centre; a planetary stage's, which has no scene, the box round the stage axis,
        docs/planetary.md "In a case file"), as a
        :class:`~jaxgear.io.HousingBody`: the mesh, the condensed housing (cached) and the
        scene's :class:`jaxgear.scenes.Housing` (docs/housing.md).

        Raises:
            ValueError: the case has no ``[housing]``.
        """
        from ._housing_table import housing_body

        if self.housing is None:
            raise ValueError(f"case {self.name!r}: no [housing] table")
        if scene is None and self.scene is None:  # a planetary stage's (no [scene] to hold
            from ._housing_table import stage_housing  # a housing otherwise: case_housing)

            return stage_housing(self.housing, cache=cache)
        shafts, positions = self._bearing_layout(self.scene if scene is None else scene)
        return housing_body(self.housing, shafts, positions, cache=cache)

    def housing_size(self):
        """The estimated sizes of the case's ``[housing]`` before it is built
        (:func:`jaxgear.io._housing_table.housing_size`: cells, DOFs, modes, memory), laid out
        as :meth:`housing_body` lays it (a gearbox's: :meth:`CaseForm.own_housing_size`); None
        without ``[housing]`` or with a mesh file.

        Raises:
            SchemaError: a housing this machine cannot build (one line naming the key, the
                estimate and the limit).
        """
        from ._housing_table import housing_size

        if self.housing is None:
            return None
        own = self.form.own_housing_size()  # a gearbox's: round its housed stages' bearings
        if own is not None:
            return own
        if self.scene is None:  # a planetary stage's: the box round the stage axis
            return housing_size(self.housing, (), [[(0.0, 0.0, 0.0)]])
        return housing_size(self.housing, *self._bearing_layout(self.scene))

    def _bearing_layout(self, scene) -> tuple:
        """(shafts, positions): the lumped 3D ``scene``'s shafts (a pair's two, a train's
        ``[[scene.shafts]]``) and each one's bearings' scene positions
        (:func:`jaxgear.scenes.bearing_positions`: a pair's axes through the line of action's
        centres, a train's each through its first gear's layout centre)."""
        if isinstance(self.form, TrainForm):
            shafts = tuple(scene.shafts)
            first = [min(g for g, s in enumerate(self.shaft_of) if s == i)
                     for i in range(len(shafts))]
            centres = [self.layout().centres[g] for g in first]
        else:
            shafts = (scene.pinion_shaft, scene.gear_shaft)
            centres = line_of_action(self.pair)["centres"]
        gear_z = [s.gear_positions[0] for s in shafts]
        return shafts, bearing_positions(shafts, centres, gear_z)

    def hybrid_housing(self, *, cache=True) -> dict:
        """The ``housing`` and ``seats`` keywords of the case's hybrid scene
        (:func:`jaxgear.scenes.hybrid_pair`, :meth:`hybrid_train`) from its ``[housing]``
        (:meth:`housing_body`); ``{}`` without one. Each bearing sits in the housing's
        nearest seat, a condensed body's shaft's too (it meets its seats at its body frame's
        angle at θ = 0; docs/housing.md, "Hybrid scenes")."""
        if self.housing is None:
            return {}
        housing = self.housing_body(cache=cache).housing
        _, positions = self._bearing_layout(self.scene)
        seats = [housing.nearest_seat(p) for ps in positions for p in ps]
        return {"housing": housing, "seats": seats}

    def hybrid_train(
        self,
        bodies: tuple,
        slices: int | None = None,
        *,
        tooth_mass: bool = True,
        housing=None,
        seats=None,
        housing_position=None,
    ):
        """The train's lumped 3D scene with its flexible gears as condensed FE bodies
        (:func:`jaxgear.scenes.hybrid_train`; ``[scene.bodies]``), the output held; its meshes'
        tooth stiffness leaves out a flexible gear's foundation term.

        Args:
            bodies: each gear's condensed body or ``None`` (rigid), (n,)
                (:func:`jaxgear.io.load_bodies` of the case's scene).
            tooth_mass: lump the teeth's mass on the rim masters (default).
            housing, seats: a :class:`jaxgear.scenes.Housing` the shafts sit in
                and each bearing's seat, None for a bearing on the ground
                (:func:`~jaxgear.scenes.hybrid_train`; docs/housing.md, "Hybrid scenes").
            housing_position: with ``housing``, the scene origin's place in the housing's
                frame (m; :func:`~jaxgear.scenes.hybrid_train`'s).

        Raises:
            ValueError: the case has no lumped 3D scene, or what
                :func:`~jaxgear.scenes.hybrid_train` refuses.
        """
        if not self.lumped:
            raise ValueError("a hybrid train needs [scene] model = 'lumped3d'")
        flexible = tuple(b is not None for b in bodies)
        spec = TrainSpec(
            tuple(zip(self.mesh_models(slices, flexible), self.gears, strict=True)),
            self.layout(),
            self.scene.shafts,
            self.shaft_of,
            pairs=self.pairs,
            bodies=tuple(bodies),
            rims=self.scene.gear_rims or None,
            gear_names=self.gear_names,
            **self._lumped_args(),
        )
        return hybrid_train(spec, tooth_mass=tooth_mass, housing=housing, seats=seats,
                            housing_position=housing_position)

    def dynamic_train(self, slices: int | None = None):
        """The train's rigid-gear scene: :meth:`lumped_train` for a lumped 3D scene, else
        :meth:`torsional_train` (a train with flexible gears: :meth:`hybrid_train`, which needs
        their bodies; :func:`jaxgear.io.build_dynamic_model` loads them).

        Raises:
            ValueError: a train with flexible gears.
        """
        if self.flexible:
            raise ValueError(
                "[scene.bodies]: a train with flexible gears is a hybrid scene: "
                "case.hybrid_train(bodies) or jaxgear.io.build_dynamic_model(case)"
            )
        return self.lumped_train(slices) if self.lumped else self.torsional_train(slices)

    def static_train(self, slices: int | None = None, bodies: tuple | None = None):
        """The scene of the train's quasi-static solve: :meth:`dynamic_train` with the output
        shaft's rotation held by a spring (the output torque's reaction; the meshes' TE and
        loads do not depend on it); with flexible gears, :meth:`hybrid_train` of ``bodies``
        (which holds the output itself), on the case's ``[housing]`` if it has one
        (:meth:`hybrid_housing`).

        Raises:
            ValueError: flexible gears without their ``bodies``.
        """
        if self.flexible:
            if bodies is None:
                raise ValueError(
                    "static_train: the case has flexible gears ([scene.bodies]); pass their "
                    "condensed bodies (jaxgear.io.load_bodies(case.scene))"
                )
            return self.hybrid_train(bodies, slices, **self.hybrid_housing())
        train = self.dynamic_train(slices)
        return grounded(train, (train.torque_dofs[1],), factor=1e9)

    @property
    def normal_load(self) -> float:
        """Flank-normal mesh force F_n = T/(r_b1 cos β_b) (N) of a one-mesh case."""
        return self.torque / (self.pair.base_radii[0] * math.cos(self.pair.base_helix_angle))

    def nominal_line_load(self, torque: float | None = None) -> float:
        """Mean transverse load per unit face width, F_bt/(ε_α b) (N/m), for the Hertz term."""
        t = self.torque if torque is None else torque
        return (
            t
            / self.pair.base_radii[0]
            / (self.pair.transverse_contact_ratio * self.pair.face_width)
        )

    def specific_load(self, torque: float | None = None) -> float:
        """Nominal tangential load at the reference circle per unit face width, F_t / b =
        T / (r_1 b) (N/m), K_A = 1: the load of the ISO 6336-1 low-load factor (``iso6336``)."""
        t = self.torque if torque is None else torque
        return t / self.pair.pitch_radii[0] / self.pair.face_width

    def mesh_conditions(self, torque: float | None = None) -> MeshConditions:
        """The material and load :meth:`mesh_model`'s stiffness table is evaluated at: the
        case's E and ν, :meth:`nominal_line_load` and :meth:`specific_load` of ``torque``
        (N·m; default the case's)."""
        return MeshConditions(
            self.youngs_modulus,
            self.poisson_ratio,
            self.nominal_line_load(torque),
            self.specific_load(torque),
        )

    def mesh_model(
        self,
        slices: int | None = None,
        torque: float | None = None,
        flexible: tuple[bool, bool] = (False, False),
    ) -> MeshModel:
        """Build the :class:`~jaxgear.MeshModel` (stiffness table evaluated at the nominal line
        load; the ``iso6336`` table at the case's E and :meth:`specific_load` of ``torque``).

        ``flexible``: members that are condensed FE bodies (pinion, gear): their tooth stiffness
        leaves out the foundation term, which the FE rim replaces (seed remark after (2.31)).
        With :attr:`coast` the model holds the coast flanks too (docs/backlash.md).
        """
        s, k = stiffness_table(
            self.pair,
            self.stiffness.without_body(flexible),
            youngs_modulus=self.youngs_modulus,
            poisson_ratio=self.poisson_ratio,
            line_load=self.nominal_line_load(torque),
            specific_load=self.specific_load(torque),
        )
        return MeshModel.from_pair(
            self.pair,
            s,
            k,
            self.slices if slices is None else slices,
            coast=self.coast,
            contact_geometry=self.contact_geometry,
        )


#: the name the train case had before the one case type (a pair is a train of one mesh)
TrainCase = Case
