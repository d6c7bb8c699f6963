"""The body file's schema: the body-file reader of fem_prep, the one place that maps the names
in a body file to objects.

:func:`parse_body` checks a ``body.toml`` (schema in ``docs/fem_prep.md``) and builds a
:class:`~fem_prep.Body`; the kinds the file names (``element``, ``coupling``, ``method``,
``rim_coupling``, ``support``) become objects here and only here, by the tables :data:`ELEMENTS`,
:data:`COUPLINGS`, :data:`METHODS`, :data:`RIM_COUPLINGS` and :data:`SUPPORTS` (a new kind: one
more class beside its algorithm and one more entry here).  All lengths in the file are in mm, the
modulus in GPa; :class:`~fem_prep.Body` stores SI values (m, Pa, kg/m^3) next to the raw text.

Each table of a body file (and of a ring-gear file, :func:`parse_ring_body`) is a typed section
(:class:`fem_prep.sections.Section`, a pydantic model: :class:`BodyFile`, :class:`BodyTable`,
:class:`BearingTable`, ...) that declares its keys, their types and ranges once; what relates
two tables (the bearings and the element sizes to the body, the pinion rim's place) is checked
here after them. Every error is a :class:`SchemaError` (a ``ValueError``) whose one-line message
names the offending key, its value as written in the file (mm, deg) and the allowed range, so
that a user can fix the file without reading the code; integer keys accept integral floats
(``modes = 50.0``) and reject others (``modes = 50.5``), as in jaxgear's case files.

The checking helpers shared with jaxgear's case files live in :mod:`fem_prep.checks`, the atomic
writers and embedded-file helpers in :mod:`fem_prep.files`; their names are re-exported here for
the code that still imports them from ``fem_prep.schema``.
"""

from __future__ import annotations

import itertools
import math
from importlib import resources
from pathlib import Path
from typing import Annotated, Any, ClassVar, Literal

import pydantic
from pydantic import AfterValidator, BeforeValidator, Field

from . import checks as sc, files
from ._body import (
    BearingSeat,
    Body,
    Condensation,
    Geometry,
    Holes,
    Material,
    MeshSettings,
    PinionRim,
)
from ._condense import CraigBampton, Guyan, Herting
from ._couplings import Averaging, Distributing, Nodal, Rigid
from ._elements import Hex20, Hex27
from ._kinds import Kind
from ._prepare import Bearings, Free
from ._ring import BoltedFlange, ElasticFoundation, FreeRing, RingBody

# the shared helpers, re-exported (import them from fem_prep.checks / fem_prep.files)
from .checks import (  # noqa: F401
    MISSING as MISSING,
    Interval as Interval,
    SchemaError as SchemaError,
    boolean as boolean,
    check_keys as check_keys,
    choice as choice,
    did_you_mean as did_you_mean,
    fail as fail,
    finite as finite,
    fmt as fmt,
    g6 as g6,
    interval as interval,
    key_path as key_path,
    load_toml as load_toml,
    name as name,
    number as number,
    number_list as number_list,
    string as string,
    subtable as subtable,
    subtables as subtables,
    table_array as table_array,
)
from .files import (  # noqa: F401
    OUTPUT_MANIFEST as OUTPUT_MANIFEST,
    atomic_open as atomic_open,
    atomic_write as atomic_write,
    check_output_dir as check_output_dir,
    check_output_file as check_output_file,
    embedded_names as embedded_names,
    embedded_text as embedded_text,
    print_or_write as print_or_write,
    record_outputs as record_outputs,
    recorded_outputs as recorded_outputs,
    write_new_file as write_new_file,
)
from .sections import Section, number as _number  # schema.number: checks.number's

__all__ = [
    "COUPLINGS",
    "ELEMENTS",
    "METHODS",
    "RIM_COUPLINGS",
    "SUPPORTS",
    "embedded_bodies",
    "embedded_body_text",
    "estimate_mesh_dofs",
    "load_body",
    "parse_body",
    "parse_ring_body",
]

# the names of the kinds in a body file (the first of each is its default, but METHODS')
METHODS: dict[str, Kind] = {"guyan": Guyan(), "craig-bampton": CraigBampton(), "herting": Herting()}
ELEMENTS: dict[str, Kind] = {"hex20": Hex20(), "hex27": Hex27()}
COUPLINGS: dict[str, Kind] = {"rigid": Rigid(), "averaging": Averaging()}
RIM_COUPLINGS: dict[str, Kind] = {"distributing": Distributing(), "nodal": Nodal()}  # ._rim
SUPPORTS: dict[str, Kind] = {"bearings": Bearings(), "free": Free()}


