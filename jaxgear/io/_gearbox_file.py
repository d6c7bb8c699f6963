"""A gearbox case file: stages in series, each an embedded case or a case file, the operating
point given on the first stage's input and carried stage to stage by the stages' ratios
(lossless), the stages joined by shafts of given torsional stiffness::

    name = "my-gearbox"
    [operating]
    torque_Nm = 3.946e6                # on stage 1's input member
    speed_rad_s = 1.2671
    [[stages]]
    case = "nrel-5mw-planetary"        # an embedded case, or a case file (relative to this one)
    [[stages]]
    case = "nrel-5mw-stage2"
    shaft_Nm_per_rad = 1.26e9          # the shaft from the previous stage's output member
    [[stages]]
    case = "nrel-5mw-stage3"           # a pair: which gear the previous stage drives, its
    input = "gear"                     # gears' polar inertias and its mean mesh stiffness
    shaft_Nm_per_rad = 1.435e8
    pinion_inertia_kg_m2 = 3.75
    gear_inertia_kg_m2 = 921.0
    mesh_stiffness_N_per_um = 7668.0

A pair stage is torsional (two rotations, the inertias and mean mesh stiffness above) unless
``model = "lumped3d"``: then it is its case's lumped 3D scene (the pair case's ``[scene]`` with
``model = "lumped3d"``: its shafts, bearings and gear bodies, its own ``[housing]`` if any) as a
:class:`~jaxgear.gearbox.LumpedPairGearboxStage`, the gearbox's shafts joined at its shafts'
torque nodes; its inertias and mesh stiffness are the scene's (the three keys refused).

A gearbox-level ``[housing]`` (the keys of a pair's ``[housing]``,
:mod:`jaxgear.io._housing_table`) is one housing shared by every lumped 3D pair stage
(``model = "lumped3d"``), in the gearbox's frame: the first stage's scene frame, each stage's
scene origin at its ``housing_position_mm`` (3 numbers, mm; default the origin, the scene axes
parallel). A box is built round all those stages' bearings (a bore round each shaft in both end
walls: seats 0..A-1 in the -z wall, A..2A-1 in the +z wall, the A shafts in stage order,
pinion shaft first); ``housing_seats`` lists each of a stage's bearings' seat (its pinion
shaft's bearings, then its gear shaft's; -1 keeps one on the ground; default the nearest seat).
A planetary stage whose ring is held joins the box with ``housing_seat`` (the seat its ring is
bolted to) and ``housing_position_mm`` (its centre; its axis the gearbox frame's z): one more
axis of the box (a bore round it in both end walls, in stage order), the stage a
planetary stage of its kind on a :class:`~jaxgear.scenes.HousingMount` of the box (``mount=``),
its ring's torsional support on that seat. Every bore is the ``[housing]``'s ``bore_diameter_mm``
unless its stage gives ``housing_bore_diameter_mm`` (the bores round its axes: a lumped stage's two
shafts, a planetary stage's ring seat), each checked to lie within the end walls' inner faces and
clear of the other bores before the box is meshed. Torsional stages, and planetary stages without
``housing_seat``, stay on the ground.

A planetary stage's ``model`` is its kind in the coupled chain (:data:`PLANETARY_MODELS`:
``"torsional"``, the default, or ``"planar"``, whose translations read its case's radial
bearings and pins); the torsional chain's view is the torsional one for both. The stages'
coupled chain then has the housing's coordinates once
(:class:`~jaxgear.gearbox.GearboxTorsional`'s ``housing``).

A ``[whine]`` table (the keys and units of a pair's, :mod:`jaxgear.io._whine_table`; its
method ``"quasi-periodic"``, the default here: every stage meshes at its own frequency) asks
``jaxgear run`` for the whole coupled gearbox's whine (:func:`jaxgear.gearbox.gearbox_whine`), its
speeds the first stage's input member's, its ``positions_per_period`` per stage (the torus grid
has positions^G static solves, G the stages: at most :data:`MAX_WHINE_GRID`).

A planetary stage's input and output are its ``[planetary]`` table's; each stage's own
``[operating]`` is replaced by the carried one (a pair's torque and speed are its pinion's), also
for its ``[rating]``: ``jaxgear run`` rates every mesh of every stage that has one, each at the
carried point.

A ``[load_spectrum]`` table (the keys of a pair's ``[rating.spectrum]``,
:mod:`jaxgear.io._spectrum_table`, of the first stage's input member: its torque (N·m) and speed
(rpm) per bin with its hours, cycles (the input's turns) or time share, or a sampled history) is
the load spectrum of the whole chain: each bin carried stage to stage by the stages' ratios as
the operating point is (:meth:`GearboxForm.stage_spectrum`), under which ``jaxgear run`` gives
each rolling bearing of a ``model = "lumped3d"`` stage its lives by Palmgren–Miner
(:func:`jaxgear.io.bearing_spectrum_lives`; docs/gearbox.md, "Rolling bearings in a stage").
Allowed only with such a stage; the lives do not depend on the bins' total time, only on their
shares::

    [load_spectrum]                    # on stage 1's input member
    torque_Nm = [80.0, 60.0, 30.0]
    speed_rpm = [300.0, 286.5, 200.0]  # or one number for every bin
    time_share = [0.1, 0.6, 0.3]       # or hours = [...], cycles = [...]
"""

from __future__ import annotations

import dataclasses
import functools
import math
import os
from typing import Annotated, ClassVar, Literal

import numpy as np
import pydantic

from fem_prep import schema as sc

from ..dynamics import (
    MAX_WHINE_GRID,
    AbstractStage,
    QuasiPeriodicBalance,
    WhineSize,
    check_whine_size,
    whine_size,
)
from ..gearbox import (
    OPERATING_RUN,
    GearboxModel,
    GearboxRun,
    GearboxTorsional,
    LumpedPairGearboxStage,
    PairGearboxStage,
    PlanetaryGearboxStage,
    TorsionalPairGearboxStage,
)
from ..planetary import PlanarPlanetary, TorsionalPlanetary
from ..rating import LoadSpectrum
from ..scenes import (
    HOUSING_BAND,
    HousingMount,
    band_cutoff_hz,
    band_holds,
    housing_band_hz,
)
from ._case import Case, CaseForm, PairForm
from ._case_model import PAIR_SCENES, _case_model, dynamic_model_kind, whine_size_of
from ._housing_table import (
    HousedAxis,
    HousingBody,
    HousingSpec,
    check_box,
    check_housing_band,
    check_housing_points,
    housing_body,
    housing_size,
    parse_housing,
)
from ._planetary_spec import PlanetaryForm
from ._planetary_table import MESH_STIFFNESS_N_PER_UM, torque_floor
from ._plausibility import MIN_LINE_LOAD_N_PER_MM
from ._sections import NEEDED, Section, Text, in_range, number, number_list
from ._spectrum_table import parse_spectrum
from ._whine_table import (
    WhineInputs,
    WhineSection,
    highest_order_frequency,
    lowest_order_frequency,
)

