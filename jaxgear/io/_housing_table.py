"""The ``[housing]`` table of a case (docs/housing.md): a flexible housing the lumped 3D scene's
bearings join the shafts to, condensed by :mod:`fem_prep.housing` (built once, then cached).

.. code-block:: toml

    [housing]
    # a parametric box round the shafts (or mesh_file, below)
    width_mm = 250.0             # across the shafts' plane (scene x)
    height_mm = 160.0            # scene y; the feet on the bottom (y min)
    wall_thickness_mm = 10.0
    length_mm = 110.0            # along the shafts; default: the bearings' span + the wall
    bore_diameter_mm = 50.0      # default: 1.5 x the largest shaft diameter
    foot_size_mm = 30.0          # square feet at the bottom's four corners; default 3 walls
    mesh_size_mm = 40.0          # the mesher's largest cell edge
    mesher = "structured"        # or "gmsh" (pip install 'jaxgear[housing]')
    element = "tet10"            # or "tet4"
    youngs_modulus_GPa = 210.0   # default: the case's [material]
    poisson_ratio = 0.3
    density_kg_m3 = 7800.0
    cutoff_Hz = 3000.0           # the interior modes kept; or highest_mesh_frequency_Hz
                                 # (cut-off 1.5 x it); neither: 1.5 x the highest order's
                                 # frequency of the case's [whine] at its top speed
    loss_factor = 0.02           # modal damping zeta = loss_factor / 2 on the housing's modes
    coupling = "rigid"           # the seats' coupling: "rigid" or "averaging"
    [housing.points_mm]          # accelerometer points (scene frame, mm): each read at the
    top = [100.0, 80.0, 0.0]     # outer skin's node nearest it (jaxgear run, [whine])

The box's frame: its length along the shafts (scene z), its width along scene x, its height
along scene y; centred on the shafts' axes across, its end walls' mid-planes at the outermost
bearings along; a bore round every shaft in both end walls; each bearing on its nearest seat.
``mesh_file`` (any meshio format, in the housing frame: x along the shafts, z up, the feet on
its lowest plane) replaces the box: ``mesh_unit`` ("mm" or "m"), ``offset_mm`` (the scene
position of the mesh's origin), ``[[housing.seats]]`` (``centre_mm``, ``axis``,
``diameter_mm``, ``width_mm``, ``name``) and ``[[housing.feet]]`` (``x_mm``, ``y_mm``:
(min, max)).
"""

from __future__ import annotations

import dataclasses
import os
import re
from typing import Annotated, Any, ClassVar, Literal, NamedTuple

import numpy as np
import pydantic

from fem_prep import schema as sc

from ..scenes import HOUSING_BAND, band_cutoff_hz, band_holds, housing_band_hz
from ._sections import NEEDED, Section, Text, number, number_list

__all__ = [
    "HOUSING_BAND",
    "HousingBody",
    "HousingSection",
    "HousingSize",
    "HousingSpec",
    "build_housing",
    "check_housing_band",
    "housing_body",
    "housing_size",
    "housing_surface",
    "parse_housing",
    "stage_housing",
    "stage_housing_spec",
]


_BOX_ONLY = (
    "width_mm",
    "height_mm",
    "wall_thickness_mm",
    "length_mm",
    "bore_diameter_mm",
    "foot_size_mm",
    "mesh_size_mm",
    "layers",
    "mesher",
)
_FILE_ONLY = ("mesh_unit", "offset_mm", "seats", "feet")
MESHERS = ("structured", "gmsh")
ELEMENTS = ("tet10", "tet4")
COUPLINGS = ("rigid", "averaging")
#: the housing frame -> the scene frame: housing x (length) along the shafts (scene z), housing
#: y (width) along scene x, housing z (height, feet at z = 0) along scene y
ROTATION = ((0.0, 1.0, 0.0), (0.0, 0.0, 1.0), (1.0, 0.0, 0.0))
#: the relative margin of a cut-off derived from ``[whine]`` above 1.5 x its top order
EDGE = 1e-9


@dataclasses.dataclass(frozen=True)
class HousingSpec:
    """A case's ``[housing]`` in SI (m, Pa, kg/m³, Hz); ``None``: the default (module
    docstring). ``seats``: (centre (3,), axis (3,), diameter, width, name) per seat and
    ``feet``: ((x_min, x_max), (y_min, y_max)) per foot, of a mesh file (housing frame, m);
    ``points``: ((name, (x, y, z)), ...) the named points (scene frame, m);
    ``cutoff_source``: where the cut-off came from (the key, or the ``[whine]`` it was derived
    from: :func:`parse_housing`)."""

    cutoff: float
    width: float | None = None
    height: float | None = None
    wall_thickness: float | None = None
    length: float | None = None
    bore_diameter: float | None = None
    foot_size: float | None = None
    mesh_size: float | None = None
    layers: int = 1
    mesher: str = "structured"
    element: str = "tet10"
    material: tuple | None = None
    loss_factor: float = 0.0
    coupling: str = "rigid"
    mesh_file: str | None = None
    mesh_scale: float = 1e-3
    offset: tuple = (0.0, 0.0, 0.0)
    seats: tuple = ()
    feet: tuple = ()
    points: tuple = ()
    cutoff_source: str = "cutoff_Hz"


#: a box's or a seat's size (mm): from 1 µm (a thinner wall or foot is below what the box's
#: metres resolve beside its sides: a foot of 1e-300 mm ends where it starts) to 100 m
_SIZE_MM = "[0.001, 1e+05]"