def _within(where: str, key: str, value: float, rng: str, note: str = "") -> None:
    """Raise ``[where] key = value: out of range, allowed rng (note)`` unless value in rng: a
    range that follows from other keys (of the table or of the file)."""
    r = sc.interval(rng)
    if value not in r:
        raise sc.fail(where, key, f"out of range, allowed {r}{f' ({note})' if note else ''}", value)


# --------------------------------------------------------------------------------------------
# The tables of a body file (lengths in mm, angles in deg, as the file writes them)

_LENGTH = "[0.001, 1e+06]"  # mm: 1 µm to 1 km (a denormal passes "> 0" and fails the mesher)
_Length = _number(_LENGTH)
#: the most DOFs a body's mesh may have (the embedded bodies: 17 k to 104 k): its assembly
#: alone takes about 10 kB a DOF (20 GB here), the factorisation more
MAX_MESH_DOFS = 2_000_000
#: the most component modes of a condensation (the seed retains 50)
MAX_MODES = 2000


def _words(allowed: str = "", default: str = "") -> dict:
    """A field's range or default that other keys decide, in words (the reference's)."""
    return {"json_schema_extra": {k: v for k, v in (("allowed", allowed), ("default", default))
                                  if v}}


class HolesTable(Section):
    """``[body] holes = { count, center_radius_mm, radius_mm }``: holes through the web."""

    WHERE: ClassVar[str] = "body.holes"
    count: _number("[0, 10000]", integer=True) = 0
    center_radius_mm: _number(">= 0") = 0.0
    radius_mm: _number(">= 0") = 0.0


class BodyTable(Section):
    """``[body]``: the meridian section (mm, deg); its radii in order, the web inside the rim,
    the holes in the web apart (checked here)."""

    WHERE: ClassVar[str] = "body"
    bore_radius_mm: _Length
    hub_outer_radius_mm: _Length
    hub_width_mm: _Length
    web_thickness_mm: _Length
    web_offset_mm: _number() = Field(0.0, **_words(
        "[-(rim_width_mm - web_thickness_mm)/2, (rim_width_mm - web_thickness_mm)/2]"))
    web_inclination_deg: _number("(-60, 60)") = 0.0
    rim_inner_radius_mm: _Length
    rim_outer_radius_mm: _Length
    rim_width_mm: _Length
    shaft_outer_radius_mm: _Length | None = Field(None, **_words(default="hub_outer_radius_mm"))
    holes: HolesTable = HolesTable()

    @property
    def shaft_mm(self) -> float:
        """The shaft stubs' outer radius (mm; default the hub's)."""
        s = self.shaft_outer_radius_mm
        return self.hub_outer_radius_mm if s is None else s

    @pydantic.model_validator(mode="after")
    def _fits(self):
        bore, hub_r, rim_i = self.bore_radius_mm, self.hub_outer_radius_mm, self.rim_inner_radius_mm
        rim_o, rim_w, web_t = self.rim_outer_radius_mm, self.rim_width_mm, self.web_thickness_mm
        w = self.WHERE
        _within(w, "bore_radius_mm", bore, f"(0, {hub_r!r})", "below hub_outer_radius_mm")
        _within(w, "hub_outer_radius_mm", hub_r, f"({bore!r}, {rim_i!r}]",
                "bore to rim_inner_radius_mm")
        _within(w, "rim_inner_radius_mm", rim_i, f"[{hub_r!r}, {rim_o!r})", "hub_outer to rim_outer")
        _within(w, "web_thickness_mm", web_t, f"(0, {min(rim_w, self.hub_width_mm)!r}]",
                "<= rim and hub widths")
        lim = (rim_w - web_t) / 2
        _within(w, "web_offset_mm", self.web_offset_mm, f"[{-lim!r}, {lim!r}]",
                "the web inside the rim: |offset| <= (rim_width - web_thickness)/2")
        _within(w, "shaft_outer_radius_mm", self.shaft_mm, f"({bore!r}, {hub_r!r}]",
                "bore to hub outer")
        n, hc, hr = self.holes.count, self.holes.center_radius_mm, self.holes.radius_mm
        h = HolesTable.WHERE
        if n > 0:
            _within(h, "radius_mm", hr, ">= 0.001", "holes need a radius")
            if hub_r >= rim_i:
                raise sc.fail(h, "count", "needs a web (hub_outer_radius_mm < rim_inner)", n)
            _within(h, "center_radius_mm", hc, f"({hub_r + hr!r}, {rim_i - hr!r})",
                    "hub_outer + radius, rim_inner - radius")
            if n > 1:
                _within(h, "radius_mm", hr, f"(0, {hc * math.sin(math.pi / n)!r})",
                        f"{n} holes overlap beyond center_radius * sin(pi / count)")
        return self