__all__ = ["GearboxForm", "GearboxOperating", "GearboxStage", "StageEntry", "is_gearbox",
           "parse_gearbox"]

_KEYS = ("name", "operating", "stages", "whine", "housing", "load_spectrum")
#: the keys a planetary stage refuses (a pair stage's only)
_PAIR_KEYS = ("input", "pinion_inertia_kg_m2", "gear_inertia_kg_m2", "mesh_stiffness_N_per_um",
              "housing_seats")
#: a pair stage's ``input``: which gear the previous stage drives
PAIR_INPUTS = {"pinion": 0, "gear": 1}
#: a pair stage's ``model``: the torsional pair or its case's lumped 3D scene
PAIR_MODELS = ("torsional", "lumped3d")
#: a planetary stage's ``model``: its kind in the coupled chain (the torsional chain's view,
#: :meth:`~jaxgear.gearbox.PlanetaryGearboxStage.matrices`, is the torsional one for both)
PLANETARY_MODELS = {"torsional": TorsionalPlanetary(), "planar": PlanarPlanetary()}
#: the stage keys that seat a stage in the gearbox's ``[housing]``
_HOUSING_KEYS = ("housing_position_mm", "housing_seats", "housing_seat",
                 "housing_bore_diameter_mm")
#: the keys of a torsional pair stage only
_TORSIONAL_KEYS = ("pinion_inertia_kg_m2", "gear_inertia_kg_m2", "mesh_stiffness_N_per_um")


class GearboxOperating(Section):
    """A gearbox's ``[operating]``: the first stage's input torque (N·m; its floor follows the
    stages, :func:`_check_torque`) and speed (rad/s)."""

    WHERE: ClassVar[str] = "operating"
    torque_Nm: number("(0, 1e+09]")
    speed_rad_s: number("(0, 1e+05]")


class StageEntry(Section):
    """A ``[[stages]]`` entry (module docstring): its ``case``, the shaft from the previous
    stage (N·m/rad), a pair stage's ``input`` gear, torsional inertias (kg m²) and mean mesh
    stiffness (N/µm), its ``model`` (a pair's :data:`PAIR_MODELS`, a planetary stage's
    :data:`PLANETARY_MODELS`) and its seat in the gearbox's ``[housing]``. Which keys a stage
    takes follows its case's form and its place in the chain, checked by
    :func:`parse_gearbox`."""

    WHERE: ClassVar[str] = "stages[]"
    case: Text
    # required as the stage asks (NEEDED): the shaft after the first stage, a pair's input, a
    # torsional pair's inertias and mesh stiffness
    shaft_Nm_per_rad: Annotated[number("(0, 1e+15]") | None, NEEDED] = None
    input: Annotated[Literal[tuple(PAIR_INPUTS)] | None, NEEDED] = None
    pinion_inertia_kg_m2: Annotated[number("[1e-12, 1e+09]") | None, NEEDED] = None
    gear_inertia_kg_m2: Annotated[number("[1e-12, 1e+09]") | None, NEEDED] = None
    mesh_stiffness_N_per_um: Annotated[number(MESH_STIFFNESS_N_PER_UM) | None, NEEDED] = None
    model: Literal[tuple(dict.fromkeys((*PAIR_MODELS, *PLANETARY_MODELS)))] = "torsional"
    housing_position_mm: number_list(length=3) | None = None
    housing_seats: number_list(">= -1", integer=True,
                               note=" (a seat index per bearing; -1 on the ground)") | None = None
    housing_seat: number(">= 0", integer=True, note=" (the seat index of the gearbox's "
                         "[housing] the held ring is bolted to)") | None = None
    housing_bore_diameter_mm: number("(0, 1e+05]") | None = None

    @pydantic.field_validator("housing_seat", mode="before")
    @classmethod
    def _seat(cls, v, info):
        """``housing_seat`` refused in its words (an integral float as its integer)."""
        if not ((isinstance(v, int) and not isinstance(v, bool) or type(v) is float
                 and v.is_integer()) and v >= 0):
            raise sc.fail(info.context["where"], "housing_seat", "allowed an integer >= 0 (the "
                          "seat index of the gearbox's [housing] the held ring is bolted to)", v)
        return v

    def required(self, key: str, where: str):
        """A key the stage's kind requires."""
        if key not in self.given:
            raise sc.fail(where, key, "missing required key")
        return getattr(self, key)


@dataclasses.dataclass(frozen=True)
class GearboxStage:
    """One stage as the gearbox holds it: its case (its operating point the carried one),
    the ratio ω_in/ω_out, the input speed (rad/s) and torque (N·m) of its input member, the
    torsional stiffness of the shaft from the previous stage (N·m/rad; 0 for the first) and its
    torsional model in the chain (:class:`~jaxgear.dynamics.AbstractStage`; a lumped 3D stage
    on the ground); a lumped 3D stage in the gearbox's ``[housing]``: its scene origin in the
    gearbox frame ``housing_position`` (m) and its bearings' seats ``housing_seats`` (None:
    the nearest; an entry None: on the ground); a planetary stage in it: its centre
    ``housing_position`` (m; its axis the gearbox's z) and its held ring's seat ``housing_seat``
    (None: the ring on the ground); a housed stage's ``housing_bore_diameter`` (m): the box's
    bores round its axes (None: the ``[housing]``'s ``bore_diameter_mm``)."""

    case: Case
    ratio: float
    input_speed: float
    input_torque: float
    shaft_stiffness: float
    torsional: AbstractStage
    housing_position: tuple = (0.0, 0.0, 0.0)
    housing_seats: tuple | None = None
    housing_seat: int | None = None
    housing_bore_diameter: float | None = None

    @property
    def output_speed(self) -> float:
        return carried_through(self.ratio, self.input_speed, self.input_torque)[0]

    @property
    def output_torque(self) -> float:
        return carried_through(self.ratio, self.input_speed, self.input_torque)[1]


