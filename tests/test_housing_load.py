"""A box ``[housing]`` checked at load, in the case file's words (docs/housing.md, "Checked at
load"): the box's sizes, its axes within it, each bore clear of its shaft, within the walls and
clear of the other bores, the named points on its skin and the microphones outside it, all
refused in one line by ``jaxgear.io.load_case`` before anything is meshed; a mesh file that is
not a mesh, or whose seats miss its bores (a file in mm read as metres), refused in one line
before it is condensed.

References, apart from the code under test: the accessory-spur pair's numbers from its TOML
(shafts 30 and 35 mm, bearings ±50 mm of the gears) and its centre distance; the box's rules
(docs/housing.md: centred on the axes across, its length the bearings' span plus a wall, feet
3 walls square) worked out by hand here; the signed distance to a box and the bores' room by
hand for chosen points; the skin's longest cell edge measured on the meshed box's outer skin.
"""

import math
import pathlib

import numpy as np
import pytest
from _housing import HOUSING_BOX, HOUSING_TABLE, PLANETARY_BOX, WHINE_TABLE
from _toml import assert_one_line_errors

import jaxgear.io as jio
from fem_prep.housing import (
    Bore,
    Foot,
    HousingBox,
    Tet4,
    bore_limits,
    box_skin_edge,
    mesh_box,
    outer_surface,
)
from fem_prep.schema import SchemaError

ACCESSORY = jio.embedded_case_text("accessory-spur").replace("slices = 40", "slices = 4")
MIC = '\n[acoustics]\n[[acoustics.microphones]]\nname = "m"\nposition_mm = {}\n'


def _centre_distance_mm() -> str:
    return f"{jio.load_case('accessory-spur').pair.center_distance * 1e3:.4g}"