#: a bearing's position and band within this many times the body's largest size
_BEARING_REACH = 20
_REACH = f"{_BEARING_REACH} x max(rim_width_mm, hub_width_mm, rim_outer_radius_mm)"


class BearingTable(Section):
    """A ``[[bearings]]`` entry: a bearing node and how it holds the bore (its range is the
    body's: checked by :func:`parse_body`)."""

    axial_position_mm: _number() = Field(**_words(f"[-{_REACH}, {_REACH}]"))
    coupling: Literal[tuple(COUPLINGS)] = "rigid"
    width_mm: _number() | None = Field(None, **_words(f"[0.001, 2 x {_REACH}]"))


def _bearing_tables(value: Any) -> Any:
    """``[[bearings]]`` as written, one inline table as a list of one; none refused."""
    value = [value] if isinstance(value, dict) else value
    if not isinstance(value, list) or not value:
        raise sc.SchemaError("[[bearings]]: at least one [[bearings]] table is required "
                             "(axial_position_mm, coupling)")
    return value


class MaterialTable(Section):
    """``[material]``: isotropic linear elastic (GPa, kg/m^3); up to 1e6 GPa: a rigidified body
    (the seed uses E = 4e14 Pa)."""

    youngs_modulus_GPa: _number("[0.1, 1e+06]") = 210.0
    poisson_ratio: _number("(-1, 0.5)") = 0.3
    density_kg_m3: _number("[100, 1e+06]") = 7800.0

    def material(self) -> Material:
        """The :class:`~fem_prep.Material` (SI)."""
        return Material(self.youngs_modulus_GPa * 1e9, self.poisson_ratio, self.density_kg_m3)


#: an element size's floor: 1e-3 of the rim's outer radius (checked by :func:`parse_body`)
_FLOOR = "1e-3 x rim_outer_radius_mm"


class MeshTable(Section):
    """``[mesh]`` of a body file: the element and the target sizes (mm; ``None``: ``size_mm``)."""

    element: Literal[tuple(ELEMENTS)] = "hex20"
    size_mm: _Length = Field(2.0, **_words(f"{_LENGTH}, >= {_FLOOR}"))
    hub_size_mm: _Length | None = Field(None, **_words(f"{_LENGTH}, >= {_FLOOR}"))
    web_size_mm: _Length | None = Field(None, **_words(f"{_LENGTH}, >= {_FLOOR}"))
    rim_size_mm: _Length | None = Field(None, **_words(f"{_LENGTH}, >= {_FLOOR}"))
    circumferential_size_mm: _Length | None = Field(None, **_words(f"{_LENGTH}, >= {_FLOOR}"))


class CondensationTable(Section):
    """``[condensation]``: the method, its retained modes, the rim masters."""

    method: Literal[tuple(METHODS)] = "craig-bampton"
    modes: _number(f"[0, {MAX_MODES}]", integer=True, note=" (the seed: 50)") = 50
    teeth: _number("[3, 1000]", integer=True)
    axial_master_nodes: _number("[1, 50]", integer=True) = 5
    rim_coupling: Literal[tuple(RIM_COUPLINGS)] = "distributing"

    def condensation(self) -> Condensation:
        """The :class:`~fem_prep.Condensation` (the kinds as objects)."""
        return Condensation(method=METHODS[self.method], modes=self.modes, teeth=self.teeth,
                            axial_master_nodes=self.axial_master_nodes,
                            rim_coupling=RIM_COUPLINGS[self.rim_coupling])


class CentrifugalTable(Section):
    """``[centrifugal]``: up to 1e5 rad/s (as jaxgear's ``[operating] speed_rad_s``): a rim
    speed beyond any steel's."""

    speed_rad_s: _number("[0, 1e+05]") = 0.0
    spin_softening: bool = False