def carried_through(ratio: float, speed, torque) -> tuple:
    """(speed, torque) at a stage's output member from those at its input (rad/s, N·m; numbers
    or arrays of bins) and its ratio ω_in/ω_out, lossless: ω/ratio, T·ratio. The chain's one
    carrying rule: the operating point stage to stage, a pair's pinion driven from its gear
    (:func:`_pair_pinion`) and the ``[load_spectrum]``'s bins
    (:meth:`GearboxForm.stage_spectrum`)."""
    return speed / ratio, torque * ratio


def _pair_pinion(side: int, ratio: float, speed, torque) -> tuple:
    """(speed, torque) of a pair stage's pinion, the pair's own operating point, from the
    stage's input member's (``side`` 0: the pinion, 1: the gear, of ratio ω_in/ω_out)."""
    return (speed, torque) if side == 0 else carried_through(ratio, speed, torque)


@dataclasses.dataclass(frozen=True)
class GearboxForm(CaseForm):
    """A gearbox case file (``[[stages]]``): stages in series; its meshes (the case's
    ``pairs``) are its stages' meshes in order, each named ``stage<i>:<the stage's name of it>``
    (i from 1) and given as a pair case by its stage (:meth:`mesh_case`); ``whine``: its
    ``[whine]`` (:class:`~jaxgear.io.WhineInputs`, a
    :class:`~jaxgear.dynamics.QuasiPeriodicBalance`) or None; ``housing``: its ``[housing]``
    (:class:`~jaxgear.io.HousingSpec`, shared by its lumped 3D stages and its planetary
    stages with ``housing_seat``) or None; ``spectrum``: its ``[load_spectrum]``, the first
    stage's input member's bins (:class:`jaxgear.rating.LoadSpectrum`: torque N·m, speed
    rad/s, time s) or None."""

    stages: tuple[GearboxStage, ...]
    whine: WhineInputs | None = None
    housing: HousingSpec | None = None
    spectrum: LoadSpectrum | None = None

    def stage_name(self, i: int) -> str:
        """Stage ``i``'s name in the outputs: ``stage<i + 1>``."""
        return f"stage{i + 1}"

    def _where(self, k: int) -> tuple[Case, int, int]:
        for i, s in enumerate(self.stages):
            if k < len(s.case.pairs):
                return s.case, k, i
            k -= len(s.case.pairs)
        raise IndexError(f"mesh {k}: the gearbox has fewer meshes")

    def mesh_name(self, case: Case, k: int) -> str:
        stage, j, i = self._where(k)
        return f"{self.stage_name(i)}:{stage.form.mesh_name(stage, j)}"

    def mesh_label(self, case: Case, k: int) -> str:
        return self.mesh_name(case, k)

    def mesh_case(self, case: Case, k: int) -> Case:
        stage, j, _ = self._where(k)
        return stage.form.mesh_case(stage, j)

    def ratio(self) -> float:
        """The overall ratio ω_in/ω_out: the stages' product."""
        out = 1.0
        for s in self.stages:
            out *= s.ratio
        return out

    def stage_spectrum(self, k: int) -> LoadSpectrum:
        """The gearbox's ``[load_spectrum]`` at stage ``k``'s operating member (0-based): each
        bin's input torque and speed carried through the stages before it
        (:func:`carried_through`, the operating point's rule) to the stage's input, a pair
        stage's then to its pinion (the pair's own operating point); the bins' times
        unchanged. (k,) bins of torque (N·m), speed (rad/s) and time (s).

        Raises:
            ValueError: the gearbox has no ``[load_spectrum]``; ``k`` not a stage (one line).
        """
        if self.spectrum is None:
            raise ValueError("GearboxForm.stage_spectrum: the gearbox has no [load_spectrum]")
        if not 0 <= k < len(self.stages):
            raise ValueError(f"GearboxForm.stage_spectrum: k = {k}: allowed 0..."
                             f"{len(self.stages) - 1} (the gearbox's stages)")
        speed = np.asarray(self.spectrum.speed, float)
        torque = np.asarray(self.spectrum.torque, float)
        for s in self.stages[:k]:
            speed, torque = carried_through(s.ratio, speed, torque)
        s = self.stages[k]
        if isinstance(s.case.form, PairForm):
            speed, torque = _pair_pinion(s.torsional.input, s.ratio, speed, torque)
        return LoadSpectrum(torque, speed, np.asarray(self.spectrum.duration, float))

    def torsional(self) -> GearboxTorsional:
        """The chain's torsional model (:class:`~jaxgear.gearbox.GearboxTorsional`)."""
        return GearboxTorsional(
            tuple(s.torsional for s in self.stages),
            tuple(s.shaft_stiffness for s in self.stages[1:]),
        )


    def housed(self) -> tuple[int, ...]:
        """The stages seated in the gearbox's ``[housing]``: its lumped 3D stages and its
        planetary stages with ``housing_seat`` (none without one)."""
        if self.housing is None:
            return ()
        return tuple(k for k, s in enumerate(self.stages) if _in_housing(s))

    @functools.cached_property
    def housing_body(self) -> HousingBody:
        """The gearbox's ``[housing]`` round its housed stages' bearings in the gearbox frame
        (the first stage's scene frame): meshed, condensed (fem_prep's cache) and damped
        (:func:`jaxgear.io._housing_table.housing_body`); built once per form.

        Raises:
            ValueError: the gearbox has no ``[housing]``.
        """
        if self.housing is None:
            raise ValueError("GearboxForm.housing_body: the gearbox has no [housing] table")
        shafts, positions, diameters, _ = _housed_bearings(self)
        return housing_body(self.housing, shafts, positions, diameters=diameters)

    def own_housing_size(self):
        """The estimated sizes of the gearbox's ``[housing]`` round its housed stages'
        bearings (:func:`jaxgear.io._housing_table.housing_size`), None without one or with a
        mesh file.

        Raises:
            SchemaError: a housing this machine cannot build (one line)."""
        if self.housing is None:
            return None
        return housing_size(self.housing, *_housed_bearings(self)[:3])

    def coupled(self, slices: int = 1) -> GearboxTorsional:
        """The chain with every stage on its contact cells, for the coupled dynamic model
        (:func:`jaxgear.gearbox.gearbox_dynamics`): a planetary stage's
        :meth:`~jaxgear.io.PlanetaryForm`'s dynamic meshes (its pairs' own models, phased per
        planet; the torsional model), a pair's :meth:`~jaxgear.io.Case.mesh_model` and its
        modifications, ``slices`` slices per contact line; with ``[housing]`` the one shared
        housing (:attr:`housing_body`'s, placed once in the gearbox frame), which the chain keeps
        once: a lumped 3D stage its case's scene on it, its scene origin
        at its ``housing_position`` there; a planetary stage with ``housing_seat`` its
        ``model`` kind (:data:`PLANETARY_MODELS`) on a :class:`~jaxgear.scenes.HousingMount` of
        it on the stage axis through its ``housing_position``
        (:meth:`~jaxgear.scenes.HousingMount.on_axis`), its ring's torsional support joined to
        that seat."""
        stages = []
        housed = self.housed()
        shared = self.housing_body.housing if housed else None  # placed in the gearbox frame
        for k, s in enumerate(self.stages):
            t = s.torsional
            housing = shared if k in housed else None
            if isinstance(t, PlanetaryGearboxStage):
                meshes = s.case.form.spec.dynamic_meshes(s.case, slices)
                mount = (None if housing is None else
                         HousingMount.on_axis(housing, (("ring", s.housing_seat),),
                                              centre=s.housing_position))
                stages.append(PlanetaryGearboxStage(t.stage, t.input, t.output, meshes,
                                                    model=t.model, mount=mount))
            elif isinstance(t, LumpedPairGearboxStage):
                stages.append(lumped_stage(s.case, t.input, slices, housing, s.housing_seats,
                                           None if housing is None else s.housing_position))
            else:
                # the pair's own dynamic model on its cells (its chain view the given spring)
                stages.append(TorsionalPairGearboxStage(t.inertias, t.base_radii,
                                                        t.mesh_stiffness, t.input,
                                                        s.case.mesh_model(slices),
                                                        s.case.modifications))
        return GearboxTorsional(tuple(stages), self.torsional().shaft_stiffnesses,
                                housing=shared)


    def output_hold(self) -> float:
        """The torsional spring (N m/rad) that holds the last stage's output in the coupled
        model: the last shaft's stiffness (the generator is not in the chain); 1e9 for a
        single stage."""
        shafts = [s.shaft_stiffness for s in self.stages[1:]]
        return float(shafts[-1]) if shafts else 1e9

    def dynamic_model(self, slices: int = 1) -> GearboxModel:
        """The coupled model at the case's operating point (:class:`~jaxgear.gearbox.GearboxModel`
        of :meth:`coupled` with ``slices`` slices per contact line): the first stage's input
        torque, :meth:`output_hold`, and the plan constants of
        :data:`~jaxgear.gearbox.OPERATING_RUN`; its speed is the first stage's input speed."""
        first = self.stages[0]
        run = GearboxRun(first.input_torque, self.output_hold(), **OPERATING_RUN)
        return GearboxModel(self.coupled(slices), run)


