"""The body file's schema: the body-file reader of fem_prep, the one place that maps the names
in a body file to objects.

:func:`parse_body` checks a ``body.toml`` (schema in ``docs/fem_prep.md``) and builds a
:class:`~fem_prep.Body`; the kinds the file names (``element``, ``coupling``, ``method``,
``rim_coupling``, ``support``) become objects here and only here, by the tables :data:`ELEMENTS`,
:data:`COUPLINGS`, :data:`METHODS`, :data:`RIM_COUPLINGS` and :data:`SUPPORTS` (a new kind: one
more class beside its algorithm and one more entry here).  All lengths in the file are in mm, the
modulus in GPa; :class:`~fem_prep.Body` stores SI values (m, Pa, kg/m^3) next to the raw text.

Every error is a :class:`SchemaError` (a ``ValueError``) whose one-line message names the
offending key, its value as written in the file (mm, deg) and the allowed range, so that a user can
fix the file without reading the code; integer keys accept integral floats (``modes = 50.0``) and
reject others (``modes = 50.5``), as in jaxgear's case files.

The checking helpers shared with jaxgear's case files live in :mod:`fem_prep.checks`, the atomic
writers and embedded-file helpers in :mod:`fem_prep.files`; their names are re-exported here for
the code that still imports them from ``fem_prep.schema``.
"""

from __future__ import annotations

import functools
import itertools
import math
from importlib import resources
from pathlib import Path
from typing import Any

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


def _kind(table: dict, key: str, where: str, kinds: dict[str, Kind], default: str) -> Any:
    """The kind object that ``table[key]`` names (``default`` when absent), out of ``kinds``."""
    return kinds[sc.choice(table, key, where, kinds, default)]


@functools.singledispatch
def _tables(value: Any) -> Any:
    """An array of tables as written (``[[bearings]]``), one inline table as a list of one."""
    return value


@_tables.register
def _(value: dict) -> list:
    return [value]


# --------------------------------------------------------------------------------------------
# Parsing (checks and messages from fem_prep.checks, shared with jaxgear's case files)

_SCHEMA: dict[str, set[str] | None] = {
    "name": None,
    "body": {
        "bore_radius_mm",
        "hub_outer_radius_mm",
        "hub_width_mm",
        "web_thickness_mm",
        "web_offset_mm",
        "web_inclination_deg",
        "rim_inner_radius_mm",
        "rim_outer_radius_mm",
        "rim_width_mm",
        "holes",
        "shaft_outer_radius_mm",
    },
    "bearings": {"axial_position_mm", "coupling", "width_mm"},
    "material": {"youngs_modulus_GPa", "poisson_ratio", "density_kg_m3"},
    "mesh": {
        "element",
        "size_mm",
        "hub_size_mm",
        "web_size_mm",
        "rim_size_mm",
        "circumferential_size_mm",
    },
    "condensation": {"method", "modes", "teeth", "axial_master_nodes", "rim_coupling"},
    "centrifugal": {"speed_rad_s", "spin_softening"},
    "modal": {"support", "n_frequencies", "vtu_modes"},
    "pinion_rim": {
        "axial_position_mm",
        "outer_radius_mm",
        "width_mm",
        "teeth",
        "axial_master_nodes",
    },
}
_HOLES_KEYS = {"count", "center_radius_mm", "radius_mm"}
_LENGTH = "[0.001, 1e+06]"  # mm: 1 µm to 1 km (a denormal passes "> 0" and fails the mesher)


#: the most DOFs a body's mesh may have (the embedded bodies: 17 k to 104 k): its assembly
#: alone takes about 10 kB a DOF (20 GB here), the factorisation more
MAX_MESH_DOFS = 2_000_000
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


