"""A few embedded catalogue bearings, in SI, with their sources.

Deep groove ball bearings 6205 and 6203: boundary dimensions, ball count, ball and pitch
diameters of the SKF 6205-2RS JEM and 6203-2RS JEM as the Case Western Reserve University
Bearing Data Center states them for its test rig (drive end and fan end; inches converted),
basic load ratings C, C₀ and the factor f₀ of the SKF rolling bearings catalogue (6205:
14.8 kN, 7.8 kN, 14; 6203: 9.95 kN, 4.75 kN, 13). Groove conformities are not published: the
kinds' default 0.52 (Harris & Kotzalas's typical value).

Angular contact 7205 B, cylindrical NU 205 and tapered 30205: boundary dimensions of ISO 15 and
ISO 355 (d 25 mm, D 52 mm, B 15 mm; the 30205's cup-and-cone width T = 16.25 mm and the
catalogue's e = 0.37 for its contact angle, α = atan(e / 1.5)), the 7205 B's 40°. Their rolling
elements (count, diameter, length, pitch diameter) are representative values ESTIMATED from
the boundary dimensions, not a maker's data, and they carry no load ratings: give
``dynamic_rating`` (and ``static_rating``) from the maker's catalogue for a life.

Spherical roller bearings 231/750 CA/W33 and 240/710 ECA/W33 (the NREL 5 MW reference
gearbox's INP-B and PLC-A), and the single-row tapered roller bearings 32060 X and
LM 567949/910 (its stage-3 pairs HS-B/C and IMS-B/C, one row each): boundary dimensions, the basic dynamic load rating C and ISO 281's
e of Nejad et al., "Development of a 5 MW reference gearbox for offshore wind turbines", Wind
Energy 19 (2016), Table IX, as github.com/gfsReboucas/Drivetrain (4a88df3,
@NREL_5MW/NREL_5MW.m, ``bearing``) transcribes them with the SKF designations; the contact
angle from e = 1.5 tan α. No C₀ is published there. Their rollers are ESTIMATED by the rule
:func:`estimated_rollers` (d_m = (D + d)/2, D_w = (D − d)/4, Z per row the whole part of
0.8 π d_m / D_w, l = 0.35 B; a tapered row's l = 0.7 B), not a maker's data.

Angular contact 7305 BE and single-row tapered roller bearings 30305 and 32205 (beside the
25 mm entries above, for a choice on a 25 mm shaft): boundary dimensions d, D, B (a tapered
row's T), the basic load ratings C, C₀ and a tapered row's e of SKF's "Rolling bearings"
catalogue (PUB BU/P1 17000/1 EN, 2018; the rows 7305 BECBPH, 30305 J2/Q and 32205 BJ2/Q) as
github.com/gumyr/bd_warehouse (9d0dc94, src/bd_warehouse/data/
single_row_angular_contact_ball_bearing_parameters.csv and
single_row_tapered_roller_bearing_parameters.csv) transcribes them: 7305 BE 25 × 62 × 17 mm,
26.5 kN, 15.3 kN, 40°; 30305 25 × 62 × 18.25 mm, 44.6 kN, 43 kN, e 0.3; 32205 25 × 52 ×
19.25 mm, 35.8 kN, 44 kN, e 0.57 (α = atan(e / 1.5)). Their rolling elements are ESTIMATED
(:func:`estimated_rollers` with B = T; the balls by :func:`estimated_balls`), not a maker's
data (SKF does not publish them).
"""

from __future__ import annotations

import math

from .._util import check_instance
from ._kinds import (
    AbstractRollingBearing,
    AngularContactBall,
    CylindricalRoller,
    DeepGrooveBall,
    SphericalRoller,
    TaperedRoller,
)

__all__ = ["CATALOGUE", "catalogue", "estimated_balls", "estimated_rollers"]

_IN = 0.0254
_CWRU = ("Case Western Reserve University Bearing Data Center, bearing specifications "
         "(SKF 6205-2RS JEM drive end, 6203-2RS JEM fan end); SKF rolling bearings catalogue "
         "(C, C0, f0)")
_EST = ("ISO 15 / ISO 355 boundary dimensions; rolling elements estimated from them "
        "(representative, not a maker's data); no load ratings")

_NREL = ("Nejad et al. 2016 (Wind Energy 19, 1089-1106) Table IX via github.com/gfsReboucas/"
         "Drivetrain 4a88df3 @NREL_5MW/NREL_5MW.m: d, D, B, C, e (alpha = atan(e/1.5)); rollers "
         "estimated (estimated_rollers); no C0")


def estimated_rollers(bore, outer_diameter, width, rows: int = 1) -> dict:
    """A roller set ESTIMATED from a roller bearing's boundary dimensions d, D, B (m), where
    the maker's is not at hand: pitch diameter d_m = (D + d)/2, roller diameter
    D_w = (D − d)/4 (half the ring section), per row Z = the whole part of 0.8 π d_m / D_w (the
    cage's bars take a fifth of the pitch circle), effective length l = 0.7 B / ``rows`` (the
    rings' shoulders, the rollers' end chamfers and, for two rows, the guide ring take the
    rest). Returns ``pitch_diameter``, ``element_diameter``, ``elements``,
    ``effective_length`` (m, -), the arguments of a roller kind."""
    dm = 0.5 * (outer_diameter + bore)
    D = 0.25 * (outer_diameter - bore)
    return dict(pitch_diameter=dm, element_diameter=D,
                elements=int(0.8 * math.pi * dm / D), effective_length=0.7 * width / rows)