class SeatEntry(Section):
    """A ``[[housing.seats]]`` entry of a mesh file (housing frame, mm): its bore's centre,
    axis (default x; not zero), diameter and width, and its name (default ``seat<k>``)."""

    WHERE: ClassVar[str] = "housing.seats[]"
    centre_mm: number_list(length=3)
    axis: number_list(length=3) = pydantic.Field(default_factory=lambda: [1.0, 0.0, 0.0])
    diameter_mm: number(_SIZE_MM)
    width_mm: number(_SIZE_MM)
    name: Text | None = None


class FootEntry(Section):
    """A ``[[housing.feet]]`` entry of a mesh file: its (min, max) along x and y (mm, housing
    frame; max > min)."""

    WHERE: ClassVar[str] = "housing.feet[]"
    x_mm: number_list(length=2)
    y_mm: number_list(length=2)


class HousingSection(Section):
    """``[housing]`` (module docstring): a box's keys or a mesh file's (one or the other), the
    housing's material (default the case's), cut-off (``cutoff_Hz`` or
    ``highest_mesh_frequency_Hz``, one of them; neither: derived from ``[whine]``,
    :func:`parse_housing`), damping, coupling, element and named points (scene frame, mm)."""

    WHERE: ClassVar[str] = "housing"
    # a box (its width, height and walls required: _related)
    width_mm: Annotated[number(_SIZE_MM) | None, NEEDED] = None
    height_mm: Annotated[number(_SIZE_MM) | None, NEEDED] = None
    wall_thickness_mm: Annotated[number(_SIZE_MM) | None, NEEDED] = None
    length_mm: number(_SIZE_MM) | None = None
    bore_diameter_mm: number(_SIZE_MM) | None = None
    foot_size_mm: number(_SIZE_MM) | None = None
    mesh_size_mm: number(_SIZE_MM) | None = None
    layers: number("[1, 8]", integer=True) = 1
    mesher: Literal[MESHERS] = "structured"
    # both
    element: Literal[ELEMENTS] = "tet10"
    youngs_modulus_GPa: number("[0.1, 1e+07]") | None = None
    poisson_ratio: number("[0, 0.5)") | None = None
    density_kg_m3: number("[1, 1e+05]") | None = None
    cutoff_Hz: number("(0, 1e+06]") | None = None
    highest_mesh_frequency_Hz: number("(0, 1e+06]") | None = None
    loss_factor: number("[0, 1]") = 0.0
    coupling: Literal[COUPLINGS] = "rigid"
    points_mm: dict[str, number_list(length=3)] = pydantic.Field(default_factory=dict)
    # a mesh file
    mesh_file: Text | None = None
    mesh_unit: Literal["mm", "m"] = "mm"
    offset_mm: number_list(length=3) = pydantic.Field(default_factory=lambda: [0.0, 0.0, 0.0])
    seats: list[SeatEntry] = pydantic.Field(default_factory=list)
    feet: list[FootEntry] = pydantic.Field(default_factory=list)

    @pydantic.model_validator(mode="after")
    def _related(self):
        w = self.WHERE
        if self.cutoff_Hz is not None and self.highest_mesh_frequency_Hz is not None:
            raise sc.fail(w, "cutoff_Hz",
                          "give exactly one of cutoff_Hz and highest_mesh_frequency_Hz")
        if self.mesh_file is not None:
            for key in _BOX_ONLY:
                if key in self.given:
                    raise sc.fail(w, key, "a box key: not with mesh_file", getattr(self, key))
            for k, seat in enumerate(self.seats):
                if not any(seat.axis):
                    raise sc.fail(f"{w}.seats[{k}]", "axis", "allowed a non-zero vector",
                                  list(seat.axis))
            if not self.seats:
                raise sc.fail(w, "seats", "a mesh file needs [[housing.seats]] (one per bore)")
            for k, foot in enumerate(self.feet):
                for key in ("x_mm", "y_mm"):
                    r = getattr(foot, key)
                    if not r[1] > r[0]:
                        raise sc.fail(f"{w}.feet[{k}]", key, "allowed [min, max], max > min", r)
            return self
        for key in _FILE_ONLY:
            if key in self.given:
                raise sc.fail(w, key, "a mesh file's key: allowed with mesh_file only",
                              getattr(self, key))
        for key in ("width_mm", "height_mm", "wall_thickness_mm"):
            if key not in self.given:
                raise sc.fail(w, key, "missing required key")
        return self