@_case_model.register
def _(form: GearboxForm, case: Case, spec, slices: int | None, bodies: tuple | None):
    return form.dynamic_model(1 if slices is None else int(slices))


@dynamic_model_kind.register
def _(form: GearboxForm, case: Case):
    return GearboxModel


@whine_size_of.register
def _(form: GearboxForm, case: Case, inputs, kind) -> WhineSize:
    """A gearbox's ``[whine]`` size, from its stages (checked at load already)."""
    return _check_whine_size(inputs, form.stages)


def _in_housing(stage: GearboxStage) -> bool:
    """A stage seated in its gearbox's ``[housing]``: a lumped 3D stage, a planetary stage
    with ``housing_seat``."""
    return (isinstance(stage.torsional, LumpedPairGearboxStage)
            or stage.housing_seat is not None)


def _housed_bearings(form: GearboxForm):
    """(shafts, bearing positions, bore diameters, stage indices) of the housed stages in the
    gearbox frame, axis after axis in stage order (:meth:`jaxgear.io.Case._bearing_layout`
    moved by each stage's ``housing_position``; a housed planetary stage one axis, its centre,
    and no shaft), each axis's bore diameter its stage's ``housing_bore_diameter`` (None: the
    ``[housing]``'s) and its stage's index."""
    shafts, positions, diameters, owners = [], [], [], []
    for k in form.housed():
        s = form.stages[k]
        if s.housing_seat is not None:  # a planetary stage: its axis through its centre
            pos = [[np.asarray(s.housing_position, dtype=float)]]
        else:
            sh, pos = s.case._bearing_layout(s.case.scene)
            shafts += list(sh)
            pos = [[np.asarray(p) + np.asarray(s.housing_position) for p in ps] for ps in pos]
        positions += pos
        diameters += [s.housing_bore_diameter] * len(pos)
        owners += [k] * len(pos)
    return shafts, positions, diameters, owners


def is_gearbox(data: dict) -> bool:
    """A gearbox case file: it has ``[[stages]]``, or only a gearbox file's other keys (a
    gearbox whose stages are missing, refused by :func:`parse_gearbox` in its own words)."""
    return "stages" in data or (
        isinstance(data, dict) and bool(set(data) - {"name"}) and set(data) <= set(_KEYS)
    )


@functools.singledispatch
def _stage(form, case: Case, table: StageEntry, where: str, speed: float, torque: float):
    """(case at the carried point, ratio, torsional stage) of a stage of ``form``."""
    raise sc.fail(where, "case", f"a stage must be a planetary or a pair case, not {case.name!r}")


@_stage.register
def _(form: PlanetaryForm, case: Case, table: StageEntry, where: str, speed: float,
      torque: float):
    extra = sorted(table.given & set(_PAIR_KEYS))
    if extra:
        raise sc.fail(where, extra[0], "only for a pair stage", getattr(table, extra[0]))
    spec = form.spec
    model = table.model
    if model not in PLANETARY_MODELS:
        raise sc.fail(where, "model", "only for a pair stage (a planetary stage's model: allowed "
                      + ", ".join(repr(m) for m in PLANETARY_MODELS) + ")", model)
    kind = PLANETARY_MODELS[model]
    model = PlanetaryGearboxStage(spec.stage(case), spec.input, spec.output, model=kind)
    return _carried(case, speed, torque), spec.ratio(), model


def lumped_stage(case: Case, side: int, slices: int | None = None, housing=None,
                 seats=None, position=None) -> LumpedPairGearboxStage:
    """A pair case's lumped 3D scene (its ``[scene]``, ``model = "lumped3d"``; on ``housing``
    with ``seats``, its scene origin at ``position`` (m) in the housing's frame
    (:func:`~jaxgear.scenes.lumped_pair`'s ``housing_position``), else on its ``[housing]`` if
    any) as a :class:`~jaxgear.gearbox.LumpedPairGearboxStage` driven on ``side`` (0 the
    pinion shaft), its mesh at ``slices`` slices (None: the case's), its cells' separations
    the case's modifications."""
    scene = PAIR_SCENES["lumped3d"](case, case.scene, case.mesh_model(slices), housing, seats,
                                    position)
    return LumpedPairGearboxStage(scene, input=side, modifications=case.modifications)


