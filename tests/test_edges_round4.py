"""Case files: bad input refused at load with one line naming the key path, the
value as written and the allowed range, before any computation or file (round 4 of the edges)."""

import importlib.resources
import re
import tomllib

import pytest

import fem_prep
import jaxgear.io as jio
from _toml import ACCESSORY_PAIR
from fem_prep import schema as sc
from fem_prep.cli import main as fem_main
from jaxgear.cli import main


def _pair(extra: str = "", *subs) -> dict:
    """The accessory pair (m_n 1.5 mm, α_n 25°, 45/86 teeth) with text replaced and appended."""
    text = ACCESSORY_PAIR
    for old, new in subs:
        assert old in text, old
        text = text.replace(old, new, 1)
    return tomllib.loads(text + extra)


def _embedded(name: str) -> str:
    return (importlib.resources.files("jaxgear") / "cases" / f"{name}.toml").read_text()


def _refused(data, *needles):
    with pytest.raises(sc.SchemaError) as info:
        jio.parse_case(data)
    msg = str(info.value)
    assert "\n" not in msg
    for n in needles:
        assert n in msg, msg
    return msg


PINION_DEDENDUM = "dedendum_coeff = 1.1933\nface_width_mm = 11.5"


@pytest.mark.parametrize(
    ("data", "needles"),
    [
        # the rack's tooth tip too narrow for the default fillet (fe2d said "allowed [0, -0.231]")
        (
            _pair("", (PINION_DEDENDUM, "dedendum_coeff = 2.0\nface_width_mm = 11.5")),
            ("[pinion] dedendum_coeff = 2:", "allowed <= 1.34274", "fillet_radius_coeff = 0.25"),
        ),
        (
            _pair("", (PINION_DEDENDUM, PINION_DEDENDUM + "\nfillet_radius_coeff = 0.5")),
            ("[pinion] fillet_radius_coeff = 0.5:", "allowed [0, 0.359385]"),
        ),
        (
            _pair("", ("face_width_mm = 11.5", "face_width_mm = 1e308")),
            ("[pinion] face_width_mm = 1e+308:", "allowed [0.15, 150]"),
        ),
        (
            _pair("", ("torque_Nm = 80.0", "torque_Nm = 5e-324")),
            ("[operating] torque_Nm = 4.94066e-324:", "allowed >= 2.91e-07"),
        ),
        (
            _pair("[modifications]\ntip_relief = { depth_um = 1e30 }\n"),
            ("[modifications.tip_relief] depth_um = 1e+30:", "allowed [0, 1500]"),
        ),
        (
            _pair("[modifications.gear]\nhelix_slope = { deviation_um = 1e308 }\n"),
            ("[modifications.gear.helix_slope] deviation_um = 1e+308:", "allowed [-1500, 1500]"),
        ),
        (
            _pair("[deviations.pinion]\nrunout_um = 1e6\n"),
            ("[deviations.pinion] runout_um = 1e+06:", "allowed [0, 1500]"),
        ),
        (
            _pair("[deviations.gear]\nprofile_slope_um = 1e300\n"),
            ("[deviations.gear] profile_slope_um = 1e+300:", "allowed [-1500, 1500]"),
        ),
        (
            _pair("[robust]\nspeeds_rad_s = [1e300]\n"),
            ("[robust] speeds_rad_s = [1e+300]:", "allowed (0, 100000]"),
        ),
        (_pair("[robust]\nsamples = 'many'\n"), ("[robust] samples = 'many':", "integer")),
        (
            _pair("[deviations]\ngrade = 6\n", ("teeth = 86", "teeth = 1200")),
            ("[gear] teeth = 1200:", "grade = 6", "allowed [5, 1000]", "ISO 1328-1"),
        ),
        # thickened teeth jam at the default (nominal zero-backlash) centre distance
        (
            _pair(
                "",
                ("teeth = 45", "teeth = 45\ntooth_thickness_allowance_um = 300.0"),
                ("teeth = 86", "teeth = 86\ntooth_thickness_allowance_um = 300.0"),
            ),
            (
                "tooth_thickness_allowance_um = 600:",
                "allowed <= 0",
                "[pair] center_distance_mm >= 100.054",
            ),
        ),
    ],
    ids=[
        "dedendum-default-fillet",
        "fillet-too-large",
        "face-width-1e308",
        "torque-denormal",
        "tip-relief-1e30",
        "helix-slope-1e308",
        "runout-1e6",
        "profile-slope-1e300",
        "robust-speed-1e300",
        "robust-samples-string",
        "grade-1200-teeth",
        "thick-teeth-no-centre-distance",
    ],
)
def test_pair_case_refused_at_load(data, needles):
    _refused(data, *needles)


