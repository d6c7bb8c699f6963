"""Bearing choice as ``jaxgear optimise`` (``[optimise.choices]``) and a tapered roller pair's
end play as a bearing's clearance variable (docs/optimise.md, "Bearing choice";
docs/bearings.md, "As a design variable").

References, each apart from the code under test: each candidate run separately through the
single-bearing optimisation (its case file written by text replacement, loaded, its problem
built and minimised: ``jaxgear.io.case_problem`` and ``optimise.minimise``), the bore of a
catalogue entry against the shaft's diameter (ISO 15's 25 and 17 mm bores on a 25 mm shaft),
central finite differences of the objective re-evaluated at e ± h with the loads held
(Richardson-extrapolated) for the end play's derivative."""

from __future__ import annotations

import csv
import json
import tomllib
from pathlib import Path

import jax.numpy as jnp
import numpy as np
import pytest
from _convergence import gradient_and_differences

import jaxgear.io as jio
import optimise as op
from jaxgear.cli import main

ROOT = Path(__file__).resolve().parents[1]
ROLLING = ROOT / "examples" / "accessory-lumped3d-rolling.toml"
PLAIN = ROOT / "examples" / "fzg-c14-lubricated.toml"
SEAT = "pinion_shaft.bearings[0]"
VAR = f"{SEAT}.clearance"

#: the rolling example's first pinion bearing (a 6206 from its geometry) and the replacements
_FIRST = ROLLING.read_text().index("position_mm = 0.0\nkind")
_SECOND = ROLLING.read_text().index("[[scene.pinion_shaft.bearings]]", _FIRST)


def _case_text(first: str, optimise: str = "") -> str:
    """The rolling example on a 25 mm pinion shaft (16 positions per pitch), its pinion's
    first bearing the table ``first`` (at position 0), with ``optimise`` appended."""
    text = ROLLING.read_text()
    text = text[:_FIRST] + "position_mm = 0.0\n" + first + text[_SECOND:]
    assert text.count("diameter_mm = 30.0\n") == 1  # the pinion shaft's
    text = text.replace("diameter_mm = 30.0\n", "diameter_mm = 25.0\n")
    text = text.replace("positions_per_pitch = 64", "positions_per_pitch = 16")
    return text + optimise


_CHOICE = f'\n[optimise]\nvars = ["{VAR}"]\nmax_iterations = 2\n[optimise.choices]\n'
_AS_GIVEN = "\n[optimise]\n[optimise.choices]\n"  # each candidate evaluated as given