def parse_housing(table, base_dir: str | None = None, material=None,
                  whine: tuple[float, str] | None = None) -> HousingSpec:
    """Read ``[housing]`` (:class:`HousingSection`: one-line errors naming the key, its value
    and the allowed range, before anything is built) into a :class:`HousingSpec`; ``material``
    the case's (E, ν, ρ), the default. ``whine``: the highest frequency (Hz) of the orders the
    case's ``[whine]`` computes at its top speed and the words that say which
    (:func:`jaxgear.io._whine_table.highest_order_frequency`), None without ``[whine]``: the
    cut-off when the table gives neither ``cutoff_Hz`` nor ``highest_mesh_frequency_Hz`` is
    :func:`fem_prep.housing.housing_cutoff_hz` of it (1.5 x), recorded in
    :attr:`HousingSpec.cutoff_source`.

    Raises:
        SchemaError: an unknown key, a value out of range, a box key with ``mesh_file`` or a
            file key without it, both of ``cutoff_Hz`` and ``highest_mesh_frequency_Hz``, or
            neither without ``whine`` (a mesh file that does not exist: when the housing is
            built, :func:`build_housing`).
    """
    from fem_prep.housing import housing_cutoff_hz

    w = "housing"
    t = HousingSection.read(table)
    if t.cutoff_Hz is not None:
        cutoff = t.cutoff_Hz
        source = "cutoff_Hz"
    elif t.highest_mesh_frequency_Hz is not None:
        top = t.highest_mesh_frequency_Hz
        cutoff = housing_cutoff_hz(top)
        source = f"1.5 x highest_mesh_frequency_Hz = {top:g} Hz"
    elif whine is not None:
        top, which = whine
        # the top order sits on the band's edge (f_c / 1.5): raised by EDGE, so that round-off
        # in the band's test (the orders' frequencies recomputed) keeps it in
        cutoff = housing_cutoff_hz(top * (1 + EDGE))
        if not cutoff <= 1e6:
            raise sc.fail(w, "cutoff_Hz", f"the cut-off derived from [whine] (1.5 x {which}, "
                          f"{top:.4g} Hz) is out of range, allowed (0, 1e+06]: give cutoff_Hz",
                          cutoff)
        source = f"[whine]: 1.5 x {top:.6g} Hz, {which}"
    else:
        raise sc.fail(w, "cutoff_Hz", "required: give cutoff_Hz, highest_mesh_frequency_Hz (the "
                      "cut-off 1.5 x it) or a [whine] table to derive it from")
    E0, nu0, rho0 = material or (210e9, 0.3, 7800.0)
    E = (E0 * 1e-9 if t.youngs_modulus_GPa is None else t.youngs_modulus_GPa) * 1e9
    nu = nu0 if t.poisson_ratio is None else t.poisson_ratio
    rho = rho0 if t.density_kg_m3 is None else t.density_kg_m3
    points = tuple((str(name), tuple(float(x) * 1e-3 for x in xyz))
                   for name, xyz in t.points_mm.items())
    common = {
        "points": points,
        "cutoff": cutoff,
        "cutoff_source": source,
        "material": (E, nu, rho),
        "loss_factor": t.loss_factor,
        "coupling": t.coupling,
        "element": t.element,
    }
    if t.mesh_file is not None:
        ref = t.mesh_file
        # the path resolved here, the file read when the housing is built (build_housing)
        path = ref if base_dir is None or os.path.isabs(ref) else os.path.join(base_dir, ref)
        seats = tuple((tuple(x * 1e-3 for x in s.centre_mm), tuple(float(x) for x in s.axis),
                       s.diameter_mm * 1e-3, s.width_mm * 1e-3,
                       f"seat{k}" if s.name is None else s.name)
                      for k, s in enumerate(t.seats))
        feet = tuple((tuple(x * 1e-3 for x in f.x_mm), tuple(x * 1e-3 for x in f.y_mm))
                     for f in t.feet)
        return HousingSpec(
            **common,
            mesh_file=path,
            mesh_scale=1e-3 if t.mesh_unit == "mm" else 1.0,
            offset=tuple(float(x) * 1e-3 for x in t.offset_mm),
            seats=seats,
            feet=feet,
        )
    out = {k: getattr(t, f"{k}_mm") * 1e-3 for k in ("width", "height", "wall_thickness")}
    for k in ("length", "bore_diameter", "foot_size", "mesh_size"):
        v = getattr(t, f"{k}_mm")
        out[k] = None if v is None else v * 1e-3
    return HousingSpec(**common, **out, layers=t.layers, mesher=t.mesher)


def box_bores(spec: HousingSpec, shafts, positions, diameters=None):
    """The box's bores round the housed axes (module docstring): (the box's length (m), the
    scene position of its origin (3,) (m), each axis's bore centre in the end walls' plane
    (A, 2) (m), its bore diameter (A,) (m)); whether they fit: :func:`check_box`.
    ``diameters``: one per entry of ``positions`` (None: the default, ``bore_diameter_mm`` or
    1.5 x the largest shaft diameter); an axis is an entry with a position."""
    P = np.array([p for ps in positions for p in ps]).reshape(-1, 3)
    keep = [k for k, ps in enumerate(positions) if ps]
    axes = np.array([positions[k][0][:2] for k in keep])
    t = spec.wall_thickness
    z0, z1 = float(P[:, 2].min()), float(P[:, 2].max())
    length = spec.length if spec.length is not None else (z1 - z0) + t
    mid = 0.5 * (axes.min(axis=0) + axes.max(axis=0))
    off = np.array(
        [mid[0] - spec.width / 2, mid[1] - spec.height / 2, 0.5 * (z0 + z1) - length / 2]
    )
    default = spec.bore_diameter or 1.5 * max((s.diameter for s in shafts), default=0.0)
    given = [None] * len(positions) if diameters is None else list(diameters)
    d = np.array([default if given[k] is None else float(given[k]) for k in keep])
    return length, off, axes - off[:2], d


def _box(spec: HousingSpec, shafts, positions, diameters=None):
    """The :class:`fem_prep.housing.HousingBox` round the bearings (module docstring) and the
    scene position of its origin (m); ``diameters``: :func:`box_bores`'."""
    from fem_prep.housing import Bore, Foot, HousingBox

    length, off, centres, d = box_bores(spec, shafts, positions, diameters)
    t = spec.wall_thickness
    bores = tuple(
        Bore(wall, (c[0], c[1]), dk / 2)
        for wall in ("x-", "x+") for c, dk in zip(centres, d, strict=True)
    )
    f = spec.foot_size or 3 * t
    # each foot's ranges end exactly on the bottom's edges (x + f may round past them)
    feet = tuple(
        Foot(xr, yr)
        for xr in ((0.0, f), (length - f, length))
        for yr in ((0.0, f), (spec.width - f, spec.width))
    )
    try:
        box = HousingBox(length, spec.width, spec.height, t, bores=bores, feet=feet)
    except (ValueError, TypeError) as err:
        raise sc.SchemaError(f"[housing]: the box round the shafts does not fit: {err}") from None
    return box, off


def _mesh_size(spec: HousingSpec, box) -> float:
    """The box's mesh size (m): ``mesh_size_mm``, else a quarter of the smallest side."""
    return spec.mesh_size or min(box.width, box.height, box.length) / 4