def _within(key: str, value: float, rng: str, note: str, where: str = "body") -> None:
    """Raise ``[where] key = value: out of range, allowed rng (note)`` unless value in rng."""
    r = sc.interval(rng)
    if value not in r:
        raise sc.fail(where, key, f"out of range, allowed {r} ({note})", value)


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
    sc.check_keys(data, _SCHEMA, "")
    name = sc.name(data, "name", "", default_name)

    # ---- [body]
    b = sc.subtable(data, "body", "", _SCHEMA["body"], required=True)
    w = "body"
    mm = 1e-3
    bore = sc.number(b, "bore_radius_mm", w, allowed=_LENGTH)
    hub_r = sc.number(b, "hub_outer_radius_mm", w, allowed=_LENGTH)
    hub_w = sc.number(b, "hub_width_mm", w, allowed=_LENGTH)
    web_t = sc.number(b, "web_thickness_mm", w, allowed=_LENGTH)
    web_off = sc.number(b, "web_offset_mm", w, 0.0)
    incl_deg = sc.number(b, "web_inclination_deg", w, 0.0, allowed="(-60, 60)")
    rim_i = sc.number(b, "rim_inner_radius_mm", w, allowed=_LENGTH)
    rim_o = sc.number(b, "rim_outer_radius_mm", w, allowed=_LENGTH)
    rim_w = sc.number(b, "rim_width_mm", w, allowed=_LENGTH)
    shaft_r = sc.number(b, "shaft_outer_radius_mm", w, hub_r, allowed=_LENGTH)
    _within("bore_radius_mm", bore, f"(0, {hub_r!r})", "below hub_outer_radius_mm")
    _within("hub_outer_radius_mm", hub_r, f"({bore!r}, {rim_i!r}]", "bore to rim_inner_radius_mm")
    _within("rim_inner_radius_mm", rim_i, f"[{hub_r!r}, {rim_o!r})", "hub_outer to rim_outer")
    _within("web_thickness_mm", web_t, f"(0, {min(rim_w, hub_w)!r}]", "<= rim and hub widths")
    lim = (rim_w - web_t) / 2
    _within(
        "web_offset_mm",
        web_off,
        f"[{-lim!r}, {lim!r}]",
        "the web inside the rim: |offset| <= (rim_width - web_thickness)/2",
    )
    _within("shaft_outer_radius_mm", shaft_r, f"({bore!r}, {hub_r!r}]", "bore to hub outer")

    h = b.get("holes", {})
    if not isinstance(h, dict):
        raise sc.fail(
            w, "holes", "must be an inline table { count, center_radius_mm, radius_mm }", h
        )
    h = {f"holes.{k}": v for k, v in h.items()}  # messages: [body] holes.count = ...
    sc.check_keys(h, {f"holes.{k}" for k in _HOLES_KEYS}, w)
    n_holes = sc.number(h, "holes.count", w, 0, allowed="[0, 10000]", integer=True)
    hc = sc.number(h, "holes.center_radius_mm", w, 0.0, allowed=">= 0")
    hr = sc.number(h, "holes.radius_mm", w, 0.0, allowed=">= 0")
    if n_holes > 0:
        _within("holes.radius_mm", hr, ">= 0.001", "holes need a radius")
        if hub_r >= rim_i:
            raise sc.fail(
                w, "holes.count", "needs a web (hub_outer_radius_mm < rim_inner)", n_holes
            )
        _within(
            "holes.center_radius_mm",
            hc,
            f"({hub_r + hr!r}, {rim_i - hr!r})",
            "hub_outer + radius, rim_inner - radius",
        )
        if n_holes > 1:
            rmax = hc * math.sin(math.pi / n_holes)
            _within(
                "holes.radius_mm",
                hr,
                f"(0, {rmax!r})",
                f"{n_holes} holes overlap beyond center_radius * sin(pi / count)",
            )
    geometry = Geometry(
        bore_radius=bore * mm,
        hub_outer_radius=hub_r * mm,
        hub_width=hub_w * mm,
        web_thickness=web_t * mm,
        web_offset=web_off * mm,
        web_inclination=math.radians(incl_deg),
        rim_inner_radius=rim_i * mm,
        rim_outer_radius=rim_o * mm,
        rim_width=rim_w * mm,
        holes=Holes(n_holes, hc * mm if n_holes else 0.0, hr * mm if n_holes else 0.0),
        shaft_outer_radius=shaft_r * mm,
    )

    # ---- [[bearings]]
    bl = _tables(data.get("bearings", []))
    if not isinstance(bl, list) or not bl:
        raise sc.SchemaError(
            "[[bearings]]: at least one [[bearings]] table is required (axial_position_mm, "
            "coupling)"
        )
    lim = 20 * max(rim_w, hub_w, rim_o)
    seen: dict[float, int] = {}
    raw = []  # (position, coupling, explicit width or None), mm
    for k, t in enumerate(bl):
        wb = f"bearings[{k}]"
        if not isinstance(t, dict):
            raise sc.fail("", wb, "must be a table", t)
        sc.check_keys(t, _SCHEMA["bearings"], wb)  # type: ignore[arg-type]
        pos = sc.number(t, "axial_position_mm", wb, allowed=f"[{-lim!r}, {lim!r}]")
        for other, j in seen.items():
            if abs(other - pos) < 1e-3:
                raise sc.fail(wb, "axial_position_mm", f"same position as bearings[{j}]", pos)
        seen[pos] = k
        coupling = _kind(t, "coupling", wb, COUPLINGS, "rigid")
        width = sc.number(t, "width_mm", wb, None, allowed=f"[0.001, {2 * lim!r}]")
        raw.append((pos, coupling, width))
    bearings = _bearing_bands(raw, geometry, hub_w)

    # ---- [material]
    m = sc.subtable(data, "material", "", _SCHEMA["material"])
    # up to 1e6 GPa: a rigidified body (the seed uses E = 4e14 Pa)
    e = sc.number(m, "youngs_modulus_GPa", "material", 210.0, allowed="[0.1, 1e+06]")
    nu = sc.number(m, "poisson_ratio", "material", 0.3, allowed="(-1, 0.5)")
    rho = sc.number(m, "density_kg_m3", "material", 7800.0, allowed="[100, 1e+06]")
    material = Material(e * 1e9, nu, rho)

    # ---- [mesh]
    ms = sc.subtable(data, "mesh", "", _SCHEMA["mesh"])
    element = _kind(ms, "element", "mesh", ELEMENTS, "hex20")
    floor = float(f"{1e-3 * rim_o:.6g}")  # the bound as printed (0.052 for a 52 mm rim)
    sizes = {}
    for key in ("size_mm", "hub_size_mm", "web_size_mm", "rim_size_mm", "circumferential_size_mm"):
        v = sc.number(ms, key, "mesh", 2.0 if key == "size_mm" else None, allowed=_LENGTH)
        if v is not None:
            _within(key, v, f">= {floor!r}", "1e-3 x rim_outer_radius_mm", "mesh")
        sizes[key[:-3]] = None if v is None else v * mm
    mesh = MeshSettings(element, **sizes)  # type: ignore[arg-type]

    # ---- [condensation]
    c = sc.subtable(data, "condensation", "", _SCHEMA["condensation"])
    w = "condensation"
    condensation = Condensation(
        method=_kind(c, "method", w, METHODS, "craig-bampton"),
        modes=sc.number(
            c, "modes", w, 50, allowed=f"[0, {MAX_MODES}]", integer=True, note=" (the seed: 50)"
        ),
        teeth=sc.number(c, "teeth", w, allowed="[3, 1000]", integer=True),
        axial_master_nodes=sc.number(
            c, "axial_master_nodes", w, 5, allowed="[1, 50]", integer=True
        ),
        rim_coupling=_kind(c, "rim_coupling", w, RIM_COUPLINGS, "distributing"),
    )

    # ---- [centrifugal]
    cf = sc.subtable(data, "centrifugal", "", _SCHEMA["centrifugal"])
    # up to 1e5 rad/s (as jaxgear's [operating] speed_rad_s): a rim speed beyond any steel's
    speed = sc.number(cf, "speed_rad_s", "centrifugal", 0.0, allowed="[0, 1e+05]")
    spin = sc.boolean(cf, "spin_softening", "centrifugal", False)

    # ---- [modal] (optional extension)
    md = sc.subtable(data, "modal", "", _SCHEMA["modal"])
    support = _kind(md, "support", "modal", SUPPORTS, "bearings")
    nf = sc.number(md, "n_frequencies", "modal", 20, allowed="[1, 200]", integer=True)
    nv = sc.number(
        md, "vtu_modes", "modal", 10, allowed=f"[0, {nf}]", integer=True, note=" (<= n_frequencies)"
    )

    pinion = _pinion_rim(data, geometry, bearings, condensation)
    _check_mesh_size(ms, mesh, geometry, bearings, condensation.teeth, pinion)

    return Body(
        name=name,
        geometry=geometry,
        bearings=tuple(bearings),
        material=material,
        mesh=mesh,
        condensation=condensation,
        speed=speed,
        spin_softening=spin,
        support=support,
        n_frequencies=nf,
        vtu_modes=nv,
        pinion_rim=pinion,
        source_text=text,
    )