@pytest.mark.parametrize(
    ("first", "optimise", "match"),
    [
        ('catalogue = "6205"\n', _CHOICE + f'"{SEAT}" = ["6205", "6206"]\n',
         r"\[optimise\.choices\] 'pinion_shaft\.bearings\[0\]' = .*unknown catalogue name "
         r"'6206', allowed 6205, 6203, 7205 B"),
        ('catalogue = "6205"\n', _CHOICE + f'"{SEAT}" = []\n',
         r"\[optimise\.choices\] .* = \[\]: allowed a non-empty array of catalogue names"),
        ('catalogue = "6205"\n', _AS_GIVEN + '"gear_shaft.bearings[5]" = ["6205"]\n',
         r"\[optimise\.choices\] .*\[scene\.gear_shaft\] has 2 bearings, allowed "
         r"bearings\[0\] to bearings\[1\]"),
        ('catalogue = "6205"\n', _AS_GIVEN + '"idler.bearings[0]" = ["6205"]\n',
         r"\[optimise\.choices\] .*no \[scene\.idler\] of a lumped3d scene"),
        ('catalogue = "6205"\n', _CHOICE + '"pinion_shaft.bearings[0]" = ["6205"]\n'
         '"gear_shaft.bearings[0]" = ["6205"]\n', r"\[optimise\] choices = .*allowed one "
         "bearing"),
        ('catalogue = "6205"\n', '\n[optimise]\nvars = ["tip_relief.depth"]\n'
         f'[optimise.choices]\n"{SEAT}" = ["6205"]\n', r"\[optimise\] vars = .*with "
         r"\[optimise\.choices\] allowed \[\"pinion_shaft\.bearings\[0\]\.clearance\"\]"),
        ('radial_N_per_um = 200.0\naxial_N_per_um = 100.0\n', _AS_GIVEN + f'"{SEAT}" = ["6205"]\n',
         r"\[optimise\.choices\] .*is a linear bearing"),
        # candidates as inline tables: each read as a scene bearing, named with its key
        ('catalogue = "6205"\n', _AS_GIVEN + f'"{SEAT}" = ["6205", {{ kind = "deep_groove_ball"'
         ', bore_mm = 0.5 }]\n', r'^\[optimise\.choices\."pinion_shaft\.bearings\[0\]"\[1\]\] '
         r"bore_mm = 0\.5: out of range, allowed \[1, 2000\]"),
        ('catalogue = "6205"\n', _AS_GIVEN + f'"{SEAT}" = [{{ catalogue = "6205", arrangement = '
         '"O" }]\n', r"^\[optimise\.choices\..*\[0\]\] arrangement = 'O': not with catalogue = "
         r"'6205' \(a DeepGrooveBall\): allowed with a tapered roller entry"),
        ('catalogue = "6205"\n', _AS_GIVEN + f'"{SEAT}" = [{{ catalogue = "30205", arrangement = '
         '"X", clearance_um = 5.0 }]\n', r"\[0\]\] clearance_um = 5: not with arrangement .*"
         "allowed end_play_um"),
        ('catalogue = "6205"\n', _AS_GIVEN + f'"{SEAT}" = [{{ catalogue = "6205", position_mm = '
         '3.0 }]\n', r"\[0\]\] position_mm = 3: not a candidate's key: a candidate stands where "
         "the case's bearing stands"),
        ('catalogue = "6205"\n', _AS_GIVEN + f'"{SEAT}" = [{{ radial_N_per_um = 200.0 }}]\n',
         r"\[0\]\] kind: missing: a candidate is a rolling bearing from its geometry, allowed "
         "catalogue = <name> or kind = <kind>"),
        ('catalogue = "6205"\n', _AS_GIVEN + f'"{SEAT}" = ["6205", {{ catalogue = "6205", '
         'clearance_um = 5.0 }]\n', r"\[optimise\.choices\] 'pinion_shaft\.bearings\[0\]' = .*"
         r"names the candidate '6205' twice: allowed distinct candidates \(a table's own name"),
        ('catalogue = "6205"\n', _AS_GIVEN + f'"{SEAT}" = [{{ catalogue = "6205", name = "" }}]\n',
         r"\[0\]\] name = '': allowed a non-empty text"),
        ('catalogue = "6205"\n', _AS_GIVEN + f'"{SEAT}" = [3]\n',
         r"\[optimise\.choices\] .*candidate 3: allowed a catalogue name or an inline table"),
    ],
)
def test_choice_refused_one_line(tmp_path, first, optimise, match):
    """``[optimise.choices]`` naming an unknown catalogue entry (the allowed ones listed), an
    empty list, a bearing or shaft the scene does not have, two bearings, with other
    variables, on a linear bearing: one line naming the key when the case loads."""
    path = tmp_path / "c.toml"
    path.write_text(_case_text(first, optimise))
    with pytest.raises(jio.SchemaError, match=match) as e:
        jio.load_case(str(path))
    assert "\n" not in str(e.value)


