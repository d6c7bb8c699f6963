"""Body-file schema: parsing and validation of the ``body.toml`` that describes a gear body.

The schema is documented in ``docs/fem_prep.md``.  All lengths in the file are in mm, the
modulus in GPa; :class:`Body` stores SI values (m, Pa, kg/m^3) next to the raw text.

The kinds a body file names (element, bearing and rim couplings, condensation method, support)
are objects here (:mod:`fem_prep._kinds`); the body-file reader :mod:`fem_prep.schema` maps the
names to them and checks the file.
"""

from __future__ import annotations

import hashlib
import json
import math
from dataclasses import asdict, dataclass, field
from typing import Any

from ._kinds import BearingCoupling, CondensationMethod, Element, RimCoupling, Support

__all__ = [
    "BearingSeat",
    "Body",
    "Condensation",
    "Geometry",
    "Holes",
    "Material",
    "MeshSettings",
    "PinionRim",
]


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
class PinionRim:
    """A second rim on the body: a pinion cut on the shaft beside the wheel's hub (the seed's
    intermediate shaft, III-3, carries the high-speed wheel and the low-speed pinion, condensed
    together). The pinion is the solid ring from the bore to its root circle over its face
    width, joined to the hub through the shaft stubs; its teeth load its outer face through
    their own rim masters, as the wheel's do (``_rim``). All lengths in m.

    Attributes:
        axial_position: z of the middle of its face (body frame: z = 0 at the wheel's mid-rim).
        outer_radius: its root circle (the outer face of the ring).
        width: its face width.
        teeth: one rim master station per tooth (tooth k at 2 pi k / teeth from +x).
        axial_master_nodes: master planes across its face (linspace over the face width).
    """

    axial_position: float
    outer_radius: float
    width: float
    teeth: int
    axial_master_nodes: int

    @property
    def band(self) -> tuple[float, float]:
        """The face's axial extent (m)."""
        return (self.axial_position - self.width / 2, self.axial_position + self.width / 2)


@dataclass(frozen=True)
class BearingSeat:
    """Where a bearing holds the body: a 6-DOF bearing node on the axis at ``axial_position``
    (m), coupled to the bore surface. The bearing's stiffness and damping are not part of the
    body: the scene gives them (:class:`jaxgear.scenes.Bearing`, the case's ``[scene]``).

    Every bore node whose axial position lies in ``band`` (m, ``(z_min, z_max)``) is coupled to
    the bearing node (``coupling``: :class:`~fem_prep.Rigid` or :class:`~fem_prep.Averaging`, see
    ``_couplings``).  The band
    is ``axial_position -/+ width / 2`` clipped to the bore (hub and shaft stubs); ``parse_body``
    resolves it.  ``band = None`` (a bearing built by hand) means ``axial_position -/+ width / 2``;
    ``width = 0`` couples the single bore-node ring nearest the bearing plane (a line support
    that does not converge under mesh refinement; kept for comparison only).
    """

    axial_position: float
    coupling: BearingCoupling
    width: float = 0.0
    band: tuple[float, float] | None = None

    @property
    def z_band(self) -> tuple[float, float]:
        """The coupled axial band (m)."""
        if self.band is not None:
            return self.band
        return (self.axial_position - self.width / 2, self.axial_position + self.width / 2)


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
    """The element (:class:`~fem_prep.Hex20` or :class:`~fem_prep.Hex27`) and the target element
    edge lengths (m) per region; ``None`` = use ``size``."""

    element: Element
    size: float = 2e-3
    hub_size: float | None = None
    web_size: float | None = None
    rim_size: float | None = None
    circumferential_size: float | None = None


@dataclass(frozen=True)
class Condensation:
    """Condensation settings (seed (2.3)-(2.5)): the ``method`` (:class:`~fem_prep.Guyan`,
    :class:`~fem_prep.CraigBampton`, :class:`~fem_prep.Herting`) and ``rim_coupling``, how the
    rim masters hold the outer rim face: :class:`~fem_prep.Distributing` (a least-squares fit of
    the whole face, the tooth loads spread as a traction) or :class:`~fem_prep.Nodal` (the FE
    nodes at the stations), see ``_rim``."""

    method: CondensationMethod
    rim_coupling: RimCoupling
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
        spin_softening: the former switch of the spin-softening matrix, still accepted so
            that older body files parse; the matrix is now always assembled and condensed.
        support: :class:`~fem_prep.Bearings` (bearing nodes held) or :class:`~fem_prep.Free`
            for the reported frequencies.
        n_frequencies: number of frequencies reported in ``summary.json``.
        vtu_modes: number of mode shapes written to the VTU file.
        pinion_rim: a second rim (:class:`PinionRim`, ``[pinion_rim]``) or ``None``: the
            body then carries two gears, the wheel on the webbed rim (rim 0) and the pinion
            (rim 1).
        source_text: the TOML text the body was parsed from.
    """

    name: str
    geometry: Geometry
    bearings: tuple[BearingSeat, ...]
    material: Material
    mesh: MeshSettings
    condensation: Condensation
    support: Support
    speed: float = 0.0
    spin_softening: bool = False
    n_frequencies: int = 20
    vtu_modes: int = 10
    pinion_rim: PinionRim | None = None
    source_text: str = field(default="", compare=False, repr=False)

    def canonical(self) -> dict[str, Any]:
        """Plain-dict form of the parsed body (without the source text; without
        ``pinion_rim`` when there is none, so that a one-rim body keeps its cache key); the kinds
        as their body-file names (the cache key is that of the body file's text)."""
        d = json.loads(json.dumps(asdict(self), default=str))
        d.pop("source_text")
        if d["pinion_rim"] is None:
            d.pop("pinion_rim")
        return d

    @property
    def rim_teeth(self) -> tuple[int, ...]:
        """The stations of each rim: the wheel's, then the pinion's if there is one."""
        t = (self.condensation.teeth,)
        return t if self.pinion_rim is None else (*t, self.pinion_rim.teeth)

    @property
    def sha256(self) -> str:
        """Hash of the canonical parsed body: the cache key (comments/format do not matter)."""
        blob = json.dumps(self.canonical(), sort_keys=True).encode()
        return hashlib.sha256(blob).hexdigest()

    @property
    def text_sha256(self) -> str:
        """sha256 of the TOML text the body came from."""
        return hashlib.sha256(self.source_text.encode()).hexdigest()