def _pinion_rim(
    data: dict, g: Geometry, bearings: list[BearingSeat], cond: Condensation
) -> PinionRim | None:
    """The optional ``[pinion_rim]`` (file units in, SI out): a pinion ring from the bore to
    ``outer_radius_mm`` over ``width_mm`` at ``axial_position_mm``, beside the wheel's hub and
    rim and on the shaft (within the bore's extent: hub and stubs to the bearings)."""
    if "pinion_rim" not in data:
        return None
    p = sc.subtable(data, "pinion_rim", "", _SCHEMA["pinion_rim"])
    w = "pinion_rim"
    mm = 1e-3
    if g.web_inclination != 0.0:
        raise sc.fail(
            "body",
            "web_inclination_deg",
            "must be 0 on a body with a [pinion_rim] (the pinion sits on the unsheared shaft)",
            math.degrees(g.web_inclination),
        )
    pos = sc.number(p, "axial_position_mm", w)
    width = sc.number(p, "width_mm", w, allowed=_LENGTH)
    shaft = g.shaft_outer_radius / mm
    radius = sc.number(p, "outer_radius_mm", w, allowed=_LENGTH)
    _within(
        "outer_radius_mm",
        radius,
        f"({shaft!r}, {g.rim_outer_radius / mm!r})",
        "above shaft_outer_radius_mm, its face free, and below the wheel's rim_outer_radius_mm",
        w,
    )
    teeth = sc.number(p, "teeth", w, allowed="[3, 1000]", integer=True)
    nax = sc.number(
        p, "axial_master_nodes", w, cond.axial_master_nodes, allowed="[1, 50]", integer=True
    )
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
    return PinionRim(pos * mm, radius * mm, width * mm, teeth, nax)


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

