"""A sizing spec's ``[sound]`` table: what the sound stage of ``jaxgear size`` (the equivalent
radiated power of a housing round each candidate of the first Pareto fronts, docs/sizing.md,
"The sound stage") needs that the candidate does not state: the housing's walls, the shafts and
bearings' layout and the whine's speeds; and the layout of a candidate (:func:`sound_layout`)
that its housed case file (:func:`jaxgear.io.housed_case_text`: the lumped 3D pair in a box
housing, which ``jaxgear run`` runs) states.

.. code-block:: toml

    [sound]                         # optional: without it, no sound stage
    candidates = 1                  # candidates of the first Pareto fronts run, [0, 100],
                                    # default 1 (0: none; jaxgear size --sound N)
    speed_range_rpm = [300.0, 1800.0]   # the whine's pinion speeds, each (0, 1e6], lo < hi
    speeds = 24                     # equally spaced over the range, [2, 400], default 24
    harmonics = 8                   # of the mesh frequency, [1, 32], default 8
    band_orders = 1                 # the housing's cut-off: 1.5 x the frequency of this mesh
                                    # order at the top speed, [1, 32], default 1 (orders above
                                    # it left out of the overall ERP)
    tip_clearance_mm = 10.0         # the gears' tip circles to the walls' inner faces,
                                    # [1, 1000], default 10
    wall_thickness_mm = 12.0        # [1, 200], default 12
    mesh_size_mm = 40.0             # the box mesh's largest cell edge, [5, 1000], default 40
    youngs_modulus_GPa = 70.0       # the housing's material, default cast aluminium:
    poisson_ratio = 0.33            # 70 GPa, 0.33, 2700 kg/m³
    density_kg_m3 = 2700.0
    loss_factor = 0.02              # the housing's modal damping, [0, 1], default 0.02
    shaft_diameter_ratio = 0.5      # both shafts' diameter over the pinion's root diameter,
                                    # (0, 0.6], default 0.5; or
    shaft_diameter_mm = 40.0        # both shafts' diameter, [1, 1e4] (one of the two)
    bearing_margin_mm = 20.0        # each gear face to its bearing, [0, 1000], default 20,
                                    # >= wall_thickness_mm / 2
    bearing_radial_N_per_um = 500.0 # each bearing's radial stiffness, (0, 1e6], default 500
    bearing_axial_N_per_um = 200.0  # the first bearing of each shaft's axial stiffness,
                                    # (0, 1e6], default 200
    sound_power = false             # the radiated sound power too (BEM on the housing's closed
                                    # skin, jaxgear run's [acoustics]), default false
    [sound.acoustics]               # optional, with sound_power = true: the housed case's
                                    # [acoustics] (docs/acoustics.md; its keys and checks)
    method = "bem"                  # "bem" (default) or "erp-only" (radiation efficiency 1)
    frequencies = 6                 # R at this many log-spaced frequencies over the orders'
                                    # range, [1, 2000], default 6 (the ranking's coarse grid)
    rank = 64                       # radiation modes kept, [1, 1e6], default all
    cache = true                    # R in fem_prep's cache, default true
    density_kg_m3 = 1.21            # the air, (0, 1e4], default 1.21
    sound_speed_m_s = 343.0         # (0, 1e5], default 343

The layout of a candidate (:func:`sound_layout`; SI there, mm in the case file): each shaft of
length b + 4 margin with its gear at the middle, its bearings at margin and length − margin (b
± 2 margin apart, b the face width), the pinion's input torque at its start and the wheel's
output at its end; the scene frame's pinion axis at x = y = 0 and the wheel's at x = a. The
box round the two tip circles: width (along the centres' line) a + (d_a1 + d_a2)/2 + 2 (c +
t), height max(d_a1, d_a2) + 2 (c + t), c the tip clearance, t the wall, both outer sizes; its
length the case reader's default, the bearings' span + t (the end walls' mid-planes at the
bearings), its bores the reader's 1.5 x the shafts' diameter. Both shafts have one diameter:
the box of a case's ``[housing]`` has one bore diameter, and a wheel shaft thicker than the
pinion's would need a bore at each axis of its own.

With ``sound_power = true`` the housed case holds ``[acoustics]`` too (:class:`SoundAcoustics`:
``[acoustics]``'s keys and checks, without ``band_Hz``, which follows each candidate's orders,
nor microphones, whose places would follow each box), so that ``jaxgear run`` of it computes the
radiated sound power the stage ranks by.
"""