class ModalTable(Section):
    """``[modal]``: the support of the reported frequencies, how many, how many shapes."""

    WHERE: ClassVar[str] = "modal"
    support: Literal[tuple(SUPPORTS)] = "bearings"
    n_frequencies: _number("[1, 200]", integer=True) = 20
    vtu_modes: _number(integer=True, any_size=True) = Field(10, **_words("[0, n_frequencies]"))

    @pydantic.model_validator(mode="after")
    def _shapes(self):
        if "vtu_modes" in self.model_fields_set:  # the default is not checked (as before)
            _within(self.WHERE, "vtu_modes", self.vtu_modes, f"[0, {self.n_frequencies}]",
                    "<= n_frequencies")
        return self


class PinionRimTable(Section):
    """``[pinion_rim]``: a pinion on the shaft beside the wheel (mm; its place is checked
    against the body by :func:`parse_body`)."""

    axial_position_mm: _number() = Field(**_words(
        "its face beside the wheel's hub and rim, on the shaft (hub and stubs to the bearings)"))
    width_mm: _Length
    outer_radius_mm: _Length = Field(**_words(
        "(shaft_outer_radius_mm, rim_outer_radius_mm), within [0.001, 1e+06]"))
    teeth: _number("[3, 1000]", integer=True)
    axial_master_nodes: _number("[1, 50]", integer=True) | None = Field(
        None, **_words(default="[condensation] axial_master_nodes"))


def _file_name(value: Any) -> Any:
    """A ``name`` that is a name, not a path (:func:`fem_prep.checks.name`)."""
    return sc.name({"name": value}, "name", "")


class BodyFile(Section):
    """A body file (``docs/fem_prep.md``): its tables, each checked on its own; what relates
    them (the bearings and the mesh sizes to the body, the pinion rim's place) is
    :func:`parse_body`'s."""

    name: Annotated[Any, AfterValidator(_file_name)] = Field(
        None, **_words(default="the file's name"))
    body: BodyTable
    bearings: Annotated[list[BearingTable], BeforeValidator(_bearing_tables)] = Field(
        default_factory=list, validate_default=True)
    material: MaterialTable = MaterialTable()
    mesh: MeshTable = MeshTable()
    condensation: CondensationTable = Field(default_factory=dict, validate_default=True)
    centrifugal: CentrifugalTable = CentrifugalTable()
    modal: ModalTable = ModalTable()
    pinion_rim: PinionRimTable | None = None


#: the most component modes of a condensation (the seed retains 50)
MAX_MODES = 2000


def estimate_mesh_dofs(
    g: Geometry, ms: MeshSettings, teeth: int, z_span: float = 0.0, pinion=None
) -> int:
    """The DOFs of :func:`fem_prep.mesh_body`'s mesh, estimated from the body's section and the
    element sizes without meshing it: structured hub (with its shaft stubs over ``z_span``, m, the
    bearings' extent), web, rim and pinion rim columns, each of ``nr × nz`` cells with the finest
    axial size (the axial grid is shared), × the circumferential divisions, nodes of the
    serendipity (hex20) or Lagrange (hex27) element counted on that grid (within about 30 % of
    the embedded bodies' meshes)."""
    size = ms.size
    s_hub, s_web, s_rim = (ms.hub_size or size), (ms.web_size or size), (ms.rim_size or size)
    s_circ = ms.circumferential_size or size
    s_z = min(s_hub, s_web, s_rim)
    n = lambda length, s: max(1.0, round(length / s))  # noqa: E731 - divisions of a length
    columns = [
        (g.hub_outer_radius - g.bore_radius, s_hub, max(g.hub_width, z_span)),
        (g.rim_inner_radius - g.hub_outer_radius, s_web, g.web_thickness),
        (g.rim_outer_radius - g.rim_inner_radius, s_rim, g.rim_width),
    ]
    base = teeth
    if pinion is not None:
        columns.append((pinion.outer_radius - g.shaft_outer_radius, s_rim, pinion.width))
        base = math.lcm(teeth, pinion.teeth)
    nt = base * max(1, math.ceil(2 * math.pi * g.rim_outer_radius / (base * s_circ) - 0.25))
    nodes = 0.0
    for dr, s_r, dz in columns:
        if dr <= 0 or dz <= 0:
            continue
        nr, nz = n(dr, s_r), n(dz, s_z)
        corners = (nr + 1) * (nz + 1)
        edges = nr * (nz + 1) + (nr + 1) * nz + corners  # radial, axial, circumferential
        faces = nr * nz + nr * (nz + 1) + (nr + 1) * nz  # hex27: face and centre nodes
        nodes += nt * (corners + edges + ms.element.inner_nodes(faces, nr * nz))
    return int(3 * nodes)