def _cutoff_subject(spec: HousingSpec) -> str:
    """The words naming the cut-off's key and value, as the file gave it."""
    src = spec.cutoff_source
    if src == "cutoff_Hz":
        return f"[housing] cutoff_Hz = {spec.cutoff:g}"
    if src.startswith("1.5 x highest_mesh_frequency_Hz"):  # "... = <value> Hz": as given
        given = src.split(" = ")[1].removesuffix(" Hz")
        return f"[housing] highest_mesh_frequency_Hz = {given} (cut-off {spec.cutoff:g} Hz)"
    return f"[housing] cutoff_Hz (not given: {spec.cutoff:.4g} Hz from {src})"


class HousingSize(NamedTuple):
    """A box housing's sizes before it is built (:func:`housing_size`): its tetrahedra and FE
    DOFs (the structured mesher's, exact; gmsh's about them), the interior modes estimated below
    the cut-off (:func:`fem_prep.housing.box_modes_below`), the condensation's peak memory
    (bytes, :func:`fem_prep.housing.condensation_bytes`) and CPU seconds
    (:func:`fem_prep.housing.condensation_seconds`, the benchmark's rates)."""

    cells: int
    dofs: int
    modes: float
    bytes: float
    seconds: float

    def line(self) -> str:
        """One printed line of the estimate."""
        return (f"housing: about {self.cells} cells, {self.dofs} DOFs, {self.modes:.0f} modes "
                f"below the cut-off, {self.bytes / 1e9:.2g} GB and {self.seconds:.2g} CPU s to "
                "condense (estimate; read from fem_prep's cache once built)")


def housing_size(spec: HousingSpec, shafts, positions, diameters=None) -> HousingSize | None:
    """Estimate a box housing before it is meshed and condensed, and refuse in one line what
    this machine cannot hold (:mod:`fem_prep.resources`): a mesh whose structured grid, or
    whose condensation, needs more than half its memory (naming ``mesh_size_mm``), or more
    than :data:`fem_prep.housing.MAX_HOUSING_MODES` interior modes estimated below the cut-off
    (naming the cut-off's key). None for a mesh file (its sizes are known once it is read:
    :func:`fem_prep.housing.prepare_housing` checks them before the assembly). Arguments as
    :func:`housing_body`'s.

    Raises:
        SchemaError: the estimate over a limit; a box that does not fit round the shafts.
    """
    import fem_prep
    from fem_prep.housing import box_modes_below, check_housing_modes, estimate_box
    from fem_prep.resources import check_memory

    if spec.mesh_file is not None:
        return None
    box, _ = _box(spec, shafts, positions, diameters)
    size = _mesh_size(spec, box)
    given = ("mesh_size_mm" if spec.mesh_size else
             "mesh_size_mm (default: a quarter of the box's smallest side)")
    subject = f"[housing] {given} = {size * 1e3:g}"
    quadratic = spec.element == "tet10"
    layers = spec.layers if spec.mesher == "structured" else 1
    try:
        bound = estimate_box(box, size, layers=layers, quadratic=quadratic, bores=False)
        check_memory(subject, bound.mesher_bytes, f"the mesh's {bound.grid_cells:.3g} grid cells",
                     "a larger mesh_size_mm")
        est = estimate_box(box, size, layers=layers, quadratic=quadratic)
        check_memory(subject, fem_prep.housing.condensation_bytes(est.dofs, 0, len(box.bores)),
                     f"about {est.cells:.3g} cells, {est.dofs:.3g} DOFs", "a larger mesh_size_mm")
        modes = min(box_modes_below(box, fem_prep.Material(*spec.material), spec.cutoff),
                    float(est.dofs))
        check_housing_modes(_cutoff_subject(spec), modes, est.dofs, len(box.bores),
                            "estimated from the walls as plates", "a lower cut-off")
    except sc.SchemaError:
        raise
    except ValueError as err:  # the estimate over a limit: the file's words, one line
        raise sc.SchemaError(str(err)) from None
    bytes_ = fem_prep.housing.condensation_bytes(est.dofs, modes, len(box.bores))
    seconds = fem_prep.housing.condensation_seconds(est.dofs, modes)
    return HousingSize(est.cells, est.dofs, modes, bytes_, seconds)


def check_housing_band(spec: HousingSpec, lowest: tuple[float, str],
                       what: str = "every order of [whine]") -> None:
    """Refuse a cut-off whose band (cut-off / 1.5: :func:`jaxgear.scenes.band_holds`,
    docs/housing.md, "What the condensation keeps") lies below the lowest frequency the run asks of the housing's model (``lowest``:
    that frequency (Hz) and the words naming it; by default the lowest order the case's
    ``[whine]`` writes, :func:`~jaxgear.io._whine_table.lowest_order_frequency`; ``what``:
    what it is the lowest of): nothing the run computes would lie in the band. One line naming
    the cut-off's key, the band and that frequency."""
    f, which = lowest
    if not band_holds(spec.cutoff, f):  # the housing's rule (jaxgear.scenes.band_holds)
        band = housing_band_hz(spec.cutoff)
        hmf = spec.cutoff_source.startswith("1.5 x highest_mesh_frequency_Hz")
        allowed = (f"allowed highest_mesh_frequency_Hz >= {f:.4g}" if hmf else
                   f"allowed cutoff_Hz >= {band_cutoff_hz(f):.4g} ({HOUSING_BAND:g} x it)")
        raise sc.SchemaError(
            f"{_cutoff_subject(spec)}: out of range: its band (cut-off / {HOUSING_BAND:g} = "
            f"{band:.4g} Hz) "
            f"lies below {what} ({which}: {f:.4g} Hz), so none of it would be in "
            f"the housing's model: {allowed}"
            + (", or leave it out (1.5 x the highest order)" if "[whine]" in what else "")
        )


