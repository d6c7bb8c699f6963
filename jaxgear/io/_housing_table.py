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
import math
import os
from typing import Any, NamedTuple

import numpy as np

from fem_prep import schema as sc

__all__ = [
    "HousingBody",
    "HousingSpec",
    "build_housing",
    "housing_body",
    "housing_surface",
    "parse_housing",
    "stage_housing",
    "stage_housing_spec",
]

_KEYS = {
    "width_mm",
    "height_mm",
    "wall_thickness_mm",
    "length_mm",
    "bore_diameter_mm",
    "foot_size_mm",
    "mesh_size_mm",
    "layers",
    "mesher",
    "element",
    "youngs_modulus_GPa",
    "poisson_ratio",
    "density_kg_m3",
    "cutoff_Hz",
    "highest_mesh_frequency_Hz",
    "loss_factor",
    "coupling",
    "mesh_file",
    "mesh_unit",
    "offset_mm",
    "seats",
    "feet",
    "points_mm",
}
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
#: the condensed housing's band: orders at frequencies up to cut-off / HOUSING_BAND count
#: (docs/housing.md, "What the condensation keeps": the default cut-off is 1.5 x the highest
#: mesh order's)
HOUSING_BAND = 1.5
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


def _vec(table, key, where, n, default=None):
    if key not in table:
        return default
    v = table[key]
    ok = (
        isinstance(v, list)
        and len(v) == n
        and all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in v)
        and all(math.isfinite(x) for x in v)
    )
    if not ok:
        raise sc.fail(where, key, f"allowed {n} finite numbers", v)
    return tuple(float(x) for x in v)


def parse_housing(table, base_dir: str | None = None, material=None,
                  whine: tuple[float, str] | None = None) -> HousingSpec:
    """Check ``[housing]`` (one-line errors naming the key, its value and the allowed range,
    before anything is built) into a :class:`HousingSpec`; ``material`` the case's (E, ν, ρ),
    the default. ``whine``: the highest frequency (Hz) of the orders the case's ``[whine]``
    computes at its top speed and the words that say which
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
    table = sc.subtable({w: table}, w, "", _KEYS)
    if "cutoff_Hz" in table and "highest_mesh_frequency_Hz" in table:
        raise sc.fail(w, "cutoff_Hz", "give exactly one of cutoff_Hz and highest_mesh_frequency_Hz")
    if "cutoff_Hz" in table:
        cutoff = sc.number(table, "cutoff_Hz", w, allowed="(0, 1e+06]")
        source = "cutoff_Hz"
    elif "highest_mesh_frequency_Hz" in table:
        top = sc.number(table, "highest_mesh_frequency_Hz", w, allowed="(0, 1e+06]")
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
    E = sc.number(table, "youngs_modulus_GPa", w, E0 * 1e-9, allowed="[0.1, 1e+07]") * 1e9
    nu = sc.number(table, "poisson_ratio", w, nu0, allowed="[0, 0.5)")
    rho = sc.number(table, "density_kg_m3", w, rho0, allowed="[1, 1e+05]")
    points = []
    for name in sc.subtable(table, "points_mm", w):
        xyz = sc.number_list(table["points_mm"], name, "housing.points_mm", length=3)
        points.append((str(name), tuple(float(x) * 1e-3 for x in xyz)))
    common = {
        "points": tuple(points),
        "cutoff": cutoff,
        "cutoff_source": source,
        "material": (E, nu, rho),
        "loss_factor": sc.number(table, "loss_factor", w, 0.0, allowed="[0, 1]"),
        "coupling": sc.choice(table, "coupling", w, COUPLINGS, "rigid"),
        "element": sc.choice(table, "element", w, ELEMENTS, "tet10"),
    }
    if "mesh_file" in table:
        for key in _BOX_ONLY:
            if key in table:
                raise sc.fail(w, key, "a box key: not with mesh_file", table[key])
        ref = sc.string(table, "mesh_file", w)
        # the path resolved here, the file read when the housing is built (build_housing)
        path = ref if base_dir is None or os.path.isabs(ref) else os.path.join(base_dir, ref)
        unit = sc.choice(table, "mesh_unit", w, ("mm", "m"), "mm")
        seats = []
        seat_keys = {"centre_mm", "axis", "diameter_mm", "width_mm", "name"}
        for k, s in enumerate(sc.table_array(table, "seats", w, seat_keys)):
            where = f"housing.seats[{k}]"
            c = _vec(s, "centre_mm", where, 3)
            if c is None:
                raise sc.fail(where, "centre_mm", "required")
            axis = _vec(s, "axis", where, 3, (1.0, 0.0, 0.0))
            if not any(axis):
                raise sc.fail(where, "axis", "allowed a non-zero vector", list(axis))
            seats.append(
                (
                    tuple(x * 1e-3 for x in c),
                    axis,
                    sc.number(s, "diameter_mm", where, allowed="(0, 1e+05]") * 1e-3,
                    sc.number(s, "width_mm", where, allowed="(0, 1e+05]") * 1e-3,
                    sc.string(s, "name", where, f"seat{k}"),
                )
            )
        if not seats:
            raise sc.fail(w, "seats", "a mesh file needs [[housing.seats]] (one per bore)")
        feet = []
        for k, f in enumerate(sc.table_array(table, "feet", w, {"x_mm", "y_mm"})):
            where = f"housing.feet[{k}]"
            rx, ry = (_vec(f, key, where, 2) for key in ("x_mm", "y_mm"))
            for key, r in (("x_mm", rx), ("y_mm", ry)):
                if r is None or not r[1] > r[0]:
                    raise sc.fail(where, key, "allowed [min, max], max > min", f.get(key))
            feet.append((tuple(x * 1e-3 for x in rx), tuple(x * 1e-3 for x in ry)))
        offset = _vec(table, "offset_mm", w, 3, (0.0, 0.0, 0.0))
        return HousingSpec(
            **common,
            mesh_file=path,
            mesh_scale=1e-3 if unit == "mm" else 1.0,
            offset=tuple(x * 1e-3 for x in offset),
            seats=tuple(seats),
            feet=tuple(feet),
        )
    for key in _FILE_ONLY:
        if key in table:
            raise sc.fail(w, key, "a mesh file's key: allowed with mesh_file only", table[key])
    mm = lambda key, default=sc.MISSING: sc.number(table, key, w, default, allowed="(0, 1e+05]")
    out = {k: mm(f"{k}_mm") * 1e-3 for k in ("width", "height", "wall_thickness")}
    for k in ("length", "bore_diameter", "foot_size", "mesh_size"):
        v = mm(f"{k}_mm", None)
        out[k] = None if v is None else v * 1e-3
    return HousingSpec(
        **common,
        **out,
        layers=int(sc.number(table, "layers", w, 1, allowed="[1, 8]", integer=True)),
        mesher=sc.choice(table, "mesher", w, MESHERS, "structured"),
    )


def box_bores(spec: HousingSpec, shafts, positions, diameters=None):
    """The box's bores round the housed axes (module docstring): (the box's length (m), the
    scene position of its origin (3,) (m), each axis's bore centre in the end walls' plane
    (A, 2) (m), its bore diameter (A,) (m), the largest diameter that fits there (A,) (m):
    within the walls' inner faces and clear of every other axis's bore at its own diameter).
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
    default = spec.bore_diameter or 1.5 * max(s.diameter for s in shafts)
    given = [None] * len(positions) if diameters is None else list(diameters)
    d = np.array([default if given[k] is None else float(given[k]) for k in keep])
    centres = axes - off[:2]
    u, v = centres[:, 0], centres[:, 1]
    room = 2.0 * np.minimum.reduce([u - t, spec.width - t - u, v - t, spec.height - t - v])
    for i in range(len(keep)):
        for j in range(len(keep)):
            if i != j:
                gap = float(np.linalg.norm(centres[i] - centres[j])) - d[j] / 2
                room[i] = min(room[i], 2.0 * gap)
    return length, off, centres, d, room