_RING_SCHEMA: dict[str, set[str] | None] = {
    "name": None,
    "ring": {"root_radius_mm", "outer_radius_mm", "width_mm"},
    "support": {"kind", "bolts", "seat_arc_mm", "phase_deg", "radial_N_per_mm3",
                "tangential_N_per_mm3", "axial_N_per_mm3"},
    "material": _SCHEMA["material"],
    "mesh": {"element", "size_mm", "circumferential_size_mm"},
    "condensation": {"method", "modes", "teeth", "axial_master_nodes", "rim_coupling"},
}


def _bolted(t: dict) -> BoltedFlange:
    return BoltedFlange(
        bolts=sc.number(t, "bolts", "support", allowed="[1, 1000]", integer=True),
        seat_arc=1e-3 * sc.number(t, "seat_arc_mm", "support", allowed=_LENGTH),
        phase=math.radians(sc.number(t, "phase_deg", "support", 0.0, allowed="[-360, 360]")),
    )


def _foundation(t: dict) -> ElasticFoundation:
    # N/mm^3 = 1e9 N/m^3 (Pa/m)
    k = [sc.number(t, f"{d}_N_per_mm3", "support", allowed="(0, 1e+09]")
         for d in ("radial", "tangential", "axial")]
    return ElasticFoundation(*(1e9 * v for v in k))