def _check_mesh_size(ms: dict, mesh: MeshSettings, g: Geometry, bearings, teeth, pinion) -> None:
    """Refuse, before meshing, a mesh of more than :data:`MAX_MESH_DOFS` (estimated), naming the
    smallest element size given (``size_mm`` by default)."""
    zb = [b.axial_position for b in bearings]
    span = max(zb) - min(zb) if zb else 0.0
    dofs = estimate_mesh_dofs(g, mesh, teeth, span, pinion)
    if dofs <= MAX_MESH_DOFS:
        return
    given = {k: v for k, v in ms.items() if k.endswith("size_mm")} or {"size_mm": 2.0}
    key = min(given, key=lambda k: given[k])
    raise sc.fail(
        "mesh",
        key,
        f"out of range: the mesh would have about {dofs:.3g} DOFs ({mesh.element}), allowed <= "
        f"{MAX_MESH_DOFS:.3g} (about {MAX_MESH_DOFS * 1e4 / 1e9:.3g} GB to assemble): raise "
        f"{key}",
        given[key],
    )


def parse_body(text: str, *, default_name: str = "body", label: str = "body file") -> Body:
    """Parse and validate body-file TOML text.

    Args:
        text: the TOML text (schema in ``docs/fem_prep.md``).
        default_name: name used when the file has no ``name`` key.
        label: how TOML syntax errors name the file.

    Returns:
        The validated :class:`Body` (SI units).

    Raises:
        SchemaError (a ``ValueError``, see :mod:`fem_prep.checks`): invalid TOML, an unknown key
            (named), a missing required key, a wrong type, or an impossible dimension; one line
            naming the key, its value in mm/deg as written and the allowed range.
    """
    data = sc.load_toml(text, label)
    f = BodyFile.read(data)
    name = sc.name({}, "name", "", default_name) if f.name is None else f.name
    b, mm = f.body, 1e-3
    n_holes, holes = b.holes.count, b.holes
    geometry = Geometry(
        bore_radius=b.bore_radius_mm * mm,
        hub_outer_radius=b.hub_outer_radius_mm * mm,
        hub_width=b.hub_width_mm * mm,
        web_thickness=b.web_thickness_mm * mm,
        web_offset=b.web_offset_mm * mm,
        web_inclination=math.radians(b.web_inclination_deg),
        rim_inner_radius=b.rim_inner_radius_mm * mm,
        rim_outer_radius=b.rim_outer_radius_mm * mm,
        rim_width=b.rim_width_mm * mm,
        holes=Holes(n_holes, holes.center_radius_mm * mm if n_holes else 0.0,
                    holes.radius_mm * mm if n_holes else 0.0),
        shaft_outer_radius=b.shaft_mm * mm,
    )
    bearings = _bearings(f.bearings, b, geometry)
    floor = float(f"{1e-3 * b.rim_outer_radius_mm:.6g}")  # the bound as printed (0.052 for 52 mm)
    sizes = {}
    for key in ("size_mm", "hub_size_mm", "web_size_mm", "rim_size_mm", "circumferential_size_mm"):
        v = getattr(f.mesh, key)
        if v is not None:
            _within("mesh", key, v, f">= {floor!r}", _FLOOR)
        sizes[key[:-3]] = None if v is None else v * mm
    mesh = MeshSettings(ELEMENTS[f.mesh.element], **sizes)  # type: ignore[arg-type]
    condensation = f.condensation.condensation()
    pinion = None if f.pinion_rim is None else _pinion_rim(f.pinion_rim, geometry, bearings,
                                                           condensation)
    _check_mesh_size(data.get("mesh", {}), mesh, geometry, bearings, condensation.teeth, pinion)
    return Body(
        name=name,
        geometry=geometry,
        bearings=tuple(bearings),
        material=f.material.material(),
        mesh=mesh,
        condensation=condensation,
        speed=f.centrifugal.speed_rad_s,
        spin_softening=f.centrifugal.spin_softening,
        support=SUPPORTS[f.modal.support],
        n_frequencies=f.modal.n_frequencies,
        vtu_modes=f.modal.vtu_modes,
        pinion_rim=pinion,
        source_text=text,
    )