class HousingBody(NamedTuple):
    """A case's housing: its ``mesh`` (:class:`fem_prep.housing.HousingMesh`, housing frame),
    its ``condensed`` form (:class:`fem_prep.housing.CondensedHousing`, with the full-field
    recovery), the scene's :class:`jaxgear.scenes.Housing` ``housing`` (placed, damped) and
    the ``offset`` t (3,) (m) of its placement x_scene = R x_housing + t."""

    mesh: Any
    condensed: Any
    housing: Any
    offset: Any


def build_housing(spec: HousingSpec, shafts, positions, *, cache=True, progress=False):
    """The :class:`jaxgear.scenes.Housing` of ``spec`` placed round the scene's bearings:
    meshed, condensed (:func:`fem_prep.housing.condensed_housing`, cached) and damped
    (:func:`housing_body`'s ``housing``)."""
    return housing_body(spec, shafts, positions, cache=cache, progress=progress).housing


def housing_body(spec: HousingSpec, shafts, positions, *, cache=True, progress=False,
                 diameters=None) -> HousingBody:
    """The housing of ``spec`` placed round the scene's bearings: meshed, condensed
    (:func:`fem_prep.housing.condensed_housing`, cached) and damped, as a :class:`HousingBody`.

    Args:
        spec: the case's ``[housing]``. shafts: each shaft's :class:`~jaxgear.scenes.ShaftSpec`.
        positions: each shaft's bearings' scene positions
            (:func:`jaxgear.scenes.bearing_positions`). cache: as ``condensed_housing``'s.
        diameters: a box's bore diameter (m) round each entry of ``positions`` (None, or an
            entry None: ``spec``'s ``bore_diameter``, else 1.5 x the largest shaft diameter;
            a gearbox stage's ``housing_bore_diameter_mm``).

    Raises:
        SchemaError: a box that does not fit round the shafts (a bore through a wall's edge),
            a mesh file that does not exist (before anything is meshed), a bore whose seat
            reaches a foot (when the box is meshed).
    """
    import fem_prep
    from fem_prep.housing import (
        Foot,
        Seat,
        Tet4,
        Tet10,
        condensed_housing,
        mesh_box,
        mesh_box_gmsh,
        read_housing_mesh,
    )

    from ..scenes import Housing

    element = {"tet10": Tet10, "tet4": Tet4}[spec.element]()
    coupling = {"rigid": fem_prep.Rigid, "averaging": fem_prep.Averaging}[spec.coupling]()
    if spec.mesh_file is not None:
        if not os.path.isfile(spec.mesh_file):
            raise sc.fail("housing", "mesh_file", "no such file", spec.mesh_file)
        seats = tuple(Seat(c, a, d / 2, wd, name) for c, a, d, wd, name in spec.seats)
        feet = tuple(Foot(x, y) for x, y in spec.feet)
        try:
            mesh = read_housing_mesh(
                spec.mesh_file, seats, feet, scale=spec.mesh_scale, element=element
            )
        except ValueError as err:  # not a mesh meshio reads, or no tetrahedra in it
            why = re.sub(r"^read_housing_mesh: '.*?' ", "", str(err))
            raise sc.fail("housing", "mesh_file", f"the file {why}: allowed a tetrahedral mesh "
                          "meshio reads (gmsh .msh, .vtu, .inp, ...)", spec.mesh_file) from None
        _check_mesh_file(spec, mesh)
        offset = np.asarray(spec.offset)
        _skin(spec, mesh, offset)  # its named points, before it is condensed
    else:
        housing_size(spec, shafts, positions, diameters)  # refused here if too large
        box, off = _box(spec, shafts, positions, diameters)
        size = _mesh_size(spec, box)
        if spec.mesher == "gmsh":
            mesh = mesh_box_gmsh(box, size, element=element)
        else:
            mesh = mesh_box(box, size, layers=spec.layers, element=element)
        offset = off  # the scene position of the housing's origin
    try:
        condensed = condensed_housing(
            mesh,
            fem_prep.Material(*spec.material),
            spec.cutoff,
            coupling=coupling,
            cache=cache,
            progress=progress,
        )
    except ValueError as err:  # a bore whose seat ring reaches a foot's or another seat's
        if "touches a foot" in str(err):
            raise sc.SchemaError(f"[housing]: {err} (allowed a bore clear of the feet: a "
                                 "smaller bore diameter, a taller box or smaller feet)") from None
        if "share bore nodes" in str(err):
            raise sc.SchemaError("[housing]: two seats' bores share nodes of the mesh (their "
                                 "bores less than about a cell apart): allowed bores farther "
                                 "apart, a smaller bore diameter or a finer mesh_size_mm"
                                 ) from None
        raise
    housing = Housing.of(
        condensed, loss_factor=spec.loss_factor, rotation=np.array(ROTATION), offset=offset
    )
    return HousingBody(mesh, condensed, housing, np.asarray(offset, dtype=float))


