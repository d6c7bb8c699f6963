"""What a sizing searches and what it requires, in SI (:class:`SizingSpec`), and the standard
module series it takes its modules from (ISO 54)."""

from __future__ import annotations

import dataclasses
import math

from .._util import check_instance
from ..rating import OperatingPoint, RatingSettings
from ._objectives import MeshLossInputs, ScuffingRequirement
from ._pareto import DEFAULT_OBJECTIVES, check_objectives

__all__ = ["ISO54_FIRST", "ISO54_SECOND", "SizingSpec", "module_series"]

#: ISO 54:1996's normal modules of first choice (mm), 1 to 50
ISO54_FIRST = (1.0, 1.25, 1.5, 2.0, 2.5, 3.0, 4.0, 5.0, 6.0, 8.0, 10.0, 12.0, 16.0, 20.0, 25.0,
               32.0, 40.0, 50.0)
#: ISO 54:1996's normal modules of second choice (mm), between those of the first
ISO54_SECOND = (1.125, 1.375, 1.75, 2.25, 2.75, 3.5, 4.5, 5.5, 7.0, 9.0, 11.0, 14.0, 18.0, 22.0,
                28.0, 36.0, 45.0)
#: the series by name: first choice, second choice, or both merged
SERIES = {"first": ISO54_FIRST, "second": ISO54_SECOND,
          "both": tuple(sorted(ISO54_FIRST + ISO54_SECOND))}


def module_series(lo: float, hi: float, series: str = "first") -> tuple[float, ...]:
    """The normal modules (m) of ISO 54's ``series`` (``"first"``, ``"second"``, ``"both"``)
    from ``lo`` to ``hi`` (m), both included (a bound read to 1e-9 mm)."""
    if series not in SERIES:
        raise ValueError(f"module_series: series = {series!r} is out of range: allowed "
                         f"{', '.join(map(repr, SERIES))}")
    return tuple(m * 1e-3 for m in SERIES[series] if lo * 1e3 - 1e-9 <= m <= hi * 1e3 + 1e-9)


