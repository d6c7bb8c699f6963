"""Body-file schema: parsing and validation of the ``body.toml`` that describes a gear body.

The schema is documented in ``docs/fem_prep.md``.  All lengths in the file are in mm, the
modulus in GPa; :class:`Body` stores SI values (m, Pa, kg/m^3) next to the raw text.

Every error is a :class:`ValueError` whose message names the offending key, its value and the
allowed range, so that a user can fix the file without reading the code.
"""

from __future__ import annotations

import hashlib
import json
import math
import tomllib
from dataclasses import asdict, dataclass, field
from importlib import resources
from pathlib import Path
from typing import Any

__all__ = [
    "Bearing",
    "Body",
    "Condensation",
    "Geometry",
    "Holes",
    "Material",
    "MeshSettings",
    "embedded_bodies",
    "load_body",
    "parse_body",
]

METHODS = ("guyan", "craig-bampton", "herting")
ELEMENTS = ("hex20", "hex27")
COUPLINGS = ("rigid", "averaging")
SUPPORTS = ("bearings", "free")


@dataclass(frozen=True)
class Holes:
    """Circular holes in the web (approximated by removing elements, see ``_mesh``).

    Attributes:
        count: number of holes, evenly spaced in angle (0 = no holes).
        center_radius: radius of the hole centres (m).
        radius: hole radius (m).
    """

    count: int = 0
    center_radius: float = 0.0
    radius: float = 0.0


@dataclass(frozen=True)
class Geometry:
    """Axisymmetric meridian section; ``z = 0`` at mid-rim. All lengths in m.

    The web mid-plane passes through ``z = web_offset`` at the rim junction (``r =
    rim_inner_radius``) and moves by ``(rim_inner_radius - r) tan(web_inclination)`` towards
    ``+z`` as the radius decreases (a conical web for a positive inclination).  The hub is
    centred axially on the web mid-plane at the hub junction.  Shaft stubs (tubes from the bore
    to ``shaft_outer_radius``) extend the hub axially to bearings that lie outside it.
    """

    bore_radius: float
    hub_outer_radius: float
    hub_width: float
    web_thickness: float
    web_offset: float
    web_inclination: float  # rad
    rim_inner_radius: float
    rim_outer_radius: float
    rim_width: float
    holes: Holes
    shaft_outer_radius: float

    @property
    def hub_shift(self) -> float:
        """Axial shift of the hub centre relative to the web offset (m)."""
        return (self.rim_inner_radius - self.hub_outer_radius) * math.tan(self.web_inclination)

    @property
    def hub_center(self) -> float:
        """Axial position of the hub centre (m)."""
        return self.web_offset + self.hub_shift


@dataclass(frozen=True)
class Bearing:
    """A 6-DOF bearing node on the axis, coupled to the bore ring at ``axial_position`` (m)."""

    axial_position: float
    coupling: str = "rigid"


@dataclass(frozen=True)
class Material:
    """Isotropic linear elastic material (SI: Pa, -, kg/m^3)."""

    youngs_modulus: float = 210e9
    poisson_ratio: float = 0.3
    density: float = 7800.0

    @property
    def lame(self) -> tuple[float, float]:
        """Lamé parameters ``(lambda, mu)`` in Pa."""
        e, nu = self.youngs_modulus, self.poisson_ratio
        return e * nu / ((1 + nu) * (1 - 2 * nu)), e / (2 * (1 + nu))


@dataclass(frozen=True)
class MeshSettings:
    """Target element edge lengths (m) per region; ``None`` = use ``size``."""

    element: str = "hex20"
    size: float = 2e-3
    hub_size: float | None = None
    web_size: float | None = None
    rim_size: float | None = None
    circumferential_size: float | None = None


@dataclass(frozen=True)
class Condensation:
    """Condensation settings (seed (2.3)-(2.5))."""

    method: str = "craig-bampton"
    modes: int = 50
    teeth: int = 0
    axial_master_nodes: int = 5