def _check_mesh_file(spec: HousingSpec, mesh) -> None:
    """A mesh file's seats and feet found on its mesh before it is condensed (the facets
    :meth:`fem_prep.housing.HousingMesh.seat_nodes` and ``foot_nodes`` take), one line naming
    the seat's or foot's key, the mesh's extent as read with ``mesh_unit`` and, where the
    other unit would put the seats within it, that unit."""
    p = mesh.mesh.p  # (3, n) m, the housing frame
    lo, hi = p.min(axis=1), p.max(axis=1)
    unit = "mm" if spec.mesh_scale == 1e-3 else "m"
    other, ratio = ("m", 1e3) if unit == "mm" else ("mm", 1e-3)
    extent = (f"the mesh, read with mesh_unit = {unit!r}, spans " + ", ".join(
        f"{a} [{_mm(lo[k])}, {_mm(hi[k])}]" for k, a in enumerate("xyz")) + " mm")

    def found(m, seat) -> bool:
        try:
            m.seat_nodes(seat)
        except ValueError:
            return False
        return True

    for k, seat in enumerate(mesh.seats):
        if not found(mesh, seat):
            rescaled = dataclasses.replace(mesh, mesh=type(mesh.mesh)(p * ratio, mesh.mesh.t))
            hint = (f"; read with mesh_unit = {other!r} it would hold the seat"
                    if found(rescaled, seat) else "")
            raise sc.fail(f"housing.seats[{k}]", "centre_mm", f"no bore facet of the mesh "
                          f"within diameter_mm / 2 = {_mm(seat.radius)} mm of this seat's axis "
                          f"({extent}{hint}): allowed a seat on a bore of the mesh (check "
                          "mesh_unit, the file's length unit)", [float(f"{x * 1e3:.6g}")
                                                                 for x in seat.centre]) from None
    for k, foot in enumerate(mesh.feet):
        try:
            mesh.foot_nodes(foot)
        except ValueError:
            raise sc.fail(f"housing.feet[{k}]", "x_mm", f"no facet of the mesh's lowest plane "
                          f"in this foot's rectangle ({extent}): allowed a foot on it (check "
                          "mesh_unit, the file's length unit)",
                          [float(f"{x * 1e3:.6g}") for x in foot.x_range]) from None


def stage_housing_spec(data: dict, base_dir, material, whine=None) -> HousingSpec:
    """``[housing]`` of a planetary stage's case (:func:`parse_housing`, ``whine`` its): the
    box round the stage axis has no shafts to size it from, so it needs ``length_mm`` and
    ``bore_diameter_mm`` (a mesh file its seats, as elsewhere)."""
    spec = parse_housing(sc.subtable(data, "housing", ""), base_dir, material, whine)
    if spec.mesh_file is None:
        for key, value in (("length_mm", spec.length), ("bore_diameter_mm", spec.bore_diameter)):
            if value is None:
                raise sc.fail("housing", key, "required round a planetary stage (its box has no "
                              "shafts to size it from)")
    return spec


def stage_housing(spec: HousingSpec, *, cache=True, progress=False) -> HousingBody:
    """The housing of a planetary stage's case round the stage axis (scene z through the
    origin, the stage's mid-plane z = 0): a box's end walls at z = ±length/2 with a bore round
    the axis in each (seat 0 the x- wall's, at −z; seat 1 the x+ wall's), or a mesh file placed
    by its ``offset_mm``; meshed, condensed (cached) and damped as :func:`housing_body`."""
    return housing_body(spec, (), [[np.zeros(3)]], cache=cache, progress=progress)


def housing_surface(spec: HousingSpec, body: HousingBody):
    """The outer skin of a case's housing (:func:`fem_prep.housing.outer_surface`) with the
    named points of ``[housing.points_mm]`` (scene frame, moved into the housing's frame by
    the placement x_h = Rᵀ (x − t)), each read at the skin node nearest it.

    Raises:
        SchemaError: a point farther from the nearest skin node than 0.6 of the skin's longest
            facet edge (outside the housing, or inside its cavity), naming the point's key.
    """
    return _skin(spec, body.mesh, body.offset)


def _skin(spec: HousingSpec, mesh, offset):
    """:func:`housing_surface` of the housing ``mesh`` (housing frame) placed at ``offset``
    (m): a mesh file's points are checked by it as soon as the file is read."""
    from fem_prep.housing import outer_surface

    R = np.asarray(ROTATION)
    local = {name: R.T @ (np.asarray(x) - offset) for name, x in spec.points}
    surface = outer_surface(mesh, local)
    if spec.points:
        v = mesh.mesh.p[:, mesh.mesh.facets[:, surface.facets]]  # (3, 3, F)
        # a point on a facet lies within 0.58 of its longest edge of one of its vertices
        tol = 0.6 * float(np.linalg.norm(v - np.roll(v, 1, axis=1), axis=0).max())
        for k, (name, x) in enumerate(spec.points):
            d = float(np.linalg.norm(surface.point_positions[k] - local[name]))
            if d > tol:
                raise sc.fail(
                    "housing.points_mm", name,
                    f"{d * 1e3:.4g} mm from the housing's outer surface (outside the housing "
                    f"or in its cavity): allowed within {tol * 1e3:.4g} mm (0.6 of its "
                    "longest skin cell edge)", [x_ * 1e3 for x_ in x],
                )
    return surface


# -- the box's geometry checked at load, in the case file's words ------------------------------


class HousedAxis(NamedTuple):
    """One axis a box's end walls have a bore round, as :func:`check_box` names it: its
    ``label`` ("the pinion shaft's axis", "stage 2's axis"), the ``shaft`` diameter through
    its bore (m; 0: none, a planetary stage's ring seat), the ``bore`` key that sizes it
    ((table, key) of the case file) and the ``place`` key that puts it there ((table, key,
    value in mm) or None: the case's own layout)."""

    label: str
    shaft: float
    bore: tuple[str, str] = ("housing", "bore_diameter_mm")
    place: tuple | None = None


def _mm(x: float) -> str:
    return f"{x * 1e3:.4g}"


def _fail_wall(spec: HousingSpec, limit: float, why: str):
    return sc.fail("housing", "wall_thickness_mm", f"allowed < {_mm(limit)} mm ({why})",
                   float(f"{spec.wall_thickness * 1e3:.6g}"))