def _bearings(tables: list[BearingTable], b: BodyTable, g: Geometry) -> list[BearingSeat]:
    """The ``[[bearings]]`` within the body's reach (file units), apart, their bands
    resolved (:func:`_bearing_bands`)."""
    lim = _BEARING_REACH * max(b.rim_width_mm, b.hub_width_mm, b.rim_outer_radius_mm)
    seen: dict[float, int] = {}
    raw = []  # (position, coupling, explicit width or None), mm
    for k, t in enumerate(tables):
        wb, pos = f"bearings[{k}]", t.axial_position_mm
        _within(wb, "axial_position_mm", pos, f"[{-lim!r}, {lim!r}]")
        for other, j in seen.items():
            if abs(other - pos) < 1e-3:
                raise sc.fail(wb, "axial_position_mm", f"same position as bearings[{j}]", pos)
        seen[pos] = k
        if t.width_mm is not None:
            _within(wb, "width_mm", t.width_mm, f"[0.001, {2 * lim!r}]")
        raw.append((pos, COUPLINGS[t.coupling], t.width_mm))
    return _bearing_bands(raw, g, b.hub_width_mm)


def _pinion_rim(
    p: PinionRimTable, g: Geometry, bearings: list[BearingSeat], cond: Condensation
) -> PinionRim:
    """The ``[pinion_rim]`` (file units in, SI out): a pinion ring from the bore to
    ``outer_radius_mm`` over ``width_mm`` at ``axial_position_mm``, beside the wheel's hub and
    rim and on the shaft (within the bore's extent: hub and stubs to the bearings)."""
    w, mm = "pinion_rim", 1e-3
    if g.web_inclination != 0.0:
        raise sc.fail(
            "body",
            "web_inclination_deg",
            "must be 0 on a body with a [pinion_rim] (the pinion sits on the unsheared shaft)",
            math.degrees(g.web_inclination),
        )
    pos, width, radius = p.axial_position_mm, p.width_mm, p.outer_radius_mm
    shaft = g.shaft_outer_radius / mm
    _within(
        w,
        "outer_radius_mm",
        radius,
        f"({shaft!r}, {g.rim_outer_radius / mm!r})",
        "above shaft_outer_radius_mm, its face free, and below the wheel's rim_outer_radius_mm",
    )
    nax = cond.axial_master_nodes if p.axial_master_nodes is None else p.axial_master_nodes
    # beside the wheel: its face clear of the hub and the rim (file units)
    hub = (g.web_offset / mm - g.hub_width / mm / 2, g.web_offset / mm + g.hub_width / mm / 2)
    rim = (-g.rim_width / mm / 2, g.rim_width / mm / 2)
    lo_w, hi_w = min(hub[0], rim[0]), max(hub[1], rim[1])
    if pos + width / 2 > lo_w + 1e-9 and pos - width / 2 < hi_w - 1e-9:
        raise sc.fail(
            w,
            "axial_position_mm",
            f"out of range, allowed <= {lo_w - width / 2:.6g} or >= {hi_w + width / 2:.6g} "
            f"(its {width:.6g} mm face beside the wheel's hub and rim, z from {lo_w:.6g} to "
            f"{hi_w:.6g} mm)",
            pos,
        )
    # on the shaft: within the bore's extent (hub and shaft stubs to the bearings)
    zb = [b.axial_position / mm for b in bearings]
    lo_s, hi_s = min(hub[0], *zb), max(hub[1], *zb)
    if pos - width / 2 < lo_s - 1e-9 or pos + width / 2 > hi_s + 1e-9:
        raise sc.fail(
            w,
            "axial_position_mm",
            f"out of range, allowed [{lo_s + width / 2:.6g}, {hi_s - width / 2:.6g}] (its face "
            f"on the shaft, which runs from {lo_s:.6g} to {hi_s:.6g} mm: hub and stubs to the "
            "bearings)",
            pos,
        )
    return PinionRim(pos * mm, radius * mm, width * mm, p.teeth, nax)