def _box(spec: HousingSpec, shafts, positions, diameters=None):
    """The :class:`fem_prep.housing.HousingBox` round the bearings (module docstring) and the
    scene position of its origin (m); ``diameters``: :func:`box_bores`'."""
    from fem_prep.housing import Bore, Foot, HousingBox

    length, off, centres, d, _ = box_bores(spec, shafts, positions, diameters)
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
        mesh = read_housing_mesh(
            spec.mesh_file, seats, feet, scale=spec.mesh_scale, element=element
        )
        offset = np.asarray(spec.offset)
    else:
        box, off = _box(spec, shafts, positions, diameters)
        size = spec.mesh_size or min(box.width, box.height, box.length) / 4
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
    except ValueError as err:  # a bore whose seat ring reaches a foot's held nodes
        if "touches a foot" not in str(err):
            raise
        raise sc.SchemaError(f"[housing]: {err} (allowed a bore clear of the feet: a smaller "
                             "bore diameter, a taller box or smaller feet)") from None
    housing = Housing.of(
        condensed, loss_factor=spec.loss_factor, rotation=np.array(ROTATION), offset=offset
    )
    return HousingBody(mesh, condensed, housing, np.asarray(offset, dtype=float))


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
    from fem_prep.housing import outer_surface

    R = np.asarray(body.housing.rotation)
    local = {name: R.T @ (np.asarray(x) - body.offset) for name, x in spec.points}
    surface = outer_surface(body.mesh, local)
    if spec.points:
        v = body.mesh.mesh.p[:, body.mesh.mesh.facets[:, surface.facets]]  # (3, 3, F)
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