def _check_box_size(spec: HousingSpec, span: float) -> float:
    """The box's own sizes: its length (``length_mm``, else the bearings' ``span`` + a wall)
    holds its two end walls, its width and height two walls each, its feet (``foot_size_mm``,
    else 3 walls) fit its bottom. Returns the length (m)."""
    t = spec.wall_thickness
    if spec.length is not None and not spec.length > 2 * t:
        raise sc.fail("housing", "length_mm", f"allowed > {_mm(2 * t)} mm (the two end walls "
                      f"of wall_thickness_mm = {_mm(t)})", float(f"{spec.length * 1e3:.6g}"))
    if spec.length is None and not span > t:
        raise _fail_wall(spec, span, f"the box's default length, the bearings' span "
                         f"{_mm(span)} mm + a wall, holds its two end walls; or give length_mm")
    length = spec.length if spec.length is not None else span + t
    for key, size in (("width_mm", spec.width), ("height_mm", spec.height)):
        if not size > 2 * t:
            raise _fail_wall(spec, size / 2, f"half of {key} = {_mm(size)}: its two walls; or "
                             f"a larger {key}")
    foot = spec.foot_size or 3 * t
    room = min(length, spec.width)
    if foot > room:
        where = "length" if length <= spec.width else "width_mm"
        if spec.foot_size is not None:
            raise sc.fail("housing", "foot_size_mm", f"allowed (0, {_mm(room)}] mm (the box's "
                          f"{where}, {_mm(room)} mm: the feet stand on its bottom's corners)",
                          float(f"{spec.foot_size * 1e3:.6g}"))
        raise _fail_wall(spec, room / 3, f"the default feet, 3 walls square, exceed the box's "
                         f"{where}, {_mm(room)} mm; or give foot_size_mm")
    return length


def _fit_problem(axes, at, d, limit, groups, keys) -> str:
    """The words of what limits a group of bores (:func:`check_box`)."""
    kind, i = limit.by[:2]
    if kind == "wall":
        return "within the box's end walls' inner faces"
    j = limit.by[2]
    s = float(np.linalg.norm(at[i] - at[j]))
    if kind == "axes":
        return (f"two bores of one diameter round {axes[i].label} and {axes[j].label}, "
                f"{_mm(s)} mm apart")
    table, key = keys[next(g for g, members in enumerate(groups) if j in members)]
    return (f"clear of the {_mm(d[j])} mm bore round {axes[j].label} at ({_mm(at[j][0])}, "
            f"{_mm(at[j][1])}) mm, {_mm(s)} mm away ([{table}] {key})")


def check_box(spec: HousingSpec, shafts, positions, axes, diameters=None) -> None:
    """A box ``[housing]`` checked round its axes before anything is meshed, one line naming
    the case file's key, its value and the allowed range: the box's sizes (``length_mm``,
    ``wall_thickness_mm``, ``foot_size_mm``), every axis within its cavity (``width_mm``,
    ``height_mm``), no two axes at one place (the ``place`` key), each bore clear of its shaft,
    within the walls and clear of the other bores (:func:`fem_prep.housing.bore_limits`; the
    key that sizes it, with the range the others leave it, or, where none is left, what
    conflicts). ``shafts``, ``positions``, ``diameters``: :func:`box_bores`'; ``axes``: one
    :class:`HousedAxis` per entry of ``positions`` with a position. A mesh file's housing is
    not checked here."""
    from fem_prep.housing import bore_limits

    if spec.mesh_file is not None:
        return
    P = np.array([p for ps in positions for p in ps]).reshape(-1, 3)
    _check_box_size(spec, float(np.ptp(P[:, 2])))
    _, _, centres, d = box_bores(spec, shafts, positions, diameters)
    at = np.array([ps[0][:2] for ps in positions if ps])  # the axes in the scene (x, y)
    t = spec.wall_thickness
    # every axis within the cavity: the box is centred on them across
    for n, (key, size) in enumerate((("width_mm", spec.width), ("height_mm", spec.height))):
        lo_k, hi_k = int(np.argmin(at[:, n])), int(np.argmax(at[:, n]))
        span = float(at[hi_k, n] - at[lo_k, n])
        if not span + 2 * t < size:
            need = span + 2 * t + max(d[lo_k], d[hi_k])
            moved = [a.place for a in (axes[lo_k], axes[hi_k]) if a.place is not None]
            hint = f"; or move [{moved[-1][0]}] {moved[-1][1]}" if moved else ""
            raise sc.fail("housing", key, f"the housed axes span {_mm(span)} mm along scene "
                          f"{'xy'[n]} ({axes[lo_k].label} at {_mm(at[lo_k, n])} mm to "
                          f"{axes[hi_k].label} at {_mm(at[hi_k, n])} mm): allowed >= "
                          f"{_mm(need)} mm (the span, two walls of {_mm(t)} mm and the bores "
                          f"round the outermost axes){hint}", float(f"{size * 1e3:.6g}"))
    for i in range(len(at)):
        for j in range(i):
            if np.linalg.norm(at[i] - at[j]) <= 1e-9:
                where = (f"{axes[i].label} at ({_mm(at[i][0])}, {_mm(at[i][1])}) mm, on "
                         f"{axes[j].label}: allowed a place where each housed axis has a bore "
                         "of its own")
                if axes[i].place is not None:
                    table, key, value = axes[i].place
                    raise sc.fail(table, key, f"puts {where}", value)
                raise sc.fail("housing", None, f"the box has {where}")
    keys = list(dict.fromkeys(a.bore for a in axes))
    groups = [[i for i, a in enumerate(axes) if a.bore == k] for k in keys]
    limits = bore_limits(spec.width, spec.height, t, centres, d, groups)
    bad = []
    for g, (members, limit) in enumerate(zip(groups, limits, strict=True)):
        lo = max(axes[i].shaft for i in members)
        dg = float(d[members[0]])
        if lo < dg <= limit.diameter * (1.0 + 1e-12):
            continue
        bad.append((limit.diameter <= lo, g, lo, dg, limit))
    if not bad:
        return
    empty, g, lo, dg, limit = min(bad, key=lambda b: b[:2])  # a range left first
    table, key = keys[g]
    i = limit.by[1]
    default = (" (its default: 1.5 x the largest shaft diameter)"
               if table == "housing" and spec.bore_diameter is None else "")
    value = float(f"{dg * 1e3:.6g}")
    where = _fit_problem(axes, at, d, limit, groups, keys)
    if not empty and dg <= lo:
        k = max(groups[g], key=lambda m: axes[m].shaft)
        raise sc.fail(table, key, f"the bore round {axes[k].label} does not clear its "
                      f"{_mm(lo)} mm shaft: allowed ({_mm(lo)}, {_mm(limit.diameter)}] mm"
                      f"{default}", value)
    if not empty:
        raise sc.fail(table, key, f"the bore round {axes[i].label} at ({_mm(at[i][0])}, "
                      f"{_mm(at[i][1])}) mm does not fit: allowed ({_mm(lo)}, "
                      f"{_mm(limit.diameter)}] mm there ({where}){default}", value)
    k = max(groups[g], key=lambda m: axes[m].shaft)
    need = f"it must exceed the {_mm(lo)} mm shaft on {axes[k].label}, and " if lo > 0 else ""
    raise sc.fail(table, key, f"no diameter fits: {need}the room {where} is "
                  f"{_mm(max(limit.diameter, 0.0))} mm (round {axes[i].label} at "
                  f"({_mm(at[i][0])}, {_mm(at[i][1])}) mm){default}", value)