def _bearing_bands(
    raw: list[tuple[float, Kind, float | None]], g: Geometry, hub_w: float
) -> list[BearingSeat]:
    """Resolve each bearing's coupled band (file units in, SI out; see ``docs/fem_prep.md``).

    The bore runs over the hub and the shaft stubs: from ``min(hub start, bearings)`` to
    ``max(hub end, bearings)``.  The default width is ``hub_width / n_bearings``, reduced to
    the distance to the nearest other bearing (bands do not overlap); each band is
    ``position -/+ width / 2`` clipped to the bore.  Explicit widths whose bands overlap raise
    a :class:`SchemaError` naming the later bearing's ``width_mm``.
    """
    hc = g.hub_center * 1e3
    lo = min([hc - hub_w / 2] + [p for p, _, _ in raw])
    hi = max([hc + hub_w / 2] + [p for p, _, _ in raw])
    pos = [p for p, _, _ in raw]
    bands = []
    for k, (p, _, w) in enumerate(raw):
        if w is None:
            gap = min([abs(p - q) for j, q in enumerate(pos) if j != k], default=math.inf)
            w = min(hub_w / len(raw), gap)
        bands.append((w, max(p - w / 2, lo), min(p + w / 2, hi)))
    order = sorted(range(len(raw)), key=lambda k: raw[k][0])
    for i, j in itertools.pairwise(order):  # neighbours along the axis
        overlap = bands[i][2] - bands[j][1]
        if overlap > 1e-6 * max(1.0, abs(hi - lo)):
            # blame the later explicit width in the file (default widths never overlap)
            k = max(m for m in (i, j) if raw[m][2] is not None)
            o = i + j - k
            gap = abs(raw[i][0] - raw[j][0])
            raise sc.fail(
                f"bearings[{k}]",
                "width_mm",
                f"its band [{bands[k][1]:.6g}, {bands[k][2]:.6g}] mm overlaps the band "
                f"[{bands[o][1]:.6g}, {bands[o][2]:.6g}] mm of bearings[{o}] (bands are "
                f"axial_position_mm -/+ width_mm/2 and must not overlap; bearings {gap:.6g} mm "
                "apart)",
                raw[k][2],
            )
    mm = 1e-3
    return [
        BearingSeat(p * mm, c, w * mm, (b0 * mm, b1 * mm))
        for (p, c, _), (w, b0, b1) in zip(raw, bands)
    ]


def embedded_bodies() -> list[str]:
    """Names of the body files shipped with fem_prep (``fem_prep/bodies/*.toml``)."""
    return files.embedded_names(resources.files("fem_prep") / "bodies")


def embedded_body_text(name: str) -> str:
    """The TOML text of the embedded body ``name`` (``fem-prep bodies NAME``).

    Raises:
        FileNotFoundError: ``name`` is not an embedded body (the message lists them).
    """
    return files.embedded_text(resources.files("fem_prep") / "bodies", name, "body")


def load_body(source: str | Path) -> Body:
    """Load a body from a file path or an embedded body name.

    Args:
        source: path to a ``.toml`` body file, or the name of an embedded body
            (see :func:`embedded_bodies`), e.g. ``"accessory-wheel"``.

    Returns:
        The validated :class:`Body`.

    Raises:
        FileNotFoundError: neither a file nor an embedded body of that name exists.
        SchemaError (a ``ValueError``): the file is not UTF-8 or is invalid (see
            :func:`parse_body`).
    """
    path = Path(source)
    if path.is_file():
        label = f"body file {str(source)!r}"
        return parse_body(_decode(path.read_bytes(), label), default_name=path.stem, label=label)
    name = str(source)
    if name in embedded_bodies():
        return parse_body(
            embedded_body_text(name), default_name=name, label=f"embedded body {name!r}"
        )
    raise FileNotFoundError(
        f"body file {str(source)!r} not found (and it is not an embedded body"
        f"{sc.did_you_mean(name, embedded_bodies())}; embedded bodies: "
        f"{', '.join(embedded_bodies())})"
    )


def _decode(raw: bytes, label: str) -> str:
    try:
        return raw.decode("utf-8")
    except UnicodeDecodeError:
        sc.load_toml(raw, label)  # raises the one-line SchemaError naming the file
        raise  # pragma: no cover


# --------------------------------------------------------------------------------------------
# Ring-gear body files (fem_prep._ring): [ring], [support], [material], [mesh], [condensation]


class RingTable(Section):
    """``[ring]``: the ring's root and outer radii and face width (mm)."""

    WHERE: ClassVar[str] = "ring"
    root_radius_mm: _Length
    outer_radius_mm: _number() = Field(**_words("(root_radius_mm, 1e+06]"))
    width_mm: _Length

    @pydantic.model_validator(mode="after")
    def _outside(self):
        _within(self.WHERE, "outer_radius_mm", self.outer_radius_mm,
                f"({self.root_radius_mm!r}, 1e+06]")
        return self


