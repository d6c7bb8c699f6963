"""Backlash and the coast flank (docs/backlash.md): the backlash of a pair against a hand
calculation, the coast flanks' quasi-static contact under a reversed torque, and the refusals."""

import dataclasses
import math

import jax.numpy as jnp
import numpy as np
import pytest
from _toml import small_helical_pair

import jaxgear as jg
import jaxgear.io as jio
import jaxgear.scenes as js
from jaxgear.io import static_scene


def _inv(a):
    return math.tan(a) - a


def _pair(A1=-40e-6, A2=-30e-6, beta=15.0, center_distance=None, x=(0.2, -0.1)):
    return jg.GearPair(
        jg.Member(20, x[0], face_width=0.02, tooth_thickness_allowance=A1),
        jg.Member(41, x[1], face_width=0.02, tooth_thickness_allowance=A2),
        2e-3,
        math.radians(20.0),
        math.radians(beta),
        center_distance=center_distance,
    )


@pytest.mark.parametrize("beta", [0.0, 15.0])
@pytest.mark.parametrize("extra_mm", [0.0, 0.05])
def test_backlash_equals_the_hand_calculation_on_the_operating_pitch_circle(beta, extra_mm):
    """j_wt = p_wt − s_w1 − s_w2 on the operating pitch circle (ISO 21771: s_w = d_w (s_t/d +
    inv α_t − inv α_wt), s_t = m_t (π/2 + 2 x tan α_n) + A_sn/cos β), j_bt = j_wt cos α_wt,
    j_bn = j_bt cos β_b: a different route than the code's base-circle thicknesses."""
    a0 = _pair(0.0, 0.0, beta).center_distance
    pair = _pair(beta=beta, center_distance=a0 + extra_mm * 1e-3)
    mn, an, b = 2e-3, math.radians(20.0), math.radians(beta)
    mt = mn / math.cos(b)
    at = math.atan(math.tan(an) / math.cos(b))
    z = (20, 41)
    d = [zi * mt for zi in z]
    awt = math.acos((d[0] + d[1]) / 2 * math.cos(at) / pair.center_distance)
    dw = [di * math.cos(at) / math.cos(awt) for di in d]
    st = [
        mt * (math.pi / 2 + 2 * x * math.tan(an)) + A / math.cos(b)
        for x, A in ((0.2, -40e-6), (-0.1, -30e-6))
    ]
    sw = [dw[i] * (st[i] / d[i] + _inv(at) - _inv(awt)) for i in range(2)]
    jwt = math.pi * dw[0] / z[0] - sw[0] - sw[1]
    bb = math.atan(math.tan(b) * math.cos(at))
    assert pair.circumferential_backlash == pytest.approx(jwt, rel=1e-12)
    assert pair.transverse_backlash == pytest.approx(jwt * math.cos(awt), rel=1e-12)
    assert pair.normal_backlash == pytest.approx(jwt * math.cos(awt) * math.cos(bb), rel=1e-12)
    # DIN 3967's first-order reading: −(A_sn1 + A_sn2) cos α_n + 2 Δa sin α_wt cos β_b (1 %)
    approx = 70e-6 * math.cos(an) + 2 * extra_mm * 1e-3 * math.sin(awt) * math.cos(bb)
    assert pair.normal_backlash == pytest.approx(approx, rel=0.01)


def test_zero_allowances_at_the_zero_backlash_distance_give_zero_backlash():
    pair = _pair(0.0, 0.0)
    assert pair.normal_backlash == 0.0 or pair.normal_backlash < 1e-18
    assert pair.backlash_center_distance == pytest.approx(pair.center_distance, rel=1e-14)


def test_thinned_teeth_may_sit_closer_than_the_nominal_zero_backlash_distance():
    pair = _pair()
    closer = _pair(center_distance=0.5 * (pair.center_distance + pair.backlash_center_distance))
    assert 0 < closer.normal_backlash < pair.normal_backlash
    with pytest.raises(ValueError, match="center_distance = .*zero-backlash"):
        _pair(center_distance=pair.backlash_center_distance * (1 - 1e-6))


def test_bad_allowance_is_one_line_error():
    with pytest.raises(
        ValueError, match=r"pinion.tooth_thickness_allowance = 0.001 is out of range"
    ):
        _pair(A1=1e-3)


def _mesh(pair, slices=8, coast=True):
    s, k = jg.stiffness_table(pair, jg.Weber())
    return jg.MeshModel.from_pair(pair, s, k, slices, coast=coast)