def test_the_box_refused_at_load_in_the_files_words(tmp_path):
    """The accessory-spur pair (30/35 mm shafts a = 99.45 mm apart, bearings ±50 mm) in
    tests/_housing.py's 250 x 160 mm box of 10 mm walls and 50 mm bores: a bore below its
    shaft, two bores wider than the axes' distance, a box too narrow or too low for the axes
    and their bores (the span, two walls, a bore: 99.45 + 20 + 50 mm across), a box lower
    than its two walls, a bore wider than the room a 60 mm high box leaves (60 - 2 x 10 mm), a 50 mm high
    box whose 30 mm of room is below the 35 mm shaft (no diameter fits: the conflict named),
    walls too thick for the height (< 80 mm) or for the default length (the span 100 mm
    + a wall: t < 100 mm), a length without room for two walls, feet wider than the length
    (110 mm), a wall or a foot below 1 µm: one line each naming the key, its value and the
    range."""
    a = _centre_distance_mm()
    assert a == "99.45"
    case = ACCESSORY + HOUSING_TABLE

    def swap(old, new):
        assert old in case
        return case.replace(old, new)

    bad = {
        swap("bore_diameter_mm = 50.0", "bore_diameter_mm = 20.0"): (
            r"^\[housing\] bore_diameter_mm = 20: the bore round the gear shaft's axis does not "
            rf"clear its 35 mm shaft: allowed \(35, {a}\] mm$"),
        swap("bore_diameter_mm = 50.0", "bore_diameter_mm = 200.0"): (
            r"^\[housing\] bore_diameter_mm = 200: the bore round the pinion shaft's axis at "
            rf"\(0, 0\) mm does not fit: allowed \(35, {a}\] mm there \(two bores of one "
            rf"diameter round the pinion shaft's axis and the gear shaft's axis, {a} mm apart\)$"),
        swap("width_mm = 250.0", "width_mm = 100.0"): (
            rf"^\[housing\] width_mm = 100: the housed axes span {a} mm along scene x .*: "
            r"allowed >= 169\.5 mm"),
        swap("height_mm = 160.0", "height_mm = 18.0"): (
            r"^\[housing\] wall_thickness_mm = 10: allowed < 9 mm \(half of height_mm = 18: "
            r"its two walls; or a larger height_mm\)$"),
        swap("height_mm = 160.0", "height_mm = 60.0"): (
            r"^\[housing\] bore_diameter_mm = 50: the bore round the pinion shaft's axis at "
            r"\(0, 0\) mm does not fit: allowed \(35, 40\] mm there \(within the box's end "
            r"walls' inner faces\)$"),
        swap("height_mm = 160.0", "height_mm = 50.0"): (
            r"^\[housing\] bore_diameter_mm = 50: no diameter fits: it must exceed the 35 mm "
            r"shaft on the gear shaft's axis, and the room within the box's end walls' inner "
            r"faces is 30 mm \(round the pinion shaft's axis at \(0, 0\) mm\)$"),
        swap("wall_thickness_mm = 10.0", "wall_thickness_mm = 90.0"): (
            r"^\[housing\] wall_thickness_mm = 90: allowed < 80 mm \(half of height_mm = 160: "
            r"its two walls; or a larger height_mm\)$"),
        swap("wall_thickness_mm = 10.0", "wall_thickness_mm = 130.0"): (
            r"^\[housing\] wall_thickness_mm = 130: allowed < 100 mm \(the box's default "
            r"length, the bearings' span 100 mm \+ a wall"),
        swap("wall_thickness_mm = 10.0", "wall_thickness_mm = 10.0\nlength_mm = 10.0"): (
            r"^\[housing\] length_mm = 10: allowed > 20 mm \(the two end walls of "
            r"wall_thickness_mm = 10\)$"),
        swap("wall_thickness_mm = 10.0", "wall_thickness_mm = 10.0\nfoot_size_mm = 500.0"): (
            r"^\[housing\] foot_size_mm = 500: allowed \(0, 110\] mm"),
        # a wall far below what the box's sides resolve (the fuzz tests' find: 1e-300 of
        # 10 mm made feet that end where they start, a ValueError of the mesher's box)
        swap("wall_thickness_mm = 10.0", "wall_thickness_mm = 1e-299"): (
            r"^\[housing\] wall_thickness_mm = 1e-299: out of range, allowed \[0\.001, "
            r"100000\]"),
        swap("wall_thickness_mm = 10.0", "wall_thickness_mm = 10.0\nfoot_size_mm = 1e-9"): (
            r"^\[housing\] foot_size_mm = 1e-09: out of range, allowed \[0\.001, 100000\]"),
    }
    assert_one_line_errors(bad, tmp_path)
    # the edges of the ranges: the shaft's diameter refused, just above it and the axes'
    # distance itself taken
    for d, ok in (("35.0", False), ("35.01", True), ("99.45", True), ("99.46", False)):
        path = tmp_path / "edge.toml"
        path.write_text(swap("bore_diameter_mm = 50.0", f"bore_diameter_mm = {d}"))
        if ok:
            assert jio.load_case(str(path)).housing.bore_diameter == pytest.approx(float(d) / 1e3)
        else:
            with pytest.raises(SchemaError, match="bore_diameter_mm"):
                jio.load_case(str(path))


def test_points_and_microphones_refused_at_load(tmp_path):
    """The named points of [housing.points_mm] on the box's outer skin, within 0.6 of its
    longest skin cell edge (the 40 mm cells: 0.6 x sqrt(25² + 27.5²)... measured below), and
    [acoustics]' microphones outside it by more: a point 10 m away, at the cavity's centre or
    just inside the top wall's inner face (the box's top at y = 80 mm, its inner face at 70 mm),
    a microphone inside the box or on its skin: one line each, at load; a point in the top
    wall and a microphone 1 m above the box load."""
    case = ACCESSORY + HOUSING_TABLE

    def point(xyz):
        return case.replace("top = [50.0, 80.0, 0.0]", f"top = {xyz}")

    whined = case + WHINE_TABLE
    bad = {
        point("[50.0, 10080.0, 0.0]"): (
            r"^\[housing\.points_mm\] top = \[50, 10080, 0\]: outside the housing, 1e\+04 mm "
            r"from its outer faces: allowed on its outer skin, within 21\.1 mm of its outer "
            r"faces .*the box spans x \[-75\.27, 174\.7\], y \[-80, 80\], z \[-55, 55\] mm"),
        point("[50.0, 0.0, 0.0]"): r"^\[housing\.points_mm\] top = \[50, 0, 0\]: in the "
                                   r"housing's cavity",
        point("[50.0, 69.0, 0.0]"): r"^\[housing\.points_mm\] top = \[50, 69, 0\]: in the "
                                    r"housing's cavity",
        whined + MIC.format("[50.0, 0.0, 0.0]"): (
            r"^\[acoustics\.microphones\[0\]\] position_mm = \[50, 0, 0\]: inside the housing "
            r"\(microphone 'm'\): allowed outside it, more than 21\.1 mm from its outer faces"),
        whined + MIC.format("[50.0, 80.0, 0.0]"): (
            r"^\[acoustics\.microphones\[0\]\] position_mm = \[50, 80, 0\]: on the housing's "
            r"skin, 0 mm from its outer faces"),
    }
    assert_one_line_errors(bad, tmp_path)
    path = tmp_path / "ok.toml"
    path.write_text(point("[50.0, 75.0, 0.0]") + WHINE_TABLE + MIC.format("[50.0, 1080.0, 0.0]"))
    loaded = jio.load_case(str(path))
    assert dict(loaded.housing.points)["top"] == pytest.approx((0.05, 0.075, 0.0))