def _bolted(t: SupportTable) -> BoltedFlange:
    return BoltedFlange(bolts=t.bolts, seat_arc=1e-3 * t.seat_arc_mm,
                        phase=math.radians(t.phase_deg))


def _foundation(t: SupportTable) -> ElasticFoundation:
    # N/mm^3 = 1e9 N/m^3 (Pa/m)
    k = (t.radial_N_per_mm3, t.tangential_N_per_mm3, t.axial_N_per_mm3)
    return ElasticFoundation(*(1e9 * v for v in k))


def _free(t: SupportTable) -> FreeRing:
    return FreeRing()


#: the ring supports by their file name (``[support] kind``): how each is built from its table
#: and the keys it requires (the other kinds' keys are checked and left unused)
RING_SUPPORTS = {
    "bolted_flange": (_bolted, ("bolts", "seat_arc_mm")),
    "elastic_foundation": (_foundation, ("radial_N_per_mm3", "tangential_N_per_mm3",
                                         "axial_N_per_mm3")),
    "free": (_free, ()),
}


class SupportTable(Section):
    """``[support]``: how the housing holds the ring (``kind``), with the keys of its kind."""

    WHERE: ClassVar[str] = "support"
    kind: Literal[tuple(RING_SUPPORTS)]
    bolts: _number("[1, 1000]", integer=True) | None = None
    seat_arc_mm: _Length | None = None
    phase_deg: _number("[-360, 360]") = 0.0
    radial_N_per_mm3: _number("(0, 1e+09]") | None = None
    tangential_N_per_mm3: _number("(0, 1e+09]") | None = None
    axial_N_per_mm3: _number("(0, 1e+09]") | None = None

    @pydantic.model_validator(mode="after")
    def _kind_keys(self):
        for key in RING_SUPPORTS[self.kind][1]:
            if getattr(self, key) is None:
                raise sc.fail(self.WHERE, key, "missing required key")
        return self

    def support(self):
        """The ring support of :attr:`kind` (:class:`~fem_prep.BoltedFlange`,
        :class:`~fem_prep.ElasticFoundation`, :class:`~fem_prep.FreeRing`; SI)."""
        return RING_SUPPORTS[self.kind][0](self)


class RingMeshTable(Section):
    """``[mesh]`` of a ring file: the element, the size (mm), the circumferential size."""

    element: Literal[tuple(ELEMENTS)] = "hex20"
    size_mm: _Length
    circumferential_size_mm: _Length | None = Field(None, **_words(default="size_mm"))


class RingCondensationTable(CondensationTable):
    """``[condensation]`` of a ring file: two axial master planes by default."""

    modes: _number(f"[0, {MAX_MODES}]", integer=True) = 50
    axial_master_nodes: _number("[1, 50]", integer=True) = 2


class RingFile(Section):
    """A ring-gear body file (docs/planetary.md, "A flexible ring gear")."""

    name: Annotated[Any, AfterValidator(_file_name)] = None
    ring: RingTable
    support: SupportTable
    material: MaterialTable = MaterialTable()
    mesh: RingMeshTable = Field(default_factory=dict, validate_default=True)
    condensation: RingCondensationTable


def parse_ring_body(text: str, *, default_name: str = "ring", label: str = "ring file") -> RingBody:
    """Parse and validate a ring-gear body file (TOML; lengths in mm, the modulus in GPa, the
    foundation in N/mm^3; docs/planetary.md, "A flexible ring gear").

    Returns:
        The :class:`~fem_prep.RingBody` (SI units).

    Raises:
        SchemaError: an unknown or missing key, a wrong type or a value out of range (one line
            naming the key, its value as written and the allowed range).
    """
    f = RingFile.read(sc.load_toml(text, label))
    name = sc.name({}, "name", "", default_name) if f.name is None else f.name
    r, ms = f.ring, f.mesh
    circ = ms.size_mm if ms.circumferential_size_mm is None else ms.circumferential_size_mm
    mesh = MeshSettings(ELEMENTS[ms.element], size=1e-3 * ms.size_mm,
                        circumferential_size=1e-3 * circ)
    return RingBody(name, 1e-3 * r.root_radius_mm, 1e-3 * r.outer_radius_mm, 1e-3 * r.width_mm,
                    f.material.material(), mesh, f.condensation.condensation(),
                    f.support.support())