def _spectrum(case: Case) -> bool:
    """The case's ``[rating]`` has a load spectrum (``[rating.spectrum]``, its typed
    :class:`~jaxgear.io._rating_table.RatingSection`'s ``spectrum``)."""
    return case.rating is not None and case.rating.spectrum is not None


def _lumped(case: Case, table: StageEntry, where: str, side: int) -> LumpedPairGearboxStage:
    """``model = "lumped3d"``: the torsional keys refused, the case's scene required. ``case``
    is the stage case carried to the chain's operating point (:func:`_carried`): its rolling
    bearings from their geometry stand at that point, its pinion's torque as the chain gives
    it (:func:`jaxgear.io.operating_point`, the pair case's fixed point, on the ground: a
    gearbox's ``[housing]`` rigid there, as a housed pair's); refused with a rating spectrum
    (its bins are the stage's own torques)."""
    for key in _TORSIONAL_KEYS:
        if key in table.given:
            raise sc.fail(where, key, 'only for model = "torsional" (a lumped 3D stage\'s '
                          "inertias and mesh stiffness are its case's [scene] and [mesh])",
                          getattr(table, key))
    if case.scene is None or not case.lumped or case.flexible:
        has = ("no [scene]" if case.scene is None else f"[scene] model = {case.scene.model!r}"
               + (" with condensed bodies" if case.flexible else ""))
        raise sc.fail(where, "model", "allowed with a stage case whose [scene] has model = "
                      f'"lumped3d" without condensed bodies (case {case.name!r}: {has})',
                      "lumped3d")
    if case.scene.rolling and _spectrum(case):  # its bins are the stage's own torques
        raise sc.fail(where, "model", "not with a stage case on rolling bearings from their "
                      f"geometry under a load spectrum (case {case.name!r}: [rating.spectrum]): "
                      "its bins' torques are the stage's own, not the chain's; allowed such a "
                      "stage case without [rating.spectrum], the gearbox's [load_spectrum] "
                      "carried to it", "lumped3d")
    try:
        return lumped_stage(case, side)
    except ValueError as err:  # coast flanks, a seat the scene refuses
        raise sc.fail(where, "model", str(err), "lumped3d") from None


@_stage.register
def _(form: PairForm, case: Case, table: StageEntry, where: str, speed: float, torque: float):
    side = PAIR_INPUTS[table.required("input", where)]
    kind = table.model
    if kind not in PAIR_MODELS:
        raise sc.fail(where, "model", f"allowed {', '.join(repr(m) for m in PAIR_MODELS)}", kind)
    pair = case.pair
    z = (pair.pinion.teeth, pair.gear.teeth)
    ratio = z[1 - side] / z[side]  # ω_in/ω_out
    # the pair's own operating point is its pinion's
    pinion = _pair_pinion(side, ratio, speed, torque)
    if kind == "lumped3d":
        staged = _carried(case, *pinion)
        return staged, ratio, _lumped(staged, table, where, side)
    inertias = [table.required(f"{g}_inertia_kg_m2", where) for g in ("pinion", "gear")]
    k_mesh = table.required("mesh_stiffness_N_per_um", where)
    model = PairGearboxStage(inertias, pair.base_radii, k_mesh * 1e6, input=side)
    return _carried(case, *pinion), ratio, model


def _stage_floor(stage: GearboxStage) -> float:
    """The least input torque (N·m) of a stage that strains its meshes measurably: a
    planetary stage's :func:`torque_floor`, a pair's line load of ``MIN_LINE_LOAD_N_PER_MM``
    on its pinion (:func:`jaxgear.io._case_file.parse_torque`), carried to the stage's input
    (the wheel's: over the ratio's inverse)."""
    case = stage.case
    if isinstance(case.form, PlanetaryForm):
        return torque_floor(case.form.spec, case.pairs)[0]
    pair = case.pair
    pinion = (MIN_LINE_LOAD_N_PER_MM * 1e3 * pair.face_width * pair.base_radii[0]
              * math.cos(pair.base_helix_angle))
    return pinion / stage.ratio if stage.torsional.input == 1 else pinion


def _check_torque(op: GearboxOperating, stages: list) -> None:
    """The gearbox's ``[operating] torque_Nm`` at least the torque that carries each stage's
    own floor (:func:`_stage_floor`) to it: stage k's input torque is the gearbox's times the
    ratios before it (lossless); one line."""
    floors, carried = [], 1.0
    for s in stages:
        floors.append(_stage_floor(s) / carried)
        carried *= s.ratio
    k = max(range(len(floors)), key=floors.__getitem__)
    in_range("operating", "torque_Nm", op.torque_Nm, f"[{float(f'{floors[k]:.3g}'):.3g}, 1e+09]",
             f" (stage {k + 1}'s floor: its meshes strained measurably)")


def _carried(case: Case, speed: float, torque: float) -> Case:
    """The stage's case at the carried operating point: its torque and speed, and its file's
    ``[operating]`` (which its ``[rating]`` reads: a pair's rating speed and torque) replaced by
    them (``speed_rpm`` dropped)."""
    raw = dict(case.raw)
    raw["operating"] = {"torque_Nm": torque, "speed_rad_s": speed}
    return case.replace(speed=speed, torque=torque, raw=raw)


def _stage_case(value: str, base: str | None, load_case, where: str) -> Case:
    path = os.path.join(base, value) if base is not None else value
    try:
        return load_case(path if base is not None and os.path.isfile(path) else value)
    except FileNotFoundError as err:  # a missing stage file is the gearbox file's error
        raise sc.fail(where, "case", str(err)) from None