def test_skin_edge_is_the_meshed_skins():
    """box_skin_edge (from the grid lines alone) is the longest edge of the outer skin's
    facets of the meshed box (fem_prep.housing.outer_surface), on the accessory box of the
    tests above (its bores, feet and 40 mm cells) and on a box of 12 mm walls, 2 layers."""
    bores = tuple(Bore(w, (x, 80e-3), 25e-3) for w in ("x-", "x+") for x in (75.27e-3, 174.7e-3))
    for length, t, size, layers in ((0.11, 0.01, 0.04, 1), (0.2, 0.012, 0.035, 2)):
        f = 3 * t
        feet = tuple(Foot(xr, yr) for xr in ((0.0, f), (length - f, length))
                     for yr in ((0.0, f), (0.25 - f, 0.25)))
        box = HousingBox(length, 0.25, 0.16, t, bores=bores, feet=feet)
        hm = mesh_box(box, size, layers=layers, element=Tet4())
        skin = outer_surface(hm)
        v = hm.mesh.p[:, hm.mesh.facets[:, skin.facets]]  # (3, 3, F)
        longest = float(np.linalg.norm(v - np.roll(v, 1, axis=1), axis=0).max())
        print("skin's longest edge", longest, "from the grid", box_skin_edge(box, size,
                                                                            layers=layers))
        assert box_skin_edge(box, size, layers=layers) == pytest.approx(longest, rel=1e-12)


def test_outer_distance_and_cavity_by_hand():
    """HousingBox.outer_distance: minus the nearest face's distance inside, the distance to
    the nearest face, edge or corner outside (by Pythagoras), 0 on a face; in_cavity: within
    the inner faces only."""
    box = HousingBox(0.3, 0.2, 0.1, 0.01)
    pts = [(0.15, 0.1, 0.05), (0.15, 0.1, 0.099), (0.15, 0.1, 0.1), (0.15, 0.1, 0.13),
           (0.34, 0.23, 0.05), (-0.03, -0.04, 0.22), (0.15, 0.1, 0.095)]
    want = [-0.05, -0.001, 0.0, 0.03, math.hypot(0.04, 0.03), math.sqrt(0.03**2 + 0.04**2
                                                                        + 0.12**2), -0.005]
    np.testing.assert_allclose(box.outer_distance(pts), want, rtol=0, atol=1e-15)
    assert box.in_cavity(pts).tolist() == [True, False, False, False, False, False, False]


def test_bore_limits_by_hand():
    """bore_limits on a 300 x 200 mm wall of 10 mm: bores at (100, 100), (180, 100) mm (one
    group, 40 mm) and (100, 160) mm (its own group, 50 mm): the group's limit is the least of
    its walls' room (2 x 90 mm round the first), the two axes' distance (80 mm) and the third
    bore's clearance (2 x 60 − 50 = 70 mm): 70 mm, set by the third bore; the third's own is
    the least of its wall room (2 x 30 = 60 mm) and 2 x 60 − 40 = 80 mm: 60 mm, the wall."""
    c = np.array([(0.1, 0.1), (0.18, 0.1), (0.1, 0.16)])
    d = np.array([0.04, 0.04, 0.05])
    first, third = bore_limits(0.3, 0.2, 0.01, c, d, [[0, 1], [2]])
    assert first.diameter == pytest.approx(0.07, abs=1e-15) and first.by == ("bore", 0, 2)
    assert third.diameter == pytest.approx(0.06, abs=1e-15) and third.by == ("wall", 2)
    # against every candidate written out
    cands = [2 * min(u - 0.01, 0.29 - u, v - 0.01, 0.19 - v) for u, v in c[:2]]
    cands += [np.linalg.norm(c[0] - c[1])]
    cands += [2 * np.linalg.norm(c[i] - c[2]) - d[2] for i in (0, 1)]
    assert first.diameter == pytest.approx(min(cands), abs=1e-15)


