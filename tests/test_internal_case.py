"""Internal gears at the case-file edge: a ``[[gears]]`` entry with negative ``teeth`` (ISO 21771)
makes the mesh it is the driven gear of an :class:`jaxgear.InternalGearPair`; ``jaxgear run`` on
a train of that one mesh writes the rigid mesh's quasi-static files, whose TE is checked against
a count of the contact lines written here (rigid teeth, a uniform stiffness per unit length:
TE = F_n / (k0 b n(θ)), n = 1 or 2 pairs in contact); what cannot take an internal mesh yet (an
internal gear driving, a second mesh, a ``[scene]``, a stiffness model without an internal-gear
form) is refused in one line before any work."""

from __future__ import annotations

import json
import math
import tomllib

import pytest

import jaxgear as jg
import jaxgear.io as jio
from jaxgear.cli import main

K0 = 12.0  # N/mm/µm: 1.2e10 N/m per m of contact line
TORQUE = 150.0

GEARS = """
name = "internal"
[[gears]]
name = "planet"
teeth = 20
normal_module_mm = 3.0
normal_pressure_angle_deg = 20.0
profile_shift = 0.3
face_width_mm = 20.0
[[gears]]
name = "ring"
teeth = -90
normal_module_mm = 3.0
normal_pressure_angle_deg = 20.0
face_width_mm = 20.0
"""
# the ring first: the input gear of the train
_PLANET, _RING = GEARS.split("[[gears]]")[1:]
RING_FIRST = GEARS.split("[[gears]]")[0] + "[[gears]]" + _RING + "[[gears]]" + _PLANET
MESH = '\n[[meshes]]\ndriving = "{a}"\ndriven = "{b}"\nangle_deg = 0.0\n'
TAIL = f"""
[mesh]
stiffness = "uniform"
stiffness_per_length_N_per_mm_per_um = {K0}
slices = 2
positions_per_pitch = 32
# theoretical path: the reference counts the contact lines on the path
extended_contact = false
[operating]
torque_Nm = {TORQUE}
"""


def _file(tmp_path, text: str):
    path = tmp_path / "internal.toml"
    path.write_text(text)
    return path


def test_a_negative_tooth_count_makes_an_internal_mesh():
    case = jio.parse_train(tomllib.loads(GEARS + MESH.format(a="planet", b="ring") + TAIL))
    pair = case.pair
    assert isinstance(pair, jg.InternalGearPair)
    assert pair.gear.teeth == -90 and pair.pinion.teeth == 20
    assert case.mesh_name(0) == "planet-ring"
    # ISO 21771: a_w = m (|z2| - z1)/2 cos α / cos α_w,
    # inv α_w = inv α + 2 tan α (x1 + x2)/(z1 + z2)
    alpha = math.radians(20.0)
    inv = math.tan(alpha) - alpha + 2 * math.tan(alpha) * 0.3 / (20 - 90)
    aw = _inverse_involute(inv)
    assert pair.center_distance == pytest.approx(
        3e-3 * 70 / 2 * math.cos(alpha) / math.cos(aw), rel=1e-12
    )


def _inverse_involute(inv: float) -> float:
    a = 0.3
    for _ in range(60):  # Newton on tan a - a = inv
        a -= (math.tan(a) - a - inv) / math.tan(a) ** 2
    return a


def _contact_line_te(pair) -> tuple[float, float]:
    """(TE ptp, TE mean) (m) of rigid spur teeth on a uniform stiffness k0 per unit length:
    F_n/(k0 b) with one pair in contact (a share 2 − ε_α of the period), half with two."""
    one_pair = TORQUE / pair.base_radii[0] / (K0 * 1e9 * pair.face_width)
    eps = pair.transverse_contact_ratio
    return one_pair / 2, one_pair * ((2 - eps) + (eps - 1) / 2)


def test_the_case_files_internal_mesh_against_the_contact_line_count():
    """The fast twin of the ``jaxgear run`` test below: the loaded case's mesh model."""
    case = jio.parse_train(tomllib.loads(GEARS + MESH.format(a="planet", b="ring") + TAIL))
    r = jg.quasi_static(case.mesh_model(), case.modifications, case.torque, positions_per_pitch=32)
    ptp, mean = _contact_line_te(case.pair)
    assert float(r.te_ptp) == pytest.approx(ptp, rel=1e-9)
    assert abs(float(r.te_mean) - mean) <= ptp / 32 + 1e-12 * mean  # within one position