def test_choice_candidates_as_tables_are_read_and_named(tmp_path):
    """``[optimise.choices]`` candidates as inline tables beside catalogue names: each read as
    the bearing's table (no ``name``), named in the ranking by its ``name``, its catalogue name
    and a pair's arrangement, or its place and kind."""
    pair = {"catalogue": "30205", "arrangement": "O", "end_play_um": 20.0}
    ball = {"kind": "deep_groove_ball", "bore_mm": 25.0, "outer_diameter_mm": 52.0,
            "width_mm": 15.0, "balls": 9, "ball_diameter_mm": 7.9, "pitch_diameter_mm": 39.0}
    path = tmp_path / "c.toml"
    path.write_text(_case_text('catalogue = "6205"\n', _AS_GIVEN + f'"{SEAT}" = ["6205", '
                               '{ catalogue = "30205", arrangement = "O", end_play_um = 20.0 }, '
                               '{ kind = "deep_groove_ball", bore_mm = 25.0, '
                               'outer_diameter_mm = 52.0, width_mm = 15.0, balls = 9, '
                               'ball_diameter_mm = 7.9, pitch_diameter_mm = 39.0 }, '
                               '{ name = "6205 at 5 um", catalogue = "6205", clearance_um = 5.0 }]'
                               '\n'))
    choices = jio.load_case(str(path)).optimise["choices"]
    assert choices == {SEAT: {"6205": {"catalogue": "6205"}, "30205 O": pair,
                              "candidate 3 (deep_groove_ball)": ball,
                              "6205 at 5 um": {"catalogue": "6205", "clearance_um": 5.0}}}