def test_planetary_stage_box_and_acoustics_at_load(tmp_path):
    """A planetary stage's box round its axis (lin-parker-1999 in a 500 x 500 mm box of 10 mm
    walls): a 600 mm bore refused with its room (500 − 2 x 10 = 480 mm); its [acoustics]
    checked at load as a pair's (an unknown key, a microphone inside the box); with a good
    table the stage loads with its microphones."""
    base = jio.embedded_case_text("lin-parker-1999") + PLANETARY_BOX.format(E=210.0, fc=3000.0) + """
[whine]
speed_min_rad_s = 40.0
speed_max_rad_s = 60.0
speeds = 2
harmonics = 2
positions_per_period = 16
"""
    bad = {
        base.replace("bore_diameter_mm = 300.0", "bore_diameter_mm = 600.0"): (
            r"^\[housing\] bore_diameter_mm = 600: the bore round the stage's axis at \(0, 0\) "
            r"mm does not fit: allowed \(0, 480\] mm there \(within the box's end walls' inner "
            r"faces\)$"),
        base + '[acoustics]\nmethod = "bem"\ncolour = 1\n': r"colour",
        base + MIC.format("[0.0, 0.0, 0.0]"): (
            r"^\[acoustics\.microphones\[0\]\] position_mm = \[0, 0, 0\]: inside the housing"),
    }
    assert_one_line_errors(bad, tmp_path)
    path = tmp_path / "ok.toml"
    path.write_text(base + MIC.format("[0.0, 0.0, 1000.0]"))
    case = jio.load_case(str(path))
    assert jio.acoustics_of(case).microphones == (("m", (0.0, 0.0, 1.0)),)


def test_mesh_file_errors_before_condensing(tmp_path, monkeypatch):
    """``mesh_file``: a corrupt .msh (meshio cannot parse it) refused naming mesh_file; the
    accessory box's own mesh written in mm and read with mesh_unit = "m": its first seat
    refused naming centre_mm, the mesh's extent as read (in m: 1000 x the box) and the unit
    that would hold the seat, and a named point 10 m off its skin, before anything is condensed
    (the cache stays empty)."""
    meshio = pytest.importorskip("meshio")
    monkeypatch.setenv("FEM_PREP_CACHE", str(tmp_path / "cache"))
    bores = tuple(Bore(w, (x, 80e-3), 25e-3) for w in ("x-", "x+") for x in (75.27e-3, 174.7e-3))
    box = HousingBox(0.11, 0.25, 0.16, 0.01, bores=bores,
                     feet=(Foot((0.0, 0.03), (0.0, 0.25)), Foot((0.08, 0.11), (0.0, 0.25))))
    hm = mesh_box(box, 0.04, element=Tet4())
    good = tmp_path / "box.vtu"
    meshio.write(good, meshio.Mesh(hm.mesh.p.T * 1e3, [("tetra", hm.mesh.t.T)]))
    corrupt = tmp_path / "bad.msh"
    corrupt.write_text("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n1\n1 0 0\n$EndNodes\n")
    lines = []
    for s in box.seats():
        lines += ["[[housing.seats]]", f"centre_mm = {[x * 1e3 for x in s.centre]}",
                  f"axis = {list(s.axis)}", f"diameter_mm = {2e3 * s.radius}",
                  f"width_mm = {1e3 * s.width}"]
    table = (HOUSING_BOX.split("width_mm")[0] + 'element = "tet4"\ncutoff_Hz = 2000.0\n'
             + 'mesh_file = "{}"\nmesh_unit = "{}"\n' + "\n".join(lines) + "\n")
    for name, unit, match in (
        ("bad.msh", "mm", (r"^\[housing\] mesh_file = '.*': the file is not a mesh meshio "
                           r"reads \(.*\): allowed a tetrahedral mesh meshio reads")),
        ("box.vtu", "m", (r"^\[housing\.seats\[0\]\] centre_mm = \[5, 75\.27, 80\]: no bore "
                         r"facet of the mesh within diameter_mm / 2 = 25 mm of this seat's axis "
                         r"\(the mesh, read with mesh_unit = 'm', spans x \[0, 1\.1e\+05\], "
                         r"y \[0, 2\.5e\+05\], z \[0, 1\.6e\+05\] mm; read with mesh_unit = "
                         r"'mm' it would hold the seat\)")),
    ):
        path = tmp_path / "file.toml"
        path.write_text(ACCESSORY + table.format(name, unit))
        case = jio.load_case(str(path))
        with pytest.raises(SchemaError, match=match) as err:
            case.housing_body()
        assert "\n" not in str(err.value)
        assert not any((tmp_path / "cache").rglob("*.npz")), "condensed before the check"
    path.write_text(ACCESSORY + table.format("box.vtu", "mm")
                    + "[housing.points_mm]\nfar = [0.0, 10000.0, 0.0]\n")
    case = jio.load_case(str(path))
    assert len(case.housing.seats) == 4
    with pytest.raises(SchemaError, match=r"^\[housing\.points_mm\] far = \[0, 10000, 0\]: "
                       r".* mm from the housing's outer surface") as err:
        case.housing_body()  # a mesh file's points: on its skin once read, before condensing
    assert "\n" not in str(err.value)
    assert not any((tmp_path / "cache").rglob("*.npz")), "condensed before the check"