def test_coast_cells_follow_the_drive_cells_of_the_second_base_plane():
    pair = _pair()
    mesh, drive = _mesh(pair), _mesh(pair, coast=False)
    th = jnp.asarray(0.1)
    c, d = mesh.cells(th), drive.cells(th)
    L = drive.n_lines
    assert mesh.n_lines == 2 * L and mesh.n_drive_lines == L
    np.testing.assert_array_equal(c.flank[:L], 1.0)
    np.testing.assert_array_equal(c.flank[L:], -1.0)
    np.testing.assert_allclose(c.s[:L], d.s, rtol=0, atol=0)
    np.testing.assert_allclose(c.s[L:], drive.cells(mesh.coast_angle - th).s, rtol=0, atol=0)


@pytest.mark.parametrize("scene_kind", ["rigid", "torsional"])
def test_negative_torque_loads_the_coast_flank_te_shifts_by_the_backlash(scene_kind):
    """Symmetric teeth: the coast solve at θ is the drive solve at θ_c − θ shifted by the
    backlash, TE(−T, θ) = −j_bn/cos β_b − TE(T, θ_c − θ) (tip relief and crowning on both
    flanks; helical)."""
    pair = _pair()
    mesh = _mesh(pair)
    drive = _mesh(pair, coast=False)
    mods = jg.Modifications(
        pinion=jg.MemberModification(
            tip_relief_depth=8e-6, tip_relief_extent=0.2, crowning_depth=3e-6
        )
    )
    scenes = {
        "rigid": (mesh, drive),
        "torsional": (js.TorsionalPair(mesh, 2e5), js.TorsionalPair(drive, 2e5)),
    }[scene_kind]
    th = jg.mesh_positions(mesh, 12)
    rev = jg.quasi_static(scenes[0], mods, -150.0, th)
    ref = jg.quasi_static(scenes[1], mods, 150.0, mesh.coast_angle - th)
    cb = math.cos(pair.base_helix_angle)
    expected = -pair.normal_backlash / cb - np.asarray(ref.transmission_error)
    np.testing.assert_allclose(np.asarray(rev.transmission_error), expected, rtol=1e-10, atol=1e-16)
    # the drive side is unchanged by the coast cells
    fwd = jg.quasi_static(scenes[0], mods, 150.0, th)
    same = jg.quasi_static(scenes[1], mods, 150.0, th)
    np.testing.assert_allclose(fwd.transmission_error, same.transmission_error, rtol=1e-12)
    L = drive.n_lines
    assert float(jnp.max(rev.line_load[:, :L])) == 0.0 < float(jnp.max(rev.line_load[:, L:]))


def test_lumped_3d_reversed_torque_mirrors_the_bearing_forces():
    """A spur pair on shafts symmetric about the gears' mid-plane: under −T the coast flank
    carries the load on the second line of action, the bearing forces mirror through the
    centre line (F_y flips, F_x stays) and the TE shifts by the backlash."""
    case = jio.load_case("accessory-spur").replace(slices=6)
    p = case.pair
    pair = dataclasses.replace(
        p,
        pinion=dataclasses.replace(p.pinion, tooth_thickness_allowance=-30e-6),
        gear=dataclasses.replace(p.gear, tooth_thickness_allowance=-30e-6),
        center_distance=p.center_distance,
    )
    # coast flanks: the theoretical path (extended contact with backlash is refused)
    case = case.replace(pair=pair, coast=True, contact_geometry=jg.TheoreticalPath())
    scene, _ = static_scene(case)
    mesh = scene.base_planes[0]
    th = jg.mesh_positions(mesh, 6)
    rev = jg.quasi_static(scene, case.modifications, -case.torque, th)
    ref = jg.quasi_static(scene, case.modifications, case.torque, mesh.coast_angle - th)
    cb = math.cos(pair.base_helix_angle)
    np.testing.assert_allclose(
        rev.transmission_error, -pair.normal_backlash / cb - ref.transmission_error, rtol=1e-9
    )
    F_rev = np.asarray(scene.base.bearing_forces(th, rev.x))
    F_ref = np.asarray(scene.base.bearing_forces(th, ref.x))
    flip = np.array([-1.0 if n.endswith(("Fy", "Fz")) else 1.0 for n in scene.base.reaction_names])
    np.testing.assert_allclose(F_rev, F_ref * flip, rtol=1e-9, atol=1e-9 * np.abs(F_ref).max())