@pytest.mark.slow  # 5-15 s (a pair's run: 4 solves, 2 Harris maps, plots); fast twin above
def test_jaxgear_run_on_an_internal_mesh_against_the_contact_line_count(tmp_path):
    path = _file(tmp_path, GEARS + MESH.format(a="planet", b="ring") + TAIL)
    out = tmp_path / "out"
    assert main(["run", str(path), "--out", str(out), "--quiet"]) == 0
    summary = json.loads((out / "summary.json").read_text())
    for name in ("te.csv", "mesh_stiffness.csv", "pressure_map.png", "transmission_error.png"):
        assert (out / name).is_file(), name
    q = summary["quasi_static"]["exact"]
    pair = jio.load_case(path).pair
    # one pair, then two pairs (half the TE): ptp F/(2 k0 b), the mean by the contact ratio
    ptp, mean = _contact_line_te(pair)
    assert q["te_ptp_m"] == pytest.approx(ptp, rel=1e-9)
    assert abs(q["te_mean_m"] - mean) <= ptp / 32 + 1e-12 * mean  # within one position
    assert summary["geometry"]["transverse_contact_ratio"] == pytest.approx(
        pair.transverse_contact_ratio
    )
    assert q["max_contact_pressure_Pa"] > 0


@pytest.mark.parametrize(
    "text, words",
    [
        (
            RING_FIRST + MESH.format(a="ring", b="planet") + TAIL,
            "[meshes[0]] driving = 'ring': is an internal gear (teeth < 0): allowed as a mesh's "
            "driven gear only",
        ),
        (
            GEARS + MESH.format(a="planet", b="ring") + TAIL + '[scene]\nmodel = "torsional"\n',
            "[scene] model: no scene kind takes an internal mesh yet (allowed: no [scene]",
        ),
        (
            GEARS
            + MESH.format(a="planet", b="ring")
            + TAIL.replace(
                'stiffness = "uniform"\nstiffness_per_length_N_per_mm_per_um = 12.0', ""
            ).replace("[mesh]", '[mesh]\nstiffness = "weber"'),
            "[mesh] stiffness = 'weber': 'weber' cannot take it: ",
        ),
        (
            GEARS.replace("teeth = -90", "teeth = -3") + MESH.format(a="planet", b="ring") + TAIL,
            "[gears.ring] teeth = -3: out of range, allowed [-10000, -5]",
        ),
    ],
)
def test_what_cannot_take_an_internal_mesh_is_refused_in_one_line(tmp_path, capsys, text, words):
    path = _file(tmp_path, text)
    out = tmp_path / "out"
    assert main(["run", str(path), "--out", str(out), "--quiet"]) == 2
    err = capsys.readouterr().err.strip()
    assert words in err and "\n" not in err, err
    assert not out.exists()  # refused before any work


def test_two_meshes_with_an_internal_gear_are_refused():
    text = (
        GEARS + '[[gears]]\nname = "sun"\nteeth = 20\nnormal_module_mm = 3.0\n'
        "normal_pressure_angle_deg = 20.0\nprofile_shift = 0.3\nface_width_mm = 20.0\n"
        + MESH.format(a="planet", b="sun").replace("0.0", "180.0")
        + MESH.format(a="planet", b="ring")
        + TAIL
    )
    words = (
        r"\[meshes\[1\]\] planet → ring: an internal gear is allowed in a train of one mesh only"
    )
    with pytest.raises(ValueError, match=words) as err:
        jio.parse_train(tomllib.loads(text))
    assert "\n" not in str(err.value)


def test_a_sweep_of_an_internal_mesh_is_refused_in_one_line(tmp_path, capsys):
    path = _file(tmp_path, GEARS + MESH.format(a="planet", b="ring") + TAIL)
    out = tmp_path / "sweep"
    assert main(["sweep", str(path), "--speeds", "100:200:2", "--out", str(out), "--quiet"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.endswith(
        "[meshes[0]]: no dynamic scene takes an internal mesh yet (allowed: jaxgear run, the "
        "rigid mesh's quasi-static files)"
    )
    assert "\n" not in err and not out.exists()