def test_every_shipped_housing_loads():
    """The embedded housed cases and the examples with [housing] pass the checks at load."""
    for name in ("power-helical-housed", "nrel-5mw-stage3-housed", "nrel-5mw-planetary-housed",
                 "two-stage-housed"):
        assert jio.load_case(name).housing is not None
    example = pathlib.Path(__file__).parents[1] / "examples" / "hybrid-pair-housed.toml"
    assert jio.load_case(str(example)).housing is not None


def test_seats_sharing_nodes_one_line(tmp_path, monkeypatch):
    """Bores of 90 mm round the accessory pair's axes 99.45 mm apart fit the box (loaded), but
    on its 40 mm cells (a bore's seat takes the facets within one cell diagonal of its
    radius: 90 / 4 = 22.5 mm cells across it) the two seats share nodes: one line naming
    [housing] when the box is meshed, before the condensation's eigensolve."""
    monkeypatch.setenv("FEM_PREP_CACHE", str(tmp_path / "cache"))
    path = tmp_path / "near.toml"
    path.write_text(ACCESSORY + HOUSING_TABLE.replace("bore_diameter_mm = 50.0",
                                                      "bore_diameter_mm = 90.0"))
    case = jio.load_case(str(path))
    with pytest.raises(SchemaError, match=r"^\[housing\]: two seats' bores share nodes of the "
                       r"mesh .*a finer mesh_size_mm$") as err:
        case.housing_body()
    assert "\n" not in str(err.value)


def test_a_band_below_the_first_looks_speeds_refused_before_work(tmp_path, capsys):
    """``cutoff_Hz = 10`` (no [whine]): the band (cut-off / 1.5) lies below order 1 of the mesh
    frequency at the lowest speed of ``jaxgear run``'s dynamic factor sweep, which keeps to the
    band and would crawl at speeds whose time plans do not fit: refused in one line before any
    work, naming the least cut-off (1.5 z1 Ω_0 / 2π from the case's teeth and that speed)."""
    from jaxgear.cli import main
    from jaxgear.cli.run import run_sweep_speeds

    path = tmp_path / "low.toml"
    path.write_text(ACCESSORY + HOUSING_BOX + "cutoff_Hz = 10.0\n")
    case = jio.load_case(str(path))  # the file alone is valid: only the sweep needs the band
    low = float(run_sweep_speeds(case.form)[0])
    least = 1.5 * case.pair.pinion.teeth * low / (2 * math.pi)
    out = tmp_path / "out"
    assert main(["run", str(path), "--out", str(out), "--quiet"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1, err
    assert err.endswith(f"allowed cutoff_Hz >= {least:.4g} (1.5 x it)"), err
    assert "[housing] cutoff_Hz = 10: out of range: its band (cut-off / 1.5 = 6.667 Hz)" in err
    assert not out.exists()