@dataclasses.dataclass(frozen=True)
class SizingSpec:
    """A sizing task in SI units: the requirements (load, ratio, life and safety in the rating
    ``settings``), the limits (space, tooth form) and the ranges searched. The case reader
    (``jaxgear.io.load_sizing_spec``) builds it from a spec file and checks every value there,
    in the file's words; here only the kinds and the ranges' order are checked.

    Attributes:
        operating: the pinion's torque T₁ (N·m) and speed (rad/s),
            :class:`jaxgear.rating.OperatingPoint`.
        settings: the rating's settings (:class:`jaxgear.rating.RatingSettings`): material,
            lubrication, life, K_A, the minimum safety factors S_Hmin and S_Fmin (the
            feasibility limits), the edition; its ``accuracy`` holds the ISO 1328-1 grade only:
            each candidate is rated with the tolerances of its own dimensions
            (:meth:`jaxgear.rating.GearAccuracy.from_dimensions`).
        ratio: the target gear ratio u = z2/z1 (>= 1). ratio_tolerance: |z2/z1 − u| <=
            tolerance · u (a fraction, 0.02 for 2 %).
        normal_modules: the normal modules searched (m), increasing (:func:`module_series`).
        pinion_teeth: (z1_min, z1_max), both searched.
        normal_pressure_angle: α_n (rad). helix_angle: β (rad).
        addendum_coeff, dedendum_coeff, fillet_radius_coeff: the basic rack's h_aP/m_n,
            h_fP/m_n and ρ_fP/m_n (both gears).
        profile_shift: (x1, x2). With a fixed centre distance x2 is not read: the sum x1 + x2
            follows from the centre distance (ISO 21771), x2 = sum − x1.
        centre_distance: (a_min, a_max) (m), the window a candidate's centre distance lies in;
            a_min == a_max: a fixed centre distance; None: any.
        profile_shift_sum: (lo, hi), the sums x1 + x2 a fixed centre distance may need (a
            candidate whose sum lies outside is not enumerated).
        face_width: (b_min, b_max) (m). face_width_ratio: the largest b/d1, or None. Each
            candidate's face width (both gears) is the widest allowed, min(b_max, (b/d1)_max
            d1); below b_min the candidate is rejected.
        outer_diameter_max: the largest tip diameter of either gear (m), or None.
        tip_thickness_min: the least normal tooth thickness at the tip, as a multiple of m_n.
        mesh_loss: the oil, roughness and friction law of the mesh loss columns
            (:class:`jaxgear.sizing.MeshLossInputs`), or None: no mesh loss.
        scuffing: the oil, FZG limits and S_Bmin of the scuffing check (ISO/TS 6336-20's
            closed form, :class:`jaxgear.sizing.ScuffingRequirement`), or None: no scuffing
            rating (no scuffing columns; the ``scuffing`` check passes every candidate).
        objectives: the Pareto front's objectives, (column, ``"min"`` | ``"max"``) pairs
            (:data:`jaxgear.sizing.OBJECTIVES`); default the mass and the least margin.
        chosen: the chosen design on the front, ``"knee"`` or an objective's column
            (:func:`jaxgear.sizing.pareto_front`).
        helix_angle_range: (β_min, β_max) (rad), the range the refinement
            (:func:`jaxgear.sizing.refine`) solves β in, or None: β fixed at ``helix_angle``
            (the enumeration's).
        profile_shift_range: (x_min, x_max), the range the refinement solves each profile shift
            in, or None: the shifts fixed as enumerated (with a fixed centre distance x2 still
            follows from it and β).
        refine: whether ``jaxgear size`` refines the continuous variables
            (:func:`jaxgear.sizing.refine`). refine_objective: what the refinement optimises,
            a key of :data:`jaxgear.sizing.OBJECTIVES` (``"mass"``: the lightest blanks
            meeting every limit; ``"margin"``: the largest least safety margin at no more
            than the enumerated design's mass).
    """

    operating: OperatingPoint
    settings: RatingSettings
    ratio: float
    ratio_tolerance: float
    normal_modules: tuple[float, ...]
    pinion_teeth: tuple[int, int]
    normal_pressure_angle: float = math.radians(20.0)
    helix_angle: float = 0.0
    addendum_coeff: float = 1.0
    dedendum_coeff: float = 1.25
    fillet_radius_coeff: float = 0.38
    profile_shift: tuple[float, float] = (0.0, 0.0)
    centre_distance: tuple[float, float] | None = None
    profile_shift_sum: tuple[float, float] = (-1.0, 2.0)
    face_width: tuple[float, float] = (0.004, 0.1)
    face_width_ratio: float | None = None
    outer_diameter_max: float | None = None
    tip_thickness_min: float = 0.2
    mesh_loss: MeshLossInputs | None = None
    scuffing: ScuffingRequirement | None = None
    objectives: tuple = DEFAULT_OBJECTIVES
    chosen: str = "knee"
    helix_angle_range: tuple[float, float] | None = None
    profile_shift_range: tuple[float, float] | None = None
    refine: bool = False
    refine_objective: str = "mass"

    def __post_init__(self):
        w = "SizingSpec"
        check_instance("operating", self.operating, OperatingPoint,
                       "a jaxgear.rating.OperatingPoint", w)
        check_instance("settings", self.settings, RatingSettings,
                       "a jaxgear.rating.RatingSettings", w)
        for name in ("pinion_teeth", "face_width", "centre_distance", "profile_shift_sum"):
            v = getattr(self, name)
            if v is not None and not (len(v) == 2 and v[0] <= v[1]):
                raise ValueError(f"{w}: {name} = {v!r} is out of range: allowed (lo, hi) with "
                                 "lo <= hi")
        for name in ("helix_angle_range", "profile_shift_range"):
            v = getattr(self, name)
            if v is not None and not (len(v) == 2 and v[0] <= v[1]):
                raise ValueError(f"{w}: {name} = {v!r} is out of range: allowed (lo, hi) with "
                                 "lo <= hi")
        if self.refine_objective not in ("mass", "margin"):
            raise ValueError(f"{w}: refine_objective = {self.refine_objective!r} is out of "
                             "range: allowed 'mass', 'margin'")
        if not self.normal_modules:
            raise ValueError(f"{w}: normal_modules = () is out of range: allowed one or more")
        if not self.ratio >= 1.0 or not self.ratio_tolerance >= 0.0:
            raise ValueError(f"{w}: ratio = {self.ratio!r}, ratio_tolerance = "
                             f"{self.ratio_tolerance!r}: allowed ratio >= 1, tolerance >= 0")
        if self.mesh_loss is not None:
            check_instance("mesh_loss", self.mesh_loss, MeshLossInputs,
                           "a jaxgear.sizing.MeshLossInputs or None", w)
        if self.scuffing is not None:
            check_instance("scuffing", self.scuffing, ScuffingRequirement,
                           "a jaxgear.sizing.ScuffingRequirement or None", w)
        check_objectives(self.objectives, self.chosen, w)

    @property
    def fixed_centre_distance(self) -> bool:
        """Whether the centre distance is fixed (the profile shift sum follows from it)."""
        return self.centre_distance is not None and self.centre_distance[0] == self.centre_distance[1]