def _whine(table, n_stages: int) -> WhineInputs:
    """A gearbox's ``[whine]``: the pair's table (:func:`parse_whine`), its method
    ``"quasi-periodic"`` (the default here), the torus grid positions^G <= :data:`MAX_WHINE_GRID`
    (G the stages: every stage of the coupled chain is on its contact cells)."""
    if isinstance(table, dict) and "method" not in table:
        table = {**table, "method": "quasi-periodic"}
    inputs = WhineSection.read(table).inputs()
    if not isinstance(inputs.method, QuasiPeriodicBalance):
        raise sc.fail("whine", "method", 'allowed "quasi-periodic" in a gearbox (each stage '
                      "meshes at its own frequency)", table["method"])
    P = inputs.positions
    if isinstance(P, tuple):  # one per stage: the torus grid is their product
        if len(P) != n_stages:
            raise sc.fail("whine", "positions_per_period", f"allowed one integer, or a list of "
                          f"{n_stages} (one per stage)", list(P))
        low = 4 * inputs.method.harmonics + 1
        if min(P) < low:
            raise sc.fail("whine", "positions_per_period", f"out of range, allowed >= 4 harmonics "
                          f"+ 1 = {low} per stage's mesh period", list(P))
        if math.prod(P) > MAX_WHINE_GRID:
            raise sc.fail("whine", "positions_per_period",
                          f"out of range: {math.prod(P)} static solves on the torus grid, allowed "
                          f"at most {MAX_WHINE_GRID:.0e}", list(P))
        return inputs
    if P**n_stages > MAX_WHINE_GRID:
        top = math.floor(MAX_WHINE_GRID ** (1.0 / n_stages) + 1e-9)
        low = 4 * inputs.method.harmonics + 1
        raise sc.fail("whine", "positions_per_period",
                      f"out of range for {n_stages} stages: allowed [{low}, {top}] "
                      f"(positions^{n_stages} static solves on the torus grid, at most "
                      f"{MAX_WHINE_GRID:.0e})", P)
    return inputs


def _check_whine_size(inputs: WhineInputs, stages) -> WhineSize:
    """The gearbox whine's size before any work (:func:`jaxgear.dynamics.whine_size`: G = the
    stages' mesh-frequency groups, the torus grid of their periods, the coordinates its meshes
    span bounded per stage: 12 for a lumped 3D pair, 3 per member (sun, carrier, ring,
    planets) for a planetary stage, 2 for a torsional pair), refused in one line as a pair's
    (:func:`jaxgear.dynamics.check_whine_size`); returns the size."""
    r = 0
    for s in stages:
        if isinstance(s.torsional, PlanetaryGearboxStage):
            r += 3 * (s.case.form.spec.n_planets + 3)
        else:
            r += 12 if isinstance(s.torsional, LumpedPairGearboxStage) else 2
    P, G = inputs.positions, len(stages)
    grid = math.prod(P) if isinstance(P, tuple) else P**G
    size = whine_size(len(inputs.speeds), inputs.method, grid, r, r, G)
    try:
        check_whine_size(size, ("[whine] speeds", "harmonics", "positions_per_period"),
                         (len(inputs.speeds), inputs.method.harmonics,
                          list(P) if isinstance(P, tuple) else P))
    except ValueError as err:
        raise sc.SchemaError(str(err)) from None
    return size


def parse_gearbox(data: dict, default_name: str, base: str | None, load_case) -> Case:
    """Validate a gearbox case file (module docstring) and build its :class:`Case`: the first
    stage's case, named by the file, of form :class:`GearboxForm`. ``load_case``: how a stage's
    ``case`` is loaded (:func:`jaxgear.io.load_case`).

    Raises:
        SchemaError: an unknown key, a stage without ``case``, a pair key on a planetary stage,
            ``model`` not one of :data:`PAIR_MODELS`, ``"lumped3d"`` with a torsional key or
            a stage case without a lumped 3D ``[scene]``,
            a planetary stage's ``model`` not one of :data:`PLANETARY_MODELS`,
            a shaft stiffness out of (0, 1e15] N·m/rad (the first stage has none), a stage that
            is not a planetary stage or a pair, a stage ``case`` that is neither a file nor an
            embedded case, a ``[whine]`` key out of range (its method not "quasi-periodic",
            its torus grid over :data:`MAX_WHINE_GRID`), a housing key without ``[housing]`` or
            on a stage that cannot take it, ``housing_seats`` of the wrong count, a seat beyond
            the box's, a ring's ``housing_seat`` a lumped stage's bearing takes, a
            ``housing_bore_diameter_mm`` not positive, with a mesh file's ``[housing]`` or whose
            bore does not fit (:func:`_check_bores`; a gearbox ``bore_diameter_mm`` alike), a
            ``[load_spectrum]`` its reader refuses (as a pair's ``[rating.spectrum]``, before
            any stage is built) or in a gearbox without a ``model = "lumped3d"`` stage on
            rolling bearings; one line each.
    """
    sc.check_keys(data, _KEYS, "")
    sc.subtables(data, ("whine", "housing", "load_spectrum"), "")  # before their readers
    name = sc.name(data, "name", "", default_name)
    op = GearboxOperating.of_file(data, required=True)
    torque, speed = op.torque_Nm, op.speed_rad_s
    spectrum = None  # its bins checked before any stage is built
    if "load_spectrum" in data:
        spectrum = parse_spectrum(data["load_spectrum"], SPECTRUM_TIME, "load_spectrum")
    if "stages" not in data:
        raise sc.SchemaError(
            "[[stages]]: missing; a gearbox file lists its stages in order, each a [[stages]] "
            'table with case = "<a pair case or a planetary stage>" (a pair case file has [pair], '
            "[pinion] and [gear] instead)"
        )
    raw = sc.table_array(data, "stages", "")
    if not raw:
        raise sc.fail("", "stages", "must be a non-empty array of tables ([[stages]])", raw)
    tables = [StageEntry.read(t, f"stages[{k}]") for k, t in enumerate(raw)]
    stages = []
    for k, t in enumerate(tables):
        where = f"stages[{k}]"
        case = _stage_case(t.case, base, load_case, where)
        if k == 0 and "shaft_Nm_per_rad" in t.given:
            raise sc.fail(where, "shaft_Nm_per_rad", "the first stage has no shaft before it")
        shaft = 0.0 if k == 0 else t.required("shaft_Nm_per_rad", where)
        if stages and stages[-1].ratio < 0:  # the chain carries each stage's drive direction
            raise sc.fail(f"stages[{k - 1}]", "case", "a stage whose output turns against its "
                          "input (a star stage: ratio < 0) is allowed only as the last stage",
                          stages[-1].case.name)
        staged, ratio, model = _stage(case.form, case, t, where, speed, torque)
        place = _placement(t, where, "housing" in data, staged, model)
        stages.append(GearboxStage(staged, ratio, speed, torque, shaft, model, *place))
        speed, torque = stages[-1].output_speed, stages[-1].output_torque
    _check_torque(op, stages)
    whine = _whine(data["whine"], len(stages)) if "whine" in data else None
    if whine is not None:
        _check_whine_size(whine, stages)
    first = stages[0].case
    housing = None
    if "housing" in data:
        top = low = None
        if whine is not None:  # the whine's groups: orders 1..H of each stage's frequency
            teeth = _stage_teeth(stages, data["operating"])
            names = [f"stage{k + 1}" for k in range(len(stages))]
            top = highest_order_frequency(whine, teeth, names=names)
            low = lowest_order_frequency(whine, teeth, names=names)
        housing = parse_housing(data["housing"], base,
                                (first.youngs_modulus, first.poisson_ratio, first.density), top)
        _check_seats(stages, housing)
        # the band must hold every stage's mesh frequency at the operating speed, and so (a
        # weaker rule) the lowest order the [whine] writes
        _check_band(stages, data["operating"], housing, data["housing"])
        if low is not None:
            check_housing_band(housing, low)
    if spectrum is not None:
        _check_spectrum_stages(stages)
    pairs = tuple(p for s in stages for p in s.case.pairs)
    form = GearboxForm(tuple(stages), whine, housing, spectrum)
    if housing is not None:
        _check_bores(form)
        form.own_housing_size()  # refused here if too large to build
    # the gearbox's own tables: its [whine] (a gearbox file has no [acoustics], [lubricant]
    # or [rating]; its stages' cases keep theirs)
    section = None if whine is None else WhineSection.read(
        {"method": "quasi-periodic", **data["whine"]})
    return first.replace(name=name, form=form, raw=data, scene=None, pairs=pairs,
                         housing=housing, whine=section, acoustics=None, lubricant=None,
                         rating=None)