def test_thick_teeth_with_a_centre_distance_run():
    """The same allowances with a centre distance beyond the jam are a valid backlash case."""
    data = _pair(
        "",
        ("teeth = 45", "teeth = 45\ntooth_thickness_allowance_um = 300.0"),
        ("teeth = 86", "teeth = 86\ntooth_thickness_allowance_um = 300.0"),
        ("normal_module_mm = 1.5", "normal_module_mm = 1.5\ncenter_distance_mm = 100.1"),
    )
    case = jio.parse_case(data)
    assert case.pair.transverse_backlash > 0


def test_train_shaft_bearings_at_one_position(tmp_path):
    """Two radial bearings at one position hold a lumped shaft like one (it ended in 'contact loop
    did not converge' after files were written)."""
    text = _embedded("two-stage")
    old = "{ position_mm = 80.0, radial_N_per_um = 300.0 }"
    assert old in text
    path = tmp_path / "one-seat.toml"
    path.write_text(text.replace(old, "{ position_mm = 10.0, radial_N_per_um = 300.0 }"))
    with pytest.raises(sc.SchemaError) as info:
        jio.load_case(path)
    msg = str(info.value)
    assert msg.startswith("[scene.shafts.input] bearings:"), msg
    assert "allowed at least 0.9 mm apart" in msg


def test_train_depth_bound_is_the_gears_module(tmp_path):
    text = _embedded("two-stage").replace(
        "crowning = { depth_um = 5.0 }", "crowning = { depth_um = 5.0 }\n[modifications.output]\n"
        "tip_relief = { depth_um = 1e300 }"
    )
    path = tmp_path / "deep.toml"
    path.write_text(text)
    with pytest.raises(sc.SchemaError, match=r"^\[modifications\.output\.tip_relief\] depth_um = "
                       r"1e\+300: out of range, allowed \[0, 2500\]"):
        jio.load_case(path)


def test_duplicate_key_names_the_key_and_table(tmp_path):
    text = _embedded("two-stage")
    old = "face_width_mm = 25.0\nfillet_radius_coeff = 0.25\n[[gears]]\nname = \"lst-pinion\""
    assert old in text
    path = tmp_path / "dup.toml"
    path.write_text(text.replace(old, "face_width_mm = 25.0\n" + old, 1))
    with pytest.raises(sc.SchemaError) as info:
        jio.load_case(path)
    msg = str(info.value)
    assert "duplicate key 'face_width_mm' in [[gears]] #2 (line" in msg, msg


@pytest.mark.parametrize(
    ("text", "needle"),
    [
        ("[pinion]\nteeth = \n", "Invalid value at key 'teeth' in [pinion] (line 2"),
        ("[scene.damping]\nmodel = 'modal'\nmodel = 'none'", "duplicate key 'model' in "
         "[scene.damping] (line 3"),
        ("[pair]\n[pair]\n", "table [pair] declared twice (line 2"),
    ],
)
def test_syntax_errors_name_the_key(text, needle):
    with pytest.raises(sc.SchemaError) as info:
        sc.load_toml(text, "case file 'x.toml'")
    assert needle in str(info.value)


def test_body_path_that_is_a_case_file_is_shown_whole(tmp_path):
    folder = tmp_path / "a-rather-long-folder-name" / "and-another-one-below-it"
    folder.mkdir(parents=True)
    case_file = folder / "my-case-file.toml"
    case_file.write_text(_embedded("accessory-spur"))
    text = _embedded("accessory-spur-flexible")
    assert 'body = "accessory-wheel"' in text
    path = tmp_path / "flex.toml"
    path.write_text(text.replace('body = "accessory-wheel"', f'body = "{case_file}"'))
    with pytest.raises(sc.SchemaError) as info:
        jio.load_case(path)
    msg = str(info.value)
    assert msg.startswith(f"[scene.gear_body] body = '{case_file}': "), msg
    assert "jaxgear case file" in msg


@pytest.mark.parametrize(
    ("subs", "key"),
    [
        ((("face_width_mm = 11.5", "face_width_mm = 1e308"),), "[pinion] face_width_mm"),
        ((("torque_Nm = 80.0", "torque_Nm = 5e-324"),), "[operating] torque_Nm"),
    ],
)
def test_run_refuses_before_writing(tmp_path, capsys, subs, key):
    text = ACCESSORY_PAIR
    for old, new in subs:
        text = text.replace(old, new)
    path = tmp_path / "bad.toml"
    path.write_text(text)
    out = tmp_path / "out"
    status = main(["run", str(path), "--out", str(out), "--quiet"])
    err = capsys.readouterr().err.strip().splitlines()
    assert status == 2 and len(err) == 1 and key in err[0] and "allowed" in err[0]
    assert not out.exists()