from __future__ import annotations

import math
from typing import ClassVar, Literal, NamedTuple

import pydantic

from fem_prep import schema as sc

from ._acoustics_table import AcousticsSection
from ._sections import Section, number, number_list

__all__ = ["POSITIONS", "SOUND_ELEMENTS", "SoundAcoustics", "SoundLayout", "SoundSection",
           "sizing_sound", "sound_layout"]

RPM = math.pi / 30
#: the finite elements along each shaft (the case reader refines them at the gear, the torque
#: and the bearings)
SOUND_ELEMENTS = 6
#: the whine's time samples per mesh period (the [whine] default of the example housed case)
POSITIONS = 64


class SoundAcoustics(AcousticsSection):
    """A sizing spec's ``[sound.acoustics]``: the ``[acoustics]`` table (:class:`~jaxgear.io.
    AcousticsSection`, its keys, ranges and defaults) written into each candidate's housed case,
    but for ``frequencies`` (default 6: a coarse grid, enough to rank candidates, docs/sizing.md,
    "The sound stage"), ``method`` ("bem" or "erp-only": a housing's closed skin), and without
    ``band_Hz`` (the grid spans each candidate's own orders) or microphones (whose places would
    follow each candidate's box)."""

    WHERE: ClassVar[str] = "sound.acoustics"
    method: Literal["bem", "erp-only"] = "bem"
    frequencies: number("[1, 2000]", integer=True) = 6

    @pydantic.model_validator(mode="after")
    def _related(self):  # replaces [acoustics]'s: neither of its related keys is read here
        for key, why in (("band_Hz", "the grid spans each candidate's own orders"),
                         ("microphones", "their places would follow each candidate's box")):
            if key in self.model_fields_set:
                value = self.band_Hz if key == "band_Hz" else self.microphone_names()
                raise sc.fail(self.WHERE, key, f"not in a sizing ({why}): allowed method, "
                              "frequencies, rank, cache, density_kg_m3, sound_speed_m_s", value)
        return self


class SoundSection(Section):
    """A sizing spec's ``[sound]`` (module docstring): each key's range declared here, the
    relations between keys in :meth:`_related`."""

    WHERE: ClassVar[str] = "sound"
    candidates: number("[0, 100]", integer=True) = 1
    speed_range_rpm: number_list("(0, 1e+06]", length=2)
    speeds: number("[2, 400]", integer=True) = 24
    harmonics: number("[1, 32]", integer=True) = 8
    band_orders: number("[1, 32]", integer=True) = 1
    tip_clearance_mm: number("[1, 1000]") = 10.0
    wall_thickness_mm: number("[1, 200]") = 12.0
    mesh_size_mm: number("[5, 1000]") = 40.0
    youngs_modulus_GPa: number("[0.1, 1e+07]") = 70.0
    poisson_ratio: number("[0, 0.5)") = 0.33
    density_kg_m3: number("[1, 1e+05]") = 2700.0
    loss_factor: number("[0, 1]") = 0.02
    shaft_diameter_ratio: number("(0, 0.6]") | None = None
    shaft_diameter_mm: number("[1, 10000]") | None = None
    bearing_margin_mm: number("[0, 1000]") = 20.0
    bearing_radial_N_per_um: number("(0, 1e+06]") = 500.0
    bearing_axial_N_per_um: number("(0, 1e+06]") = 200.0
    sound_power: bool = False
    acoustics: SoundAcoustics | None = None

    @pydantic.model_validator(mode="after")
    def _related(self):
        w = self.WHERE
        r = self.speed_range_rpm
        if not r[0] < r[1]:
            raise sc.fail(w, "speed_range_rpm", "out of range, allowed [lo, hi] with lo < hi", r)
        if r[1] * RPM > 1e5:  # the [whine] table's limit on its speeds
            raise sc.fail(w, "speed_range_rpm", f"out of range, allowed a top speed <= "
                          f"{1e5 / RPM:.6g} 1/min (1e5 rad/s, the whine's)", r)
        if self.shaft_diameter_ratio is not None and self.shaft_diameter_mm is not None:
            raise sc.fail(w, "shaft_diameter_mm", "give one of shaft_diameter_ratio and "
                          "shaft_diameter_mm, not both", self.shaft_diameter_mm)
        if not 2 * self.bearing_margin_mm >= self.wall_thickness_mm:
            raise sc.fail(w, "bearing_margin_mm", "out of range, allowed >= wall_thickness_mm / 2"
                          f" = {sc.fmt(self.wall_thickness_mm / 2)} (the gears' faces inside "
                          "the end walls, whose mid-planes are at the bearings)",
                          self.bearing_margin_mm)
        if self.acoustics is not None and not self.sound_power:
            raise sc.fail(w, "sound_power", "[sound.acoustics] is read only with "
                          "sound_power = true: allowed true with it, or no [sound.acoustics]",
                          self.sound_power)
        return self

    def radiation(self) -> SoundAcoustics | None:
        """The ``[acoustics]`` each candidate's housed case holds: ``[sound.acoustics]`` (its
        defaults where not given) with ``sound_power = true``, else None (no sound power)."""
        if not self.sound_power:
            return None
        return SoundAcoustics() if self.acoustics is None else self.acoustics

    def shaft_diameter(self, root_diameter: float) -> float:
        """Both shafts' diameter (m) for a pinion of root diameter ``root_diameter`` (m): the
        given one, else ``shaft_diameter_ratio`` (default 0.5) of it."""
        if self.shaft_diameter_mm is not None:
            return self.shaft_diameter_mm * 1e-3
        ratio = 0.5 if self.shaft_diameter_ratio is None else self.shaft_diameter_ratio
        return ratio * root_diameter