#: the time the ``[load_spectrum]``'s ``time_share`` and sampled history are scaled to (s): the
#: bearings' lives under it do not depend on it (Palmgren–Miner: the bins' shares only)
SPECTRUM_TIME = 3600.0


def _check_spectrum_stages(stages) -> None:
    """The gearbox's ``[load_spectrum]`` (module docstring; read by
    :func:`~jaxgear.io._spectrum_table.parse_spectrum` as a pair's ``[rating.spectrum]``, its
    bins the first stage's input member's) allowed with a ``model = "lumped3d"`` stage on
    rolling bearings from their geometry only (whose lives it is for); one line."""
    if not any(isinstance(s.torsional, LumpedPairGearboxStage) and s.case.scene.rolling
               for s in stages):
        raise sc.fail("", "load_spectrum", 'allowed with a model = "lumped3d" stage on rolling '
                      "bearings from their geometry only (their lives under it); this gearbox "
                      "has none")


def _stage_teeth(stages, op: dict) -> list[float]:
    """Each stage's mesh frequency per turn of the gearbox's input (its teeth per input turn,
    :func:`jaxgear.gearbox.mesh_frequencies` at 2π rad/s): a planetary stage's in its carrier's
    frame (:meth:`~jaxgear.io.PlanetarySpec.mesh_frequency` at its carried input speed), a
    pair's its pinion's teeth at its carried pinion speed; over the gearbox's input speed."""
    out = []
    for s in stages:
        c = s.case
        if isinstance(c.form, PlanetaryForm):
            f = c.form.spec.mesh_frequency(s.input_speed)
        else:
            f = c.pair.pinion.teeth * c.speed / (2 * math.pi)
        out.append(2 * math.pi * f / op["speed_rad_s"])
    return out


def _check_band(stages, op: dict, spec: HousingSpec, table: dict) -> None:
    """The housing's band, cut-off / :data:`~jaxgear.scenes.HOUSING_BAND`, holds every stage's
    mesh frequency at the gearbox's operating speed (order 1; :func:`_stage_teeth`;
    :func:`jaxgear.scenes.band_holds`): the
    housing modes the meshes excite are in the condensed model (a cut-off below it keeps
    none of them). One line naming the key the cut-off came from, its value and the least
    cut-off allowed."""
    f = [t * op["speed_rad_s"] / (2 * math.pi) for t in _stage_teeth(stages, op)]
    k = max(range(len(f)), key=f.__getitem__)
    if band_holds(spec.cutoff, f[k]):  # the housing's rule
        return
    need = band_cutoff_hz(f[k])
    why = (f"the housing's band, cut-off / {HOUSING_BAND:g} = {housing_band_hz(spec.cutoff):.4g} "
           f"Hz, leaves out stage {k + 1}'s mesh frequency at [operating] speed_rad_s = "
           f"{op['speed_rad_s']:g}, {f[k]:.4g} Hz (the housing's modes it excites would be "
           "missing from the model)")
    if "cutoff_Hz" in table:
        raise sc.fail("housing", "cutoff_Hz", f"{why}: allowed >= {need:.4g} Hz "
                      f"({HOUSING_BAND:g} x it)", spec.cutoff)
    if "highest_mesh_frequency_Hz" in table:
        raise sc.fail("housing", "highest_mesh_frequency_Hz", f"{why}: allowed >= {f[k]:.4g} "
                      "Hz", table["highest_mesh_frequency_Hz"])
    raise sc.fail("housing", "cutoff_Hz", f"{why}; the cut-off derived from {spec.cutoff_source}"
                  f" is {spec.cutoff:.4g} Hz: give cutoff_Hz >= {need:.4g} Hz")