def check_housing_points(spec: HousingSpec, shafts, positions, diameters=None,
                         microphones=()) -> None:
    """A box ``[housing]``'s named points on its outer skin and ``[acoustics]``'s
    ``microphones`` ((name, (x, y, z) m), scene frame) outside it, before anything is meshed
    (the box placed as :func:`housing_body` places it; after :func:`check_box`): a point
    within 0.6 of the skin's longest cell edge (:func:`fem_prep.housing.box_skin_edge`) of the
    box's outer faces and not in its cavity (:meth:`fem_prep.housing.HousingBox.outer_distance`,
    ``in_cavity``), a microphone farther than that outside them; one line naming the key.
    A mesh file's points are checked when its housing is built (:func:`housing_surface`)."""
    from fem_prep.housing import box_skin_edge

    if spec.mesh_file is not None or not (spec.points or microphones):
        return
    box, off = _box(spec, shafts, positions, diameters)
    size = spec.mesh_size or min(box.width, box.height, box.length) / 4
    edge = (box_skin_edge(box, size, layers=spec.layers) if spec.mesher == "structured"
            else 2.0 * size)  # gmsh's cells: about size, a margin of 2
    tol = 0.6 * edge
    R = np.asarray(ROTATION)
    corners = off[:, None] + R @ np.array([[0.0, box.length], [0.0, box.width],
                                           [0.0, box.height]])
    lo, hi = corners.min(axis=1), corners.max(axis=1)
    extent = ("the box spans " + ", ".join(f"{a} [{_mm(lo[k])}, {_mm(hi[k])}]"
                                           for k, a in enumerate("xyz")) + " mm")
    for kind, named in (("points", spec.points), ("microphones", microphones)):
        for k, (name, x) in enumerate(named):
            local = R.T @ (np.asarray(x) - off)
            dist = float(box.outer_distance(local)[0])
            cavity = bool(box.in_cavity(local)[0])
            mm = [float(f"{v * 1e3:.6g}") for v in x]
            if kind == "points":
                if cavity or abs(dist) > tol:
                    side = ("in the housing's cavity" if cavity else
                            f"outside the housing, {_mm(dist)} mm from its outer faces"
                            if dist > 0 else f"in the housing's wall, {_mm(-dist)} mm under "
                            "its outer faces")
                    raise sc.fail("housing.points_mm", name, f"{side}: allowed on its outer "
                                  f"skin, within {_mm(tol)} mm of its outer faces (0.6 of its "
                                  f"longest skin cell edge; {extent}, scene frame)", mm)
            elif not dist > tol:
                side = ("inside the housing" if dist < 0 else
                        f"on the housing's skin, {_mm(dist)} mm from its outer faces")
                raise sc.fail(f"acoustics.microphones[{k}]", "position_mm", f"{side} "
                              f"(microphone {name!r}): allowed outside it, more than "
                              f"{_mm(tol)} mm from its outer faces (0.6 of its longest skin "
                              f"cell edge; {extent}, scene frame)", mm)


def check_case_housing(case) -> None:
    """A pair's, a train's or a planetary stage's box ``[housing]`` checked at load, before
    anything is meshed (:func:`check_box`, :func:`check_housing_points` with its
    ``[acoustics]`` microphones): round its scene's shafts (a pair's pinion and gear shafts, a
    train's ``[[scene.shafts]]``), or a planetary stage's axis (no shaft; its bore
    ``bore_diameter_mm``). Nothing without a box ``[housing]``."""
    from ._acoustics_table import acoustics_of

    spec = case.housing
    if spec is None or spec.mesh_file is not None:
        return
    if case.scene is None:  # a planetary stage's box round its axis (stage_housing)
        shafts, positions = (), [[np.zeros(3)]]
        axes = [HousedAxis("the stage's axis", 0.0)]
    else:
        shafts, positions = case._bearing_layout(case.scene)
        names = case.shaft_names or ("pinion", "gear")  # a train's, else a pair's two
        axes = [HousedAxis(f"the {name} shaft's axis", float(s.diameter))
                for name, s, ps in zip(names, shafts, positions, strict=True) if ps]
    check_box(spec, shafts, positions, axes)
    acoustics = acoustics_of(case)
    check_housing_points(spec, shafts, positions,
                         microphones=() if acoustics is None else acoustics.microphones)