class SoundLayout(NamedTuple):
    """A candidate's shafts, bearings and housing box (:func:`sound_layout`), SI (m).

    Attributes:
        width, height: the box's outer sizes across the shafts (scene x, along the centres'
            line) and scene y.
        wall_thickness: the walls'.
        shaft_length, shaft_diameter: both shafts' (from z = 0).
        gear_position: each gear's centre on its shaft.
        bearing_positions: the two bearings' positions on each shaft.
    """

    width: float
    height: float
    wall_thickness: float
    shaft_length: float
    shaft_diameter: float
    gear_position: float
    bearing_positions: tuple[float, float]


def sound_layout(section: SoundSection, pair) -> SoundLayout:
    """The layout rule of the module docstring for a candidate's :class:`jaxgear.GearPair`
    ``pair`` (its centre distance a, tip radii, pinion root radius and face width b).

    Returns:
        The :class:`SoundLayout` (m).
    """
    a = float(pair.center_distance)
    ra = [float(r) for r in pair.tip_radii]
    c, t = section.tip_clearance_mm * 1e-3, section.wall_thickness_mm * 1e-3
    m, b = section.bearing_margin_mm * 1e-3, float(pair.face_width)
    length = b + 4 * m
    return SoundLayout(
        width=a + ra[0] + ra[1] + 2 * (c + t),
        height=2 * max(ra) + 2 * (c + t),
        wall_thickness=t,
        shaft_length=length,
        shaft_diameter=section.shaft_diameter(2 * float(pair.root_radii[0])),
        gear_position=length / 2,
        bearing_positions=(m, length - m),
    )


def sizing_sound(tables: dict, candidates: int | None = None) -> tuple[SoundSection | None, int]:
    """The sound stage of a spec's checked tables (:func:`jaxgear.io.load_sizing_spec`): its
    ``[sound]`` section (None without one: no stage) and the candidates it runs (``[sound]``'s
    ``candidates``, or ``candidates``, ``jaxgear size --sound N``, where given; 0 without the
    table).

    Raises:
        ValueError: ``candidates`` given for a spec without ``[sound]`` (one line).
    """
    if "sound" not in tables:
        if candidates:
            raise ValueError(f"--sound {candidates}: the spec has no [sound] table (the "
                             "housing's walls, the shafts' layout, the whine's speeds; "
                             "docs/sizing.md): allowed --sound 0, or a spec with [sound]")
        return None, 0
    section = SoundSection.of_file(tables)
    return section, section.candidates if candidates is None else int(candidates)