# --------------------------------------------------------------------------------------------
# fem-prep body files


def _body_text(name: str, *subs) -> str:
    text = (importlib.resources.files("fem_prep") / "bodies" / f"{name}.toml").read_text()
    for old, new in subs:
        assert re.search(rf"(?m)^{re.escape(old)}", text), old
        text = re.sub(rf"(?m)^{re.escape(old)}", new, text, count=1)
    return text


@pytest.mark.parametrize(
    ("subs", "needles"),
    [
        # a 4 GiB NumPy allocation in the mesher
        (
            (("size_mm = 3.5", "size_mm = 0.06"),),
            ("[mesh] size_mm = 0.06:", "DOFs", "allowed <= 2e+06", "raise size_mm"),
        ),
        # at the printed floor exactly: not refused by the floor (it said "allowed >= 0.052")
        (
            (("rim_outer_radius_mm = 32.47", "rim_outer_radius_mm = 52.0"),
             ("size_mm = 3.5", "size_mm = 0.052")),
            ("[mesh] size_mm = 0.052: out of range: the mesh would have about",),
        ),
        (
            (("modes = 50", "modes = 1e9"),),
            ("[condensation] modes = 1e+09:", "allowed [0, 2000]"),
        ),
        (
            (("speed_rad_s = ", "speed_rad_s = 1e300 #"),),
            ("[centrifugal] speed_rad_s = 1e+300:", "allowed [0, 100000]"),
        ),
    ],
    ids=["size-4GiB", "size-at-floor", "modes-1e9", "speed-1e300"],
)
def test_body_refused_before_meshing(tmp_path, capsys, subs, needles):
    text = _body_text("accessory-pinion", *subs)
    with pytest.raises(sc.SchemaError) as info:
        fem_prep.parse_body(text)
    msg = str(info.value)
    for n in needles:
        assert n in msg, msg
    assert "allowed >= 0.052" not in msg
    path = tmp_path / "body.toml"
    path.write_text(text)
    out = tmp_path / "out"
    assert fem_main(["build", str(path), "--out", str(out), "--quiet", "--no-cache"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and needles[0] in err[0]
    assert not out.exists()


def test_robust_grade_outside_iso1328_scope():
    data = _pair("[robust]\ngrade = 6\n", ("teeth = 86", "teeth = 1200"))
    _refused(data, "[gear] teeth = 1200:", "[robust] grade = 6", "allowed [5, 1000]")


def test_train_table_too_large_for_memory(tmp_path):
    """A two-stage train with a 3500-tooth LST pinion: its mesh period, 127/3500 HST periods, is
    no whole number of the 140 steps, so the table spans 17 780 rows (it ended in
    'JaxRuntimeError: YNNPACK operation failed' after 108 s); refused naming steps_per_period."""
    text = _embedded("two-stage")
    text = re.sub(r'(name = "lst-pinion"[^\[]*?teeth = )\d+', r"\g<1>3500", text, count=1)
    path = tmp_path / "big.toml"
    path.write_text(text)
    with pytest.raises(sc.SchemaError) as info:
        jio.load_case(path)
    msg = str(info.value)
    assert msg.startswith("[scene.integration] steps_per_period = 140: out of range"), msg
    assert "17780 rows" in msg and "allowed <= 1 GB" in msg and "a multiple of 3500" in msg


@pytest.mark.parametrize(
    ("old", "new", "needles"),
    [
        ("torque_Nm = 70.0", "torque_Nm = 5e-324", ("[operating] torque_Nm = 4.94066e-324:",)),
        (
            "face_width_mm = 25.0",
            "face_width_mm = 1e308",
            ("[gears.input] face_width_mm = 1e+308:", "allowed [0.15, 150]"),
        ),
        (
            "dedendum_coeff = 1.25",
            "dedendum_coeff = 2.0",
            ("[gears.input] dedendum_coeff = 2:", "allowed <= 1.34274"),
        ),
    ],
)
def test_train_gear_and_torque_bounds(tmp_path, old, new, needles):
    text = _embedded("two-stage")
    assert old in text
    path = tmp_path / "bad.toml"
    path.write_text(text.replace(old, new, 1))
    with pytest.raises(sc.SchemaError) as info:
        jio.load_case(path)
    for n in needles:
        assert n in str(info.value), str(info.value)