def test_deviations_with_backlash_are_refused():
    pair = _pair()
    mesh = _mesh(pair)
    dev = jg.Deviations(pinion=jg.GearDeviations(np.zeros(20)))
    with pytest.raises(ValueError, match="deviations .* with backlash .* not modelled"):
        jg.quasi_static(mesh, jg.Modifications(deviations=dev), 100.0, periods=1)


SMALL = small_helical_pair(
    "small-backlash",
    pinion="tooth_thickness_allowance_um = -40.0\n",
    gear="tooth_thickness_allowance_um = -30.0\n",
    slices=6,
    positions_per_pitch=8,
)


def _parse(text):
    import tomllib

    return jio.parse_case(tomllib.loads(text))


def test_case_keys_give_the_allowances_and_the_coast_flanks():
    case = _parse(SMALL)
    assert case.coast
    assert case.pair.pinion.tooth_thickness_allowance == pytest.approx(-40e-6, rel=1e-15)
    assert case.pair.gear.tooth_thickness_allowance == pytest.approx(-30e-6, rel=1e-15)
    mesh = case.mesh_model()
    assert mesh.coast and float(mesh.backlash) == pytest.approx(case.pair.normal_backlash)
    plain = _parse(
        SMALL.replace("tooth_thickness_allowance_um = -40.0\n", "").replace(
            "tooth_thickness_allowance_um = -30.0\n", ""
        )
    )
    assert not plain.coast and not plain.mesh_model().coast


def test_extended_contact_default_is_off_with_backlash():
    """docs/extended-contact.md, "Where it is on": a case file that does not say has contact
    beyond the path; with a tooth thickness allowance (the coast flanks, where it is not
    modelled) the default resolves to the theoretical path; an explicit true beside it is a
    one-line error, an explicit false is accepted."""
    plain = _parse(
        SMALL.replace("tooth_thickness_allowance_um = -40.0\n", "").replace(
            "tooth_thickness_allowance_um = -30.0\n", ""
        )
    )
    assert plain.contact_geometry == jg.BeyondPath()
    assert plain.mesh_model().contact_geometry == jg.BeyondPath()
    case = _parse(SMALL)
    assert case.coast and case.contact_geometry == jg.TheoreticalPath()
    assert case.mesh_model().contact_geometry == jg.TheoreticalPath()
    with pytest.raises(
        jio.SchemaError,
        match=r"^\[mesh\] extended_contact = true: with backlash \(coast flanks; a "
        r"tooth_thickness_allowance_um\) is not modelled: set it false or drop the allowances$",
    ):
        _parse(SMALL.replace("[mesh]\n", "[mesh]\nextended_contact = true\n"))
    off = _parse(SMALL.replace("[mesh]\n", "[mesh]\nextended_contact = false\n"))
    assert off.coast and off.contact_geometry == jg.TheoreticalPath()


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        (
            "",
            r"\[pinion\] tooth_thickness_allowance_um = -600: out of range, allowed \[-500, 500\]",
        ),
        (
            "[deviations]\ngrade = 6\n",
            r"\[pinion\] tooth_thickness_allowance_um = -40: backlash "
            r"\(coast flanks\) with \[deviations\] is not modelled",
        ),
    ],
)
def test_bad_allowance_keys_are_one_line_errors(extra, message):
    text = SMALL + extra
    if not extra:
        text = text.replace("= -40.0", "= -600.0")
    with pytest.raises(ValueError, match=message) as err:
        _parse(text)
    assert "\n" not in str(err.value)


def test_a_train_gear_has_no_allowance_key():
    case = jio.load_case("accessory-idler-train")
    raw = {**case.raw}
    raw["gears"] = [dict(g) for g in raw["gears"]]
    raw["gears"][0]["tooth_thickness_allowance_um"] = -20.0
    with pytest.raises(ValueError, match="tooth_thickness_allowance_um") as err:
        jio.parse_train(raw)
    assert "\n" not in str(err.value)


def test_run_summary_has_the_backlash(tmp_path, no_figures):
    import json

    from jaxgear.cli import main

    path = tmp_path / "c.toml"
    path.write_text(SMALL)
    assert main(["run", str(path), "--out", str(tmp_path / "o"), "--quiet"]) == 0
    s = json.loads((tmp_path / "o" / "summary.json").read_text())
    pair = _parse(SMALL).pair
    assert s["backlash"]["backlash_normal_m"] == pytest.approx(pair.normal_backlash, rel=1e-12)