def test_choice_refused_without_a_lumped3d_scene(tmp_path, capsys):
    """A choice on a case without a lumped3d scene: one line when it loads; the library
    refuses it too, and an objective a bearing's stiffness does not act on, before any
    solve."""
    path = tmp_path / "c.toml"
    path.write_text(PLAIN.read_text() + f'\n[optimise]\n[optimise.choices]\n"{SEAT}" = '
                    '["6205"]\n')
    assert main(["optimise", str(path), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "no [scene.pinion_shaft] of a lumped3d scene" in err
    with pytest.raises(ValueError, match=r"runs on a pair case whose \[scene\] is lumped3d"):
        jio.bearing_choices(jio.load_case(str(PLAIN)), SEAT, {"6205": {"catalogue": "6205"}})
    case = jio.load_case(str(ROLLING))
    with pytest.raises(ValueError, match=r"objective = 'dynamic_factor' does not take a "
                       "designed structure") as e:
        jio.bearing_choices(case, SEAT, {"6205": {"catalogue": "6205"}}, "dynamic_factor")
    assert "\n" not in str(e.value)


def test_a_candidate_that_does_not_fit_is_not_ranked(tmp_path):
    """On the 25 mm shaft a 6203 (ISO 15: 17 mm bore) does not fit: listed as not fitting,
    its bore and the seat given, not evaluated (no case, no value); and the example's 6206 seat
    (30 mm) takes no 6205 (25 mm): the check the ranking relies on."""
    path = tmp_path / "c.toml"
    path.write_text(_case_text('catalogue = "6205"\n'))
    (c,) = jio.bearing_choices(jio.load_case(str(path)), SEAT, {"6203": {"catalogue": "6203"}})
    assert not c.fits and c.case is None and c.value is None and c.result is None
    assert c.bore_mm == pytest.approx(17.0, abs=0.01) and c.seat_mm == pytest.approx(25.0)
    (c,) = jio.bearing_choices(jio.load_case(str(ROLLING)), SEAT,
                               {"6205": {"catalogue": "6205"}})
    assert not c.fits and c.seat_mm == pytest.approx(30.0)


def test_case_text_with_bearing_keeps_the_rest(tmp_path):
    """The bearing's table rewritten as a catalogue entry: the written file loads with that
    bearing, its clearance, and every other table as before; a bearing given in an inline
    array is refused in one line (``--write`` checks it before any work)."""
    text = ROLLING.read_text()
    new = jio.case_text_with_bearing(text, "gear_shaft", 1, {
        "position_mm": 100.0, "catalogue": "6205", "clearance_um": 4.5})
    data, old = tomllib.loads(new), tomllib.loads(text)
    assert data["scene"]["gear_shaft"]["bearings"][1] == {
        "position_mm": 100.0, "catalogue": "6205", "clearance_um": 4.5}
    data["scene"]["gear_shaft"]["bearings"][1] = old["scene"]["gear_shaft"]["bearings"][1]
    assert data == old
    inline = '[scene.pinion_shaft]\nbearings = [{ position_mm = 0.0, catalogue = "6205" }]\n'
    with pytest.raises(ValueError, match=r"pinion_shaft\.bearings\[0\]: the case file does not "
                       r"give it as a \[\[scene\.pinion_shaft\.bearings\]\] table") as e:
        jio.check_choice_text(inline, SEAT)
    assert "\n" not in str(e.value)
    jio.check_choice_text(text, "gear_shaft.bearings[1]")


def _separately(tmp_path, name: str, max_iterations: int):
    """One candidate run on its own: the case file with the pinion's first bearing the
    catalogue entry ``name`` (clearance 10 µm), its clearance problem minimised from its own
    clearance; (clearance µm, objective W·s... in m, unscaled, start and optimum)."""
    path = tmp_path / f"alone-{name.replace(' ', '_')}.toml"
    path.write_text(_case_text(f'catalogue = "{name}"\nclearance_um = 10.0\n'))
    case = jio.load_case(str(path))
    problem = jio.case_problem(case, VAR, "te_rms")
    x0 = problem.from_physical(problem.case_values(case.modifications))
    with pytest.warns(UserWarning, match="iteration cap"):
        res = op.minimise(problem, x0, max_iterations=max_iterations, progress=False)
    scale = float(problem.scale)
    return float(res.x[0]), res.value0 * scale, res.value * scale


@pytest.mark.slow  # three candidates' operating points and optimisations, two run again alone
def test_jaxgear_optimise_bearing_choice_ranks_and_writes_the_best(tmp_path, capsys):
    """``jaxgear optimise`` on a case with ``[optimise.choices]`` (6205, NU 205, 6203 at the
    pinion's first bearing of a 25 mm shaft, each clearance optimised by two L-BFGS steps,
    TE RMS): a line per candidate; choice.json and choice.csv rank the two that fit, each
    equal to its candidate run separately through the single-bearing optimisation (1e-9), the
    6203 listed as not fitting and not ranked; the 6205's ISO 281 life given (its C), the NU
    205's not (no C in the catalogue); the bar plot written; ``--write`` leaves the best's
    catalogue entry and clearance in the bearing's table, loading."""
    path = tmp_path / "choice.toml"
    path.write_text(_case_text('catalogue = "6205"\nclearance_um = 10.0\n',
                               _CHOICE + f'"{SEAT}" = ["6205", "NU 205", "6203"]\n'))
    out, new = tmp_path / "o", tmp_path / "best.toml"
    assert main(["optimise", str(path), "--out", str(out), "--write", str(new)]) == 0
    printed = capsys.readouterr().out
    for name in ("6205", "NU 205", "6203"):
        assert f"/3 {name}:" in printed
    assert "bore 17 mm does not fit the shaft's 25 mm: not ranked" in printed
    rep = json.loads((out / "choice.json").read_text())
    rows = rep["candidates"]
    assert [r["fits"] for r in rows] == [True, True, False]
    assert rows[2]["candidate"] == "6203" and rows[2]["rank"] is None
    assert rows[0]["objective"] <= rows[1]["objective"] and rep["best"] == rows[0]["candidate"]
    with open(out / "choice.csv", newline="") as f:
        table = list(csv.DictReader(f))
    assert [r["candidate"] for r in table] == [r["candidate"] for r in rows]
    assert (out / "choice.png").is_file()
    for r in rows[:2]:
        clearance, start, value = _separately(tmp_path, r["candidate"], 2)
        print(f"{r['candidate']}: clearance 10 -> {clearance:.4g} µm, TE RMS {start:.6g} -> "
              f"{value:.6g} m; life {r['life_L10_Mrev']} Mrev")
        assert r["clearance_um"] == pytest.approx(clearance, rel=1e-9)
        assert r["objective_start"] == pytest.approx(start, rel=1e-9)
        assert r["objective"] == pytest.approx(value, rel=1e-9)
        assert (r["life_L10_Mrev"] is None) == (r["candidate"] == "NU 205")
    best = jio.load_case(str(new))
    kind = best.scene.pinion_shaft.bearings[0].rolling
    assert tomllib.loads(new.read_text())["scene"]["pinion_shaft"]["bearings"][0][
        "catalogue"] == rep["best"]
    assert float(kind.clearance) * 1e6 == pytest.approx(rows[0]["clearance_um"], rel=1e-12)


# -- a tapered roller pair's end play as the clearance variable ---------------------------------
_PAIR = """kind = "tapered_roller_pair"
arrangement = "O"
bore_mm = 25.0
outer_diameter_mm = 52.0
width_mm = 16.25
rollers = 15
roller_diameter_mm = 6.5
roller_length_mm = 12.0
pitch_diameter_mm = 39.0
contact_angle_deg = 14.0
end_play_um = 20.0
"""
#: µm: the central differences at held loads, Richardson-extrapolated (at 20 µm the TE RMS
#: curves fast enough in e that (0.02, 0.01) µm leaves 2.5e-5 of truncation; measured 2.7e-6)
H_HELD = (0.01, 0.005)


def test_a_tapered_pairs_end_play_is_its_clearance_variable(tmp_path):
    """A tapered roller pair declares its end play as its clearance field: the variable's
    case-file value is ``end_play_um``; bounds beyond the pair's range (a preload past
    −D_w/(100 tan α) = −260.7 µm) are refused in one line naming the end play, before any
    solve; the written design sets ``end_play_um``."""
    path = tmp_path / "pair.toml"
    path.write_text(_case_text(_PAIR, f'\n[optimise]\nvars = ["{VAR}"]\n'))
    case = jio.load_case(str(path))
    kind = case.scene.pinion_shaft.bearings[0].rolling
    assert kind.clearance_field == "end_play" and jio.clearance_key(kind) == "end_play_um"
    assert float(kind.with_clearance(-1e-5).end_play) == pytest.approx(-1e-5)
    lo = -6.5e-3 / (100 * np.tan(np.radians(14.0))) * 1e6
    with pytest.raises(ValueError, match=r"end_play") as e:
        kind.with_clearance((lo - 1.0) * 1e-6)
    assert "\n" not in str(e.value)
    text = jio.case_text_with_clearance(path.read_text(), "pinion_shaft", 0, 35.0,
                                        "end_play_um")
    assert tomllib.loads(text)["scene"]["pinion_shaft"]["bearings"][0]["end_play_um"] == 35.0


@pytest.mark.slow  # the pair case's operating point, its quasi-static TE RMS and gradient
def test_end_play_derivative_against_held_load_differences(tmp_path):
    """d(TE RMS)/de of the rolling example with the pinion's first bearing a tapered roller
    pair (end play e = 20 µm): jax.grad through the pair's displacement solve and the
    assembly against a central difference of the objective at e ± h with the loads held
    (Richardson over h = 0.01, 0.005 µm; 1e-5); the problem's start is the case's end play."""
    path = tmp_path / "pair.toml"
    path.write_text(_case_text(_PAIR))
    case = jio.load_case(str(path))
    problem = jio.case_problem(case, VAR, "te_rms", bounds={VAR: (0.0, 40.0)})
    assert problem.case_values(case.modifications) == {VAR: pytest.approx(20.0)}
    grad, held = gradient_and_differences(problem, jnp.asarray([20.0]), H_HELD)
    print(f"d(objective)/de: grad {grad:.10g}, held-load differences {held:.10g} "
          f"(rel {abs(grad - held) / abs(held):.2g})")
    assert grad != 0 and grad == pytest.approx(held, rel=1e-5)


#: the 6205 as its own geometry: the CWRU Bearing Data Center's inches (drive end, SKF 6205-2RS
#: JEM: d 0.9843, D 2.0472, B 0.5906, 9 balls of 0.3126, pitch 1.537) and SKF's C, C0, f0
_IN_MM = 25.4
_6205 = (f'{{ name = "6205 from its geometry", kind = "deep_groove_ball", '
         f'bore_mm = {0.9843 * _IN_MM!r}, outer_diameter_mm = {2.0472 * _IN_MM!r}, '
         f'width_mm = {0.5906 * _IN_MM!r}, balls = 9, ball_diameter_mm = {0.3126 * _IN_MM!r}, '
         f'pitch_diameter_mm = {1.537 * _IN_MM!r}, dynamic_rating_kN = 14.8, '
         'static_rating_kN = 7.8, iso281_f0 = 14.0 }')
_30205_O = 'catalogue = "30205"\narrangement = "O"\nend_play_um = 20.0\n'


@pytest.mark.slow  # three candidates' operating points, the pair's again alone
def test_jaxgear_optimise_ranks_table_candidates(tmp_path):
    """``jaxgear optimise`` of a choice among the 6205 by name, the 6205 as an inline table of
    its published geometry and ratings, and a pair of 30205 rows in O as an inline table, each
    evaluated as given (no vars): the table equals the catalogue entry (objective and life,
    1e-12); the pair's objective equals the case file with that pair written into the bearing's
    table, loaded and its problem (``case_problem``) evaluated at its end play (1e-12), its
    clearance column the end play; the names in the ranking; ``--write`` of a pair candidate
    leaves its keys in the bearing's table."""
    path = tmp_path / "choice.toml"
    path.write_text(_case_text('catalogue = "6205"\nclearance_um = 10.0\n', _AS_GIVEN
                               + f'"{SEAT}" = ["6205", {_6205}, {{ catalogue = "30205", '
                               'arrangement = "O", end_play_um = 20.0 }]\n'))
    out, new = tmp_path / "o", tmp_path / "best.toml"
    assert main(["optimise", str(path), "--out", str(out), "--quiet", "--write", str(new)]) == 0
    rep = json.loads((out / "choice.json").read_text())
    rows = {r["candidate"]: r for r in rep["candidates"]}
    assert set(rows) == {"6205", "6205 from its geometry", "30205 O"}
    named, table = rows["6205"], rows["6205 from its geometry"]
    assert table["fits"] and table["clearance_um"] == pytest.approx(10.0, rel=1e-12)
    for key in ("objective", "objective_start", "life_L10_Mrev"):
        assert table[key] == pytest.approx(named[key], rel=1e-12), key
    alone = tmp_path / "pair.toml"
    alone.write_text(_case_text(_30205_O))
    case = jio.load_case(str(alone))
    problem = jio.case_problem(case, VAR, "te_rms")
    x0 = problem.from_physical(problem.case_values(case.modifications))
    value = float(problem.value(x0)) * float(problem.scale)
    pair = rows["30205 O"]
    print(f"TE RMS: 6205 {named['objective']:.10g} (table {table['objective']:.10g}), 30205 O "
          f"{pair['objective']:.10g} (alone {value:.10g}) m")
    assert pair["clearance_um"] == pytest.approx(20.0, rel=1e-12)
    assert pair["objective"] == pytest.approx(value, rel=1e-12)
    assert rep["best"] == min(rows, key=lambda n: rows[n]["objective"])
    # the pair ranks first (its TE RMS 0.2 % under the 6205's): written back as the file
    # that gives it alone
    written = tomllib.loads(new.read_text())["scene"]["pinion_shaft"]
    assert rep["best"] == "30205 O"
    assert written == tomllib.loads(alone.read_text())["scene"]["pinion_shaft"]
    jio.load_case(str(new))