@dataclass(frozen=True)
class Body:
    """A validated gear body description (SI units).

    Attributes:
        name: body name.
        geometry: meridian section.
        bearings: bearing nodes (at least one).
        material: elastic material.
        mesh: mesh settings.
        condensation: condensation settings.
        speed: rotation speed for the centrifugal deflection (rad/s).
        spin_softening: also assemble the spin-softening matrix.
        support: ``"bearings"`` (bearing nodes held) or ``"free"`` for the reported frequencies.
        n_frequencies: number of frequencies reported in ``summary.json``.
        vtu_modes: number of mode shapes written to the VTU file.
        source_text: the TOML text the body was parsed from.
    """

    name: str
    geometry: Geometry
    bearings: tuple[Bearing, ...]
    material: Material
    mesh: MeshSettings
    condensation: Condensation
    speed: float = 0.0
    spin_softening: bool = False
    support: str = "bearings"
    n_frequencies: int = 20
    vtu_modes: int = 10
    source_text: str = field(default="", compare=False, repr=False)

    def canonical(self) -> dict[str, Any]:
        """Plain-dict form of the parsed body (without the source text)."""
        d = asdict(self)
        d.pop("source_text")
        return d

    @property
    def sha256(self) -> str:
        """Hash of the canonical parsed body: the cache key (comments/format do not matter)."""
        blob = json.dumps(self.canonical(), sort_keys=True).encode()
        return hashlib.sha256(blob).hexdigest()

    @property
    def text_sha256(self) -> str:
        """sha256 of the TOML text the body came from."""
        return hashlib.sha256(self.source_text.encode()).hexdigest()


# --------------------------------------------------------------------------------------------
# Parsing helpers

_SCHEMA: dict[str, dict[str, Any] | None] = {
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
    "bearings": {"axial_position_mm", "coupling"},
    "material": {"youngs_modulus_GPa", "poisson_ratio", "density_kg_m3"},
    "mesh": {
        "element",
        "size_mm",
        "hub_size_mm",
        "web_size_mm",
        "rim_size_mm",
        "circumferential_size_mm",
    },
    "condensation": {"method", "modes", "teeth", "axial_master_nodes"},
    "centrifugal": {"speed_rad_s", "spin_softening"},
    "modal": {"support", "n_frequencies", "vtu_modes"},
}
_HOLES_KEYS = {"count", "center_radius_mm", "radius_mm"}


def _check_keys(table: dict[str, Any], allowed: set[str], where: str) -> None:
    for key in table:
        if key not in allowed:
            raise ValueError(
                f"unknown key {where}{key!r} in body file; allowed keys here: "
                f"{', '.join(sorted(allowed))}"
            )


def _num(table: dict[str, Any], key: str, where: str, default: float | None = None) -> float:
    if key not in table:
        if default is None:
            raise ValueError(f"missing required key {where}{key} in body file")
        return float(default)
    v = table[key]
    if isinstance(v, bool) or not isinstance(v, (int, float)):
        raise ValueError(f"{where}{key} must be a number, got {v!r}")
    if not math.isfinite(v):
        raise ValueError(f"{where}{key} must be finite, got {v!r}")
    return float(v)


def _int(table: dict[str, Any], key: str, where: str, default: int | None = None) -> int:
    if key not in table:
        if default is None:
            raise ValueError(f"missing required key {where}{key} in body file")
        return default
    v = table[key]
    if isinstance(v, bool) or not isinstance(v, int):
        raise ValueError(f"{where}{key} must be an integer, got {v!r}")
    return int(v)


def _str(
    table: dict[str, Any], key: str, where: str, allowed: tuple[str, ...], default: str
) -> str:
    v = table.get(key, default)
    if not isinstance(v, str) or v not in allowed:
        raise ValueError(f"{where}{key} = {v!r} is not allowed; use one of {', '.join(allowed)}")
    return v


def _positive(name: str, v: float) -> None:
    if not v > 0:
        raise ValueError(f"{name} = {v:g} must be > 0")


def _table(data: dict[str, Any], key: str) -> dict[str, Any]:
    t = data.get(key, {})
    if not isinstance(t, dict):
        raise ValueError(f"[{key}] must be a table")
    return t