def estimated_balls(bore, outer_diameter) -> dict:
    """A ball set ESTIMATED from a ball bearing's bore d and outer diameter D (m), where the
    maker's is not at hand: pitch diameter d_m = (D + d)/2, ball diameter D_w = 0.3 (D − d)
    (a first-design ratio: 8.10 mm for the 6205, whose published ball is 7.94 mm, 2.5 %),
    Z = the whole part of 0.8 π d_m / D_w (the cage's bars take a fifth of the pitch circle).
    Returns ``pitch_diameter``, ``element_diameter``, ``elements`` (m, -), the arguments of a
    ball kind."""
    dm = 0.5 * (outer_diameter + bore)
    D = 0.3 * (outer_diameter - bore)
    return dict(pitch_diameter=dm, element_diameter=D, elements=int(0.8 * math.pi * dm / D))


_SKF = ("SKF Rolling bearings catalogue PUB BU/P1 17000/1 EN (2018) via github.com/gumyr/"
        "bd_warehouse 9d0dc94 (src/bd_warehouse/data/single_row_*_parameters.csv): d, D, B (T), "
        "C, C0, e (alpha = atan(e/1.5)); rolling elements estimated (estimated_rollers, "
        "estimated_balls)")

#: designation -> (kind, its arguments in SI, the source)
CATALOGUE: dict[str, tuple[type, dict, str]] = {
    "6205": (DeepGrooveBall, dict(
        bore=0.9843 * _IN, outer_diameter=2.0472 * _IN, width=0.5906 * _IN, elements=9,
        element_diameter=0.3126 * _IN, pitch_diameter=1.537 * _IN, dynamic_rating=14.8e3,
        static_rating=7.8e3, iso281_f0=14.0), _CWRU),
    "6203": (DeepGrooveBall, dict(
        bore=0.6693 * _IN, outer_diameter=1.5748 * _IN, width=0.4724 * _IN, elements=8,
        element_diameter=0.2656 * _IN, pitch_diameter=1.122 * _IN, dynamic_rating=9.95e3,
        static_rating=4.75e3, iso281_f0=13.0), _CWRU),
    "7205 B": (AngularContactBall, dict(
        bore=0.025, outer_diameter=0.052, width=0.015, elements=12, element_diameter=7.938e-3,
        pitch_diameter=0.0385, contact_angle=math.radians(40.0)), _EST),
    "NU 205": (CylindricalRoller, dict(
        bore=0.025, outer_diameter=0.052, width=0.015, elements=13, element_diameter=7.0e-3,
        pitch_diameter=0.0385, effective_length=8.0e-3), _EST),
    "30205": (TaperedRoller, dict(
        bore=0.025, outer_diameter=0.052, width=0.01625, elements=15, element_diameter=6.0e-3,
        pitch_diameter=0.039, effective_length=10.0e-3,
        contact_angle=math.atan(0.37 / 1.5)), _EST),
    "7305 BE": (AngularContactBall, dict(
        bore=0.025, outer_diameter=0.062, width=0.017, **estimated_balls(0.025, 0.062),
        contact_angle=math.radians(40.0), dynamic_rating=26.5e3, static_rating=15.3e3), _SKF),
    "30305": (TaperedRoller, dict(
        bore=0.025, outer_diameter=0.062, width=0.01825,
        **estimated_rollers(0.025, 0.062, 0.01825), contact_angle=math.atan(0.3 / 1.5),
        dynamic_rating=44.6e3, static_rating=43e3), _SKF),
    "32205": (TaperedRoller, dict(
        bore=0.025, outer_diameter=0.052, width=0.01925,
        **estimated_rollers(0.025, 0.052, 0.01925), contact_angle=math.atan(0.57 / 1.5),
        dynamic_rating=35.8e3, static_rating=44e3), _SKF),
    "231/750 CA": (SphericalRoller, dict(
        bore=0.75, outer_diameter=1.22, width=0.365, **estimated_rollers(0.75, 1.22, 0.365, 2),
        contact_angle=math.atan(0.28 / 1.5), dynamic_rating=16518e3), _NREL),
    "240/710 ECA": (SphericalRoller, dict(
        bore=0.71, outer_diameter=1.03, width=0.315, **estimated_rollers(0.71, 1.03, 0.315, 2),
        contact_angle=math.atan(0.27 / 1.5), dynamic_rating=11164e3), _NREL),
    # the stage-3 tapered rows (HS-B/C, IMS-B/C): one row each; a pair is
    # TaperedRollerPair.of(catalogue(...), arrangement)
    "32060 X": (TaperedRoller, dict(
        bore=0.3, outer_diameter=0.46, width=0.1, **estimated_rollers(0.3, 0.46, 0.1),
        contact_angle=math.atan(0.43 / 1.5), dynamic_rating=1644e3), _NREL),
    "LM 567949/910": (TaperedRoller, dict(
        bore=0.41, outer_diameter=0.55, width=0.086, **estimated_rollers(0.41, 0.55, 0.086),
        contact_angle=math.atan(0.4 / 1.5), dynamic_rating=1467e3), _NREL),
}


def catalogue(designation: str, **changes) -> AbstractRollingBearing:
    """The embedded bearing ``designation`` (a key of :data:`CATALOGUE`: "6205", "6203",
    "7205 B", "NU 205", "30205", "7305 BE", "30305", "32205", "231/750 CA", "240/710 ECA",
    "32060 X", "LM 567949/910"), with
    ``changes`` to its arguments (a clearance, the ratings).

    Raises:
        ValueError: an unknown designation (one line listing the known ones); a change out of
            its range (the kind's own line)."""
    check_instance("designation", designation, str, "a designation string", where="catalogue")
    if designation not in CATALOGUE:
        raise ValueError(
            f"catalogue: designation = {designation!r} is not embedded: allowed "
            f"{', '.join(repr(k) for k in CATALOGUE)}"
        )
    kind, args, _ = CATALOGUE[designation]
    return kind(**{**args, **changes})
