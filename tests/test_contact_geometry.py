"""The contact geometry kinds (jaxgear.TheoreticalPath, jaxgear.BeyondPath) a mesh model holds:
what each lays out and where its cells act, the one-line refusals, and the deprecated boolean
spellings (``extended_contact``) that still build the same model with a DeprecationWarning."""

import math
import tomllib
from pathlib import Path

import numpy as np
import pytest

import jaxgear as jg
import jaxgear.io as jio


def _pair():
    return jg.GearPair(
        jg.Member(teeth=20, face_width=0.02),
        jg.Member(teeth=40, face_width=0.02),
        normal_module=0.004,
        normal_pressure_angle=math.radians(20.0),
    )


def _mesh(geometry, slices=2):
    pair = _pair()
    s, k = jg.stiffness_table(pair, jg.Uniform(1.4e10))
    return jg.MeshModel.from_pair(pair, s, k, slices, contact_geometry=geometry)


def test_theoretical_path_cells_act_on_the_line_within_the_path():
    pair = _pair()
    mesh = _mesh(jg.TheoreticalPath())
    g = pair.path_of_contact
    assert mesh.contact_geometry.cell_range(mesh) == (0.0, pytest.approx(g))
    s = np.linspace(-0.3, 1.3, 17) * g
    lever_driving, lever_driven, eps, o_t, o_v = (np.asarray(a) for a in mesh.corner(s))
    np.testing.assert_array_equal(lever_driving, 1.0)
    np.testing.assert_array_equal(lever_driven, 1.0)
    np.testing.assert_array_equal(np.stack([eps, o_t, o_v]), 0.0)
    np.testing.assert_array_equal(np.asarray(mesh.extension_separation(s)), 0.0)
    cells = mesh.cells(0.01)
    s_on = np.asarray(cells.s)[np.asarray(cells.mask)]
    assert s_on.min() >= 0.0 and s_on.max() <= g


def test_beyond_path_reaches_the_extension_with_the_corner_gap_there():
    """The cells' extent is the extension table's (CornerContact's gaps and levers at the ends
    of the reach), the corner's gap positive beyond the path and zero on it."""
    pair = _pair()
    mesh = _mesh(jg.BeyondPath())
    (s_a, s_r), _ = jg.extension_table(pair)
    np.testing.assert_allclose(np.asarray(mesh.extension_span), [s_a, s_r], rtol=0)
    lo, hi = mesh.contact_geometry.cell_range(mesh)
    assert float(lo) == pytest.approx(-s_a) and float(hi) == pytest.approx(
        pair.path_of_contact + s_r
    )
    s = np.array([-0.5 * s_a, 0.5 * pair.path_of_contact, pair.path_of_contact + 0.5 * s_r])
    sep = np.asarray(mesh.extension_separation(s))
    ref = jg.CornerContact(pair, s[[0, 2]]).gap * math.cos(pair.base_helix_angle)
    np.testing.assert_allclose(sep[[0, 2]], ref, rtol=1e-3)  # the table's interpolation
    assert sep[1] == 0.0
    lever_driving, lever_driven = (np.asarray(a) for a in mesh.corner(s)[:2])
    lam = jg.CornerContact(pair, s[[0, 2]]).tip_lever
    # before the start the driven gear owns the tip corner, after the end the driving gear
    assert lever_driven[0] == pytest.approx(lam[0], rel=1e-3) and lever_driving[0] == 1.0
    assert lever_driving[2] == pytest.approx(lam[1], rel=1e-3) and lever_driven[2] == 1.0
    # dropping the cells beyond the path lays out the theoretical path's lines
    plain = mesh.with_contact_geometry(jg.TheoreticalPath())
    assert (plain.n_lines, plain.first_line) == (
        _mesh(jg.TheoreticalPath()).n_lines,
        _mesh(jg.TheoreticalPath()).first_line,
    )
    # on_path keeps the shapes; a mesh without cells beyond the path comes back itself
    masked = mesh.contact_geometry.on_path(mesh)
    assert masked.contact_geometry == jg.TheoreticalPath() and masked.n_lines == mesh.n_lines
    assert plain.contact_geometry.on_path(plain) is plain


def test_refusals_in_one_line():
    pair = _pair()
    s, k = jg.stiffness_table(pair, jg.Uniform(1.4e10))
    with pytest.raises(ValueError, match="contact_geometry = True .* allowed") as info:
        jg.MeshModel.from_pair(pair, s, k, 2, contact_geometry=True)
    assert "\n" not in str(info.value)
    with pytest.raises(ValueError, match="needs the gap table") as info:
        _mesh(jg.TheoreticalPath()).with_contact_geometry(jg.BeyondPath())
    assert "\n" not in str(info.value)
    with pytest.raises(ValueError, match="backlash .* is not modelled"):
        jg.MeshModel.from_pair(pair, s, k, 2, coast=True, contact_geometry=jg.BeyondPath())


def test_the_boolean_spellings_warn_and_build_the_same_model():
    pair = _pair()
    s, k = jg.stiffness_table(pair, jg.Uniform(1.4e10))
    with pytest.warns(DeprecationWarning, match="contact_geometry"):
        old = jg.MeshModel.from_pair(pair, s, k, 2, extended_contact=True)
    new = _mesh(jg.BeyondPath())
    assert old.contact_geometry == new.contact_geometry == jg.BeyondPath()
    assert (old.n_lines, old.first_line) == (new.n_lines, new.first_line)
    np.testing.assert_array_equal(np.asarray(old.extension_gap), np.asarray(new.extension_gap))
    with pytest.warns(DeprecationWarning, match="contact_geometry"):
        assert new.extended_contact is True
    with pytest.warns(DeprecationWarning, match="with_contact_geometry"):
        off = new.with_extended_contact(False)
    assert off == new.with_contact_geometry(jg.TheoreticalPath())
    case = jio.load_case("accessory-spur")  # the case file's default: beyond the path
    assert case.contact_geometry == jg.BeyondPath()
    with pytest.warns(DeprecationWarning, match="contact_geometry"):
        plain = case.replace(extended_contact=False)
    assert plain.contact_geometry == jg.TheoreticalPath()
    with pytest.warns(DeprecationWarning, match="contact_geometry"):
        assert plain.extended_contact is False


def test_the_case_file_key_names_the_kind():
    path = Path(__file__).parent.parent / "jaxgear" / "cases" / "accessory-spur.toml"
    data = tomllib.loads(path.read_text())
    for value, kind in ((False, jg.TheoreticalPath()), (True, jg.BeyondPath())):
        data.setdefault("mesh", {})["extended_contact"] = value
        assert jio.parse_case(data).contact_geometry == kind