def parse_body(text: str, *, default_name: str = "body") -> Body:
    """Parse and validate body-file TOML text.

    Args:
        text: the TOML text (schema in ``docs/fem_prep.md``).
        default_name: name used when the file has no ``name`` key.

    Returns:
        The validated :class:`Body` (SI units).

    Raises:
        ValueError: invalid TOML, an unknown key (named), a missing required key, or an
            impossible dimension (message names the parameter, its value and the allowed range).
    """
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ValueError(f"body file is not valid TOML: {exc}") from exc
    _check_keys(data, set(_SCHEMA), "")
    name = data.get("name", default_name)
    if not isinstance(name, str) or not name:
        raise ValueError(f"name must be a non-empty string, got {name!r}")

    # ---- [body]
    b = _table(data, "body")
    if not b:
        raise ValueError("missing required table [body] in body file")
    _check_keys(b, _SCHEMA["body"], "[body] ")  # type: ignore[arg-type]
    w = "[body] "
    mm = 1e-3
    bore = _num(b, "bore_radius_mm", w) * mm
    hub_r = _num(b, "hub_outer_radius_mm", w) * mm
    hub_w = _num(b, "hub_width_mm", w) * mm
    web_t = _num(b, "web_thickness_mm", w) * mm
    web_off = _num(b, "web_offset_mm", w, 0.0) * mm
    incl_deg = _num(b, "web_inclination_deg", w, 0.0)
    rim_i = _num(b, "rim_inner_radius_mm", w) * mm
    rim_o = _num(b, "rim_outer_radius_mm", w) * mm
    rim_w = _num(b, "rim_width_mm", w) * mm
    shaft_r = _num(b, "shaft_outer_radius_mm", w, hub_r / mm) * mm
    for key, v in [
        ("bore_radius_mm", bore),
        ("hub_outer_radius_mm", hub_r),
        ("hub_width_mm", hub_w),
        ("web_thickness_mm", web_t),
        ("rim_inner_radius_mm", rim_i),
        ("rim_outer_radius_mm", rim_o),
        ("rim_width_mm", rim_w),
    ]:
        _positive(f"[body] {key}", v / mm)
    if bore >= hub_r:
        raise ValueError(
            f"[body] bore_radius_mm = {bore / mm:g} must be < hub_outer_radius_mm = {hub_r / mm:g}"
        )
    if hub_r > rim_i:
        raise ValueError(
            f"[body] hub_outer_radius_mm = {hub_r / mm:g} must be <= rim_inner_radius_mm = "
            f"{rim_i / mm:g}"
        )
    if rim_i >= rim_o:
        raise ValueError(
            f"[body] rim_inner_radius_mm = {rim_i / mm:g} must be < rim_outer_radius_mm = "
            f"{rim_o / mm:g}"
        )
    if web_t > rim_w:
        raise ValueError(
            f"[body] web_thickness_mm = {web_t / mm:g} must be <= rim_width_mm = {rim_w / mm:g}"
        )
    if web_t > hub_w:
        raise ValueError(
            f"[body] web_thickness_mm = {web_t / mm:g} must be <= hub_width_mm = {hub_w / mm:g}"
        )
    lim = (rim_w - web_t) / 2
    if abs(web_off) > lim + 1e-12:
        raise ValueError(
            f"[body] web_offset_mm = {web_off / mm:g} puts the web outside the rim; allowed range "
            f"[{-lim / mm:g}, {lim / mm:g}] (|offset| <= (rim_width - web_thickness)/2)"
        )
    if not -60.0 < incl_deg < 60.0:
        raise ValueError(f"[body] web_inclination_deg = {incl_deg:g} must be in (-60, 60)")
    if not bore < shaft_r <= hub_r:
        raise ValueError(
            f"[body] shaft_outer_radius_mm = {shaft_r / mm:g} must be in "
            f"({bore / mm:g}, {hub_r / mm:g}] (bore radius, hub outer radius]"
        )

    h = b.get("holes", {})
    if not isinstance(h, dict):
        raise ValueError(
            "[body] holes must be an inline table {count, center_radius_mm, radius_mm}"
        )
    _check_keys(h, _HOLES_KEYS, "[body] holes.")
    n_holes = _int(h, "count", "[body] holes.", 0)
    if n_holes < 0:
        raise ValueError(f"[body] holes.count = {n_holes} must be >= 0")
    hc = _num(h, "center_radius_mm", "[body] holes.", 0.0) * mm
    hr = _num(h, "radius_mm", "[body] holes.", 0.0) * mm
    if n_holes > 0:
        _positive("[body] holes.radius_mm", hr / mm)
        if hub_r >= rim_i:
            raise ValueError("[body] holes.count > 0 needs a web (hub_outer_radius_mm < rim_inner)")
        lo, hi = hub_r + hr, rim_i - hr
        if not lo < hc < hi:
            raise ValueError(
                f"[body] holes.center_radius_mm = {hc / mm:g} does not fit the holes in the web; "
                f"allowed range ({lo / mm:g}, {hi / mm:g}) (hub_outer + radius, rim_inner - radius)"
            )
        if n_holes > 1:
            rmax = hc * math.sin(math.pi / n_holes)
            if hr >= rmax:
                raise ValueError(
                    f"[body] holes.radius_mm = {hr / mm:g} makes {n_holes} holes overlap; allowed "
                    f"range (0, {rmax / mm:g}) (center_radius * sin(pi / count))"
                )
    geometry = Geometry(
        bore_radius=bore,
        hub_outer_radius=hub_r,
        hub_width=hub_w,
        web_thickness=web_t,
        web_offset=web_off,
        web_inclination=math.radians(incl_deg),
        rim_inner_radius=rim_i,
        rim_outer_radius=rim_o,
        rim_width=rim_w,
        holes=Holes(n_holes, hc if n_holes else 0.0, hr if n_holes else 0.0),
        shaft_outer_radius=shaft_r,
    )

    # ---- [[bearings]]
    bl = data.get("bearings", [])
    if isinstance(bl, dict):
        bl = [bl]
    if not isinstance(bl, list) or not bl:
        raise ValueError(
            "at least one [[bearings]] table is required (axial_position_mm, coupling)"
        )
    bearings = []
    for k, t in enumerate(bl):
        if not isinstance(t, dict):
            raise ValueError("[[bearings]] entries must be tables")
        wb = f"[[bearings]][{k}] "
        _check_keys(t, _SCHEMA["bearings"], wb)  # type: ignore[arg-type]
        pos = _num(t, "axial_position_mm", wb) * mm
        lim = 20 * max(rim_w, hub_w, rim_o)
        if abs(pos) > lim:
            raise ValueError(
                f"{wb}axial_position_mm = {pos / mm:g} outside the allowed range "
                f"[{-lim / mm:g}, {lim / mm:g}]"
            )
        bearings.append(Bearing(pos, _str(t, "coupling", wb, COUPLINGS, "rigid")))
    pos_sorted = sorted(x.axial_position for x in bearings)
    for a, c in zip(pos_sorted, pos_sorted[1:]):
        if c - a < 1e-6:
            raise ValueError(f"two [[bearings]] share axial_position_mm = {a / mm:g}")

    # ---- [material]
    m = _table(data, "material")
    _check_keys(m, _SCHEMA["material"], "[material] ")  # type: ignore[arg-type]
    e = _num(m, "youngs_modulus_GPa", "[material] ", 210.0)
    nu = _num(m, "poisson_ratio", "[material] ", 0.3)
    rho = _num(m, "density_kg_m3", "[material] ", 7800.0)
    _positive("[material] youngs_modulus_GPa", e)
    _positive("[material] density_kg_m3", rho)
    if not -1.0 < nu < 0.5:
        raise ValueError(f"[material] poisson_ratio = {nu:g} must be in (-1, 0.5)")
    material = Material(e * 1e9, nu, rho)

    # ---- [mesh]
    ms = _table(data, "mesh")
    _check_keys(ms, _SCHEMA["mesh"], "[mesh] ")  # type: ignore[arg-type]
    element = _str(ms, "element", "[mesh] ", ELEMENTS, "hex20")
    size = _num(ms, "size_mm", "[mesh] ", 2.0)
    _positive("[mesh] size_mm", size)
    over: dict[str, float | None] = {}
    for key in ("hub_size_mm", "web_size_mm", "rim_size_mm", "circumferential_size_mm"):
        if key in ms:
            v = _num(ms, key, "[mesh] ")
            _positive(f"[mesh] {key}", v)
            over[key[:-3]] = v * mm
        else:
            over[key[:-3]] = None
    smallest = min([size * mm] + [v for v in over.values() if v is not None])
    if smallest < 1e-3 * rim_o:
        raise ValueError(
            f"[mesh] sizes must be >= {1e-3 * rim_o / mm:g} mm (1e-3 x rim outer radius), got "
            f"{smallest / mm:g} mm"
        )
    mesh = MeshSettings(element, size * mm, **over)  # type: ignore[arg-type]

    # ---- [condensation]
    c = _table(data, "condensation")
    _check_keys(c, _SCHEMA["condensation"], "[condensation] ")  # type: ignore[arg-type]
    method = _str(c, "method", "[condensation] ", METHODS, "craig-bampton")
    modes = _int(c, "modes", "[condensation] ", 50)
    if modes < 0:
        raise ValueError(f"[condensation] modes = {modes} must be >= 0")
    teeth = _int(c, "teeth", "[condensation] ")
    if not 3 <= teeth <= 1000:
        raise ValueError(f"[condensation] teeth = {teeth} must be in [3, 1000]")
    nax = _int(c, "axial_master_nodes", "[condensation] ", 5)
    if not 1 <= nax <= 50:
        raise ValueError(f"[condensation] axial_master_nodes = {nax} must be in [1, 50]")
    condensation = Condensation(method, modes, teeth, nax)

    # ---- [centrifugal]
    cf = _table(data, "centrifugal")
    _check_keys(cf, _SCHEMA["centrifugal"], "[centrifugal] ")  # type: ignore[arg-type]
    speed = _num(cf, "speed_rad_s", "[centrifugal] ", 0.0)
    if speed < 0:
        raise ValueError(f"[centrifugal] speed_rad_s = {speed:g} must be >= 0")
    spin = cf.get("spin_softening", False)
    if not isinstance(spin, bool):
        raise ValueError(f"[centrifugal] spin_softening must be true or false, got {spin!r}")

    # ---- [modal] (optional extension)
    md = _table(data, "modal")
    _check_keys(md, _SCHEMA["modal"], "[modal] ")  # type: ignore[arg-type]
    support = _str(md, "support", "[modal] ", SUPPORTS, "bearings")
    nf = _int(md, "n_frequencies", "[modal] ", 20)
    if not 1 <= nf <= 200:
        raise ValueError(f"[modal] n_frequencies = {nf} must be in [1, 200]")
    nv = _int(md, "vtu_modes", "[modal] ", 10)
    if not 0 <= nv <= nf:
        raise ValueError(f"[modal] vtu_modes = {nv} must be in [0, n_frequencies = {nf}]")

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
        source_text=text,
    )


def embedded_bodies() -> list[str]:
    """Names of the body files shipped with fem_prep (``fem_prep/bodies/*.toml``)."""
    root = resources.files("fem_prep") / "bodies"
    return sorted(p.name[:-5] for p in root.iterdir() if p.name.endswith(".toml"))


def load_body(source: str | Path) -> Body:
    """Load a body from a file path or an embedded body name.

    Args:
        source: path to a ``.toml`` body file, or the name of an embedded body
            (see :func:`embedded_bodies`), e.g. ``"accessory-wheel"``.

    Returns:
        The validated :class:`Body`.

    Raises:
        FileNotFoundError: neither a file nor an embedded body of that name exists.
        ValueError: the file is invalid (see :func:`parse_body`).
    """
    path = Path(source)
    if path.is_file():
        text = path.read_text(encoding="utf-8")
        return parse_body(text, default_name=path.stem)
    name = str(source)
    if name in embedded_bodies():
        text = (resources.files("fem_prep") / "bodies" / f"{name}.toml").read_text("utf-8")
        return parse_body(text, default_name=name)
    raise FileNotFoundError(
        f"body file {str(source)!r} not found (and it is not an embedded body; embedded bodies: "
        f"{', '.join(embedded_bodies())})"
    )