def _placement(table: StageEntry, where: str, has_housing: bool, case: Case, model) -> tuple:
    """A stage's ``housing_position_mm`` (m), ``housing_seats`` (None for -1),
    ``housing_seat`` and ``housing_bore_diameter_mm`` (m; in (0, 1e5] mm, whether it fits
    is :func:`_check_bores`'): only in a gearbox with ``[housing]``, on a stage whose case has
    no ``[housing]`` of its own; ``housing_seats`` on a lumped 3D stage (one per bearing of its
    scene, each an integer >= -1), ``housing_seat`` on a planetary stage whose ring is held (an
    integer >= 0; the other keys there only with it)."""
    lumped = isinstance(model, LumpedPairGearboxStage)
    planetary = isinstance(model, PlanetaryGearboxStage)
    keys = [key for key in _HOUSING_KEYS if key in table.given]
    if "housing_seat" in table.given and not planetary:
        raise sc.fail(where, "housing_seat", "allowed on a planetary stage only (a lumped 3D "
                      "stage's bearings take housing_seats)", table.housing_seat)
    if planetary and keys and "housing_seat" not in table.given:
        raise sc.fail(where, keys[0], "allowed on a planetary stage with housing_seat only",
                      getattr(table, keys[0]))
    if keys and not has_housing:
        raise sc.fail(where, keys[0], 'allowed on a model = "lumped3d" or a planetary stage of '
                      "a gearbox with [housing] only", getattr(table, keys[0]))
    if keys and not type(model).takes_housing:
        raise sc.fail(where, keys[0], 'allowed on a model = "lumped3d" stage of a gearbox with '
                      "[housing] only", getattr(table, keys[0]))
    if not has_housing or not (lumped or keys):
        return (0.0, 0.0, 0.0), None, None, None
    if case.housing is not None:
        raise sc.fail(where, "case", "the stage case has its own [housing]: allowed without it "
                      "in a gearbox with [housing] (its housed stages share the gearbox's)",
                      case.name)
    position = (0.0, 0.0, 0.0)
    if table.housing_position_mm is not None:
        position = tuple(float(x) * 1e-3 for x in table.housing_position_mm)
    bore = None
    if table.housing_bore_diameter_mm is not None:
        bore = table.housing_bore_diameter_mm * 1e-3
    if planetary:
        seat = table.housing_seat
        fixed = case.form.spec.fixed.name.lower()
        if fixed != "ring":
            raise sc.fail(where, "housing_seat", "allowed on a stage whose ring is held (this "
                          f"stage's [planetary] fixed = {fixed!r})", seat)
        return position, None, seat, bore
    if table.housing_seats is None:
        return position, None, None, bore
    seats = table.housing_seats
    n = sum(len(sh.bearings) for sh in (case.scene.pinion_shaft, case.scene.gear_shaft))
    if len(seats) != n:
        raise sc.fail(where, "housing_seats", f"allowed {n} integers >= -1 (a seat index per "
                      "bearing, pinion shaft's then gear shaft's; -1 on the ground)", seats)
    return position, tuple(None if v < 0 else v for v in seats), None, bore


def _check_seats(stages, spec: HousingSpec) -> None:
    """Every ``housing_seats`` and ``housing_seat`` index below the housing's seats: a box's 2
    per housed axis (its two end walls; a lumped stage's two shafts, a housed planetary stage's
    one), a mesh file's ``[[housing.seats]]``; a planetary ring's seat not one a lumped stage's
    bearing takes (its ``housing_seats``, else, in a box, its shafts' own bores); one line."""
    lumped = [s for s in stages if isinstance(s.torsional, LumpedPairGearboxStage)]
    if not lumped:
        raise sc.fail("housing", None, 'allowed with at least one model = "lumped3d" stage (the '
                      "box is sized round its shafts; torsional stages stay on the ground)")
    axes, own = 0, []  # the box's axes: a lumped stage's two shafts, a planetary's one
    for s in stages:
        if isinstance(s.torsional, LumpedPairGearboxStage):
            own.append((s, (axes, axes + 1)))
            axes += 2
        elif s.housing_seat is not None:
            axes += 1
    n = len(spec.seats) if spec.mesh_file is not None else 2 * axes
    taken = set()
    for s, shafts in own:
        if s.housing_seats is not None:
            taken |= {v for v in s.housing_seats if v is not None}
        elif spec.mesh_file is None:  # the nearest: its shafts' own bores in both walls
            taken |= {a + w * axes for a in shafts for w in (0, 1)}
    for k, s in enumerate(stages):
        bad = [v for v in (s.housing_seats or ()) if v is not None and v >= n]
        if bad:
            raise sc.fail(f"stages[{k}]", "housing_seats", f"out of range, allowed -1..{n - 1} "
                          f"(the housing's {n} seats)", list(s.housing_seats))
        if s.housing_seat is not None:
            if s.housing_seat >= n:
                raise sc.fail(f"stages[{k}]", "housing_seat", f"out of range, allowed "
                              f"0..{n - 1} (the housing's {n} seats)", s.housing_seat)
            if s.housing_seat in taken:
                raise sc.fail(f"stages[{k}]", "housing_seat", "a seat a lumped stage's bearing "
                              "takes: allowed a seat of its own (a bore round this stage's "
                              "axis)", s.housing_seat)


def _check_bores(form: GearboxForm) -> None:
    """The gearbox's box ``[housing]`` round its housed axes, before anything is meshed
    (:func:`~jaxgear.io._housing_table.check_box`: its sizes, the axes within it and apart,
    each bore, its stage's ``housing_bore_diameter_mm`` or the ``[housing]``'s
    ``bore_diameter_mm``, clear of its shafts, within the end walls and clear of the other
    bores; then its named points on its skin,
    :func:`~jaxgear.io._housing_table.check_housing_points`);
    ``housing_bore_diameter_mm`` with a mesh file's ``[housing]`` refused; one line naming
    the key, its value and the allowed range."""
    spec = form.housing
    if spec.mesh_file is not None:
        for k, s in enumerate(form.stages):
            if s.housing_bore_diameter is not None:
                raise sc.fail(f"stages[{k}]", "housing_bore_diameter_mm", "allowed with a box "
                              "[housing] only (a mesh file's [[housing.seats]] give their own "
                              "diameter_mm)", s.housing_bore_diameter * 1e3)
        return
    shafts, positions, diameters, owners = _housed_bearings(form)
    axes = []
    for k, ps, shaft in zip(owners, positions, _axis_shafts(form), strict=True):
        if not ps:
            continue
        s = form.stages[k]
        bore = (("housing", "bore_diameter_mm") if s.housing_bore_diameter is None
                else (f"stages[{k}]", "housing_bore_diameter_mm"))
        place = (f"stages[{k}]", "housing_position_mm",
                 [float(f"{x * 1e3:.6g}") for x in s.housing_position])
        label = f"stage {k + 1}'s axis" if shaft is None else f"stage {k + 1}'s {shaft[0]} axis"
        axes.append(HousedAxis(label, 0.0 if shaft is None else shaft[1], bore, place))
    check_box(spec, shafts, positions, axes, diameters)
    check_housing_points(spec, shafts, positions, diameters)


def _axis_shafts(form: GearboxForm) -> list:
    """Each entry of :func:`_housed_bearings`' positions: (the shaft's name, its diameter (m)),
    or None for a housed planetary stage's axis (no shaft through its bore)."""
    out = []
    for k in form.housed():
        s = form.stages[k]
        if s.housing_seat is not None:
            out.append(None)
        else:
            sh, _ = s.case._bearing_layout(s.case.scene)
            out += [(f"{name} shaft", float(x.diameter))
                    for name, x in zip(("pinion", "gear"), sh, strict=True)]
    return out