def _free(t: dict) -> FreeRing:
    return FreeRing()


#: the ring supports by their body-file name (``[support] kind``), each built from its table
RING_SUPPORTS = {"bolted_flange": _bolted, "elastic_foundation": _foundation, "free": _free}


def parse_ring_body(text: str, *, default_name: str = "ring", label: str = "ring file") -> RingBody:
    """Parse and validate a ring-gear body file (TOML; lengths in mm, the modulus in GPa, the
    foundation in N/mm^3; docs/planetary.md, "A flexible ring gear").

    Returns:
        The :class:`~fem_prep.RingBody` (SI units).

    Raises:
        SchemaError: an unknown or missing key, a wrong type or a value out of range (one line
            naming the key, its value as written and the allowed range).
    """
    data = sc.load_toml(text, label)
    sc.check_keys(data, _RING_SCHEMA, "")
    name = sc.name(data, "name", "", default_name)
    r = sc.subtable(data, "ring", "", _RING_SCHEMA["ring"], required=True)
    r_f = sc.number(r, "root_radius_mm", "ring", allowed=_LENGTH)
    r_o = sc.number(r, "outer_radius_mm", "ring", allowed=f"({r_f!r}, 1e+06]")
    width = sc.number(r, "width_mm", "ring", allowed=_LENGTH)
    t = sc.subtable(data, "support", "", _RING_SCHEMA["support"], required=True)
    support = RING_SUPPORTS[sc.choice(t, "kind", "support", RING_SUPPORTS)](t)
    m = sc.subtable(data, "material", "", _RING_SCHEMA["material"])
    material = Material(
        1e9 * sc.number(m, "youngs_modulus_GPa", "material", 210.0, allowed="[0.1, 1e+06]"),
        sc.number(m, "poisson_ratio", "material", 0.3, allowed="(-1, 0.5)"),
        sc.number(m, "density_kg_m3", "material", 7800.0, allowed="[100, 1e+06]"),
    )
    ms = sc.subtable(data, "mesh", "", _RING_SCHEMA["mesh"])
    size = sc.number(ms, "size_mm", "mesh", allowed=_LENGTH)
    circ = sc.number(ms, "circumferential_size_mm", "mesh", size, allowed=_LENGTH)
    mesh = MeshSettings(
        _kind(ms, "element", "mesh", ELEMENTS, "hex20"), size=1e-3 * size,
        circumferential_size=1e-3 * circ,
    )
    c = sc.subtable(data, "condensation", "", _RING_SCHEMA["condensation"], required=True)
    w = "condensation"
    condensation = Condensation(
        method=_kind(c, "method", w, METHODS, "craig-bampton"),
        modes=sc.number(c, "modes", w, 50, allowed=f"[0, {MAX_MODES}]", integer=True),
        teeth=sc.number(c, "teeth", w, allowed="[3, 1000]", integer=True),
        axial_master_nodes=sc.number(c, "axial_master_nodes", w, 2, allowed="[1, 50]",
                                     integer=True),
        rim_coupling=_kind(c, "rim_coupling", w, RIM_COUPLINGS, "distributing"),
    )
    return RingBody(name, 1e-3 * r_f, 1e-3 * r_o, 1e-3 * width, material, mesh, condensation,
                    support)

