"""A gearbox-level ``[housing]`` in a gearbox case file (jaxgear.io.GearboxForm.housing): one box
shared by its lumped 3D pair stages (``model = "lumped3d"``), each stage placed by
``housing_position_mm`` and seated by ``housing_seats`` (docs/gearbox.md, "One housing for
several stages"). tests/data/gearbox/two-pair-housed.toml: tests/data/gearbox/two-pair-whine.toml's
pairs on 60 mm shafts, stage 2's scene 150 mm above stage 1's, in one steel box.

Reference, apart from the code under test: the same gearbox built by hand in Python: the box of
the housing table's rules written out here in numbers (its length the bearings' span plus a
wall, 130 mm; centred on the four axes across; a 70 mm bore round each axis in both end walls;
30 mm square feet), meshed and condensed by fem_prep, placed once in stage 1's scene frame (the
gearbox frame) with jaxgear.scenes.Housing.of, the stages' lumped_pair scenes on that one object
(stage 2 at its place, housing_position) and the chain's shared housing: the same coupled modes
and housing energy (a check of the reader).
"""

import dataclasses
import json
import math
import pathlib

import equinox as eqx
import jax.numpy as jnp
import numpy as np
import pytest
from _examples import load_example
from _toml import assert_one_line_errors
from test_gearbox_case_lumped import lumped_pair_stage
from test_gearbox_whine import TEETH

import fem_prep
import jaxgear.io as jio
import jaxgear.planetary as jp
from fem_prep.housing import Bore, Foot, HousingBox, Tet4, condensed_housing, mesh_box
from fem_prep.schema import SchemaError
from jaxgear import gearbox as gb
from jaxgear.cli import main
from jaxgear.cli.gearbox import COUPLED_RUN, chain_modes, gearbox_whine_outputs
from jaxgear.dynamics import QuasiPeriodicBalance
from jaxgear.scenes import Housing, HousingMount

DATA = pathlib.Path(__file__).parent / "data" / "gearbox"
CASE = DATA / "two-pair-housed.toml"
TORQUE, SHAFT = 200.0, 2e5
POLAR = ((0.0006213278084797084, 0.004794196053084167),
         (0.0007315362629828136, 0.005291895403577801))
# the housing frame -> the scene frame: housing x (length) along scene z, y along scene x, z
# along scene y (docs/housing.md)
R = np.array([[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]])
STAGE2 = np.array([0.0, 0.15, 0.0])  # stage 2's scene origin in stage 1's frame (m)


def _box_round(axes):
    """The files' box in numbers: 130 x 220 x 280 mm, its origin at scene (-60.5, -65, -65)
    mm, steel, 10 mm walls, Tet4 50 mm cells, four feet, condensed to 6 kHz with rigid seats;
    a bore of diameter d round each axis (x, y, d) of ``axes`` (m) in both end walls, the -z
    wall's first. Returns (the condensed housing, the origin)."""
    off = np.array([-0.0605, -0.065, -0.065])
    bores = tuple(Bore(w, (x - off[0], y - off[1]), d / 2) for w in ("x-", "x+")
                  for x, y, d in axes)
    feet = tuple(Foot(xr, yr) for xr in ((0.0, 0.03), (0.1, 0.13))
                 for yr in ((0.0, 0.03), (0.19, 0.22)))
    box = HousingBox(0.13, 0.22, 0.28, 0.01, bores=bores, feet=feet)
    mesh = mesh_box(box, 0.05, layers=1, element=Tet4())
    return condensed_housing(mesh, fem_prep.Material(210e9, 0.3, 7800.0), 6000.0,
                             coupling=fem_prep.Rigid()), off


def _box(stage2_bore=0.07):
    """The box the file asks for, in numbers: 130 x 220 x 280 mm (length: the bearings' span
    120 mm + the 10 mm wall), centred across on the axes (x 0..99 mm, y 0..150 mm: the box's
    origin at scene (-60.5, -65, -65) mm); bores round the four axes (70 mm round stage 1's,
    ``stage2_bore`` (m) round stage 2's), the -z wall's first (seats 0-3: stage 1's pinion and
    gear shafts, then stage 2's), then the +z wall's."""
    axes = [(0.0, 0.0, 0.07), (0.096, 0.0, 0.07), (0.0, 0.15, stage2_bore),
            (0.099, 0.15, stage2_bore)]
    return _box_round(axes)


def _by_hand(stage2_bore=0.07, **run):
    """The file's gearbox built here: the box placed once in stage 1's frame (the gearbox
    frame), stage 2's scene on the same object at its place ``STAGE2`` there."""
    ch, off = _box(stage2_bore)
    shared = Housing.of(ch, loss_factor=0.02, rotation=R, offset=off)
    stages = [lumped_pair_stage(TEETH[0], POLAR[0], housing=shared),
              lumped_pair_stage(TEETH[1], POLAR[1], housing=shared, seats=(2, 6, 3, 7),
                                housing_position=STAGE2)]
    return (gb.GearboxTorsional(tuple(stages), [SHAFT], housing=shared),
            gb.GearboxRun(TORQUE, SHAFT, mean_positions=COUPLED_RUN["mean_positions"], **run))


def _same_coupled_modes(form, coupled, chain, run):
    """The file's coupled chain against the hand-built one: the same coordinate names, coupled
    modes to 1e-10 and housing energies to 1e-8; ``jaxgear run``'s rows (chain_modes) the same
    frequencies, each row's stage and housing kinetic shares summing to 1. Returns the
    hand-built chain's coupled modes."""
    assert gb.coordinate_names(coupled) == gb.coordinate_names(chain)
    got, ref = (gb.gearbox_coupled_modes(c, run) for c in (coupled, chain))
    np.testing.assert_allclose(np.asarray(got.analysis.frequency),
                               np.asarray(ref.analysis.frequency), rtol=1e-10)
    np.testing.assert_allclose(np.asarray(got.housing_energy), np.asarray(ref.housing_energy),
                               atol=1e-8)
    rows = chain_modes(form)
    np.testing.assert_allclose([r["frequency_Hz"] for r in rows],
                               np.asarray(ref.analysis.frequency), rtol=1e-10)
    for r in rows:
        assert sum(r["stage_energy"]) + r["housing_energy"] == pytest.approx(1.0, abs=1e-9)
    return ref


def test_the_file_builds_the_hand_built_housed_gearbox(tmp_path):
    """The reader's coupled chain (both stages in the one box, its coordinates once) has the
    hand-built chain's coupled modes to 1e-10 and housing energies to 1e-8; ``jaxgear run``'s
    modes (chain_modes) and ``jaxgear modes``' are these, each with the stages' and the
    housing's kinetic shares summing to 1."""
    case = jio.load_case(str(CASE))
    assert case.form.housed() == (0, 1)
    coupled = case.form.coupled()
    assert coupled.housing is not None
    chain, run = _by_hand()
    ref = _same_coupled_modes(case.form, coupled, chain, run)
    assert main(["modes", str(CASE), "--out", str(tmp_path)]) == 0
    written = json.loads((tmp_path / "modes.json").read_text())
    assert "torsional_chain" not in written
    np.testing.assert_allclose([r["frequency_Hz"] for r in written["coupled_with_housing"]],
                               np.asarray(ref.analysis.frequency), rtol=1e-10)


def test_a_pair_stage_bore_diameter_of_its_own(tmp_path):
    """``housing_bore_diameter_mm = 65`` on stage 2 of two-pair-housed.toml: the bores round
    its two shafts 65 mm (stage 1's the [housing]'s 70 mm); the file's coupled modes and
    housing energies are those of the gearbox built here on that box (1e-10, 1e-8), and the
    bores' size shows: its modes are not the 70 mm box's (by more than 1e-4)."""
    for f in DATA.glob("two-pair-*.toml"):
        (tmp_path / f.name).write_text(f.read_text())
    path = tmp_path / "bores.toml"
    path.write_text(CASE.read_text().replace(
        "housing_seats = [2, 6, 3, 7]", "housing_seats = [2, 6, 3, 7]\nhousing_bore_diameter_mm = 65.0"))
    case = jio.load_case(str(path))
    assert [s.housing_bore_diameter for s in case.form.stages] == [None, pytest.approx(0.065)]
    chain, run = _by_hand(0.065)
    ref = _same_coupled_modes(case.form, case.form.coupled(), chain, run)
    f50 = np.asarray(gb.gearbox_coupled_modes(_by_hand()[0], run).analysis.frequency)[:20]
    change = np.abs(np.asarray(ref.analysis.frequency)[:20] / f50 - 1).max()
    print("stage 2's bores 65 mm against 70 mm: max relative change of the 20 lowest coupled "
          "modes", change)
    assert change > 1e-4


def test_gearbox_housing_keys_errors_one_line(tmp_path):
    """The stage keys without a gearbox [housing] or on a torsional stage, seats of the wrong
    count or out of the box's 8, a position not of 3 finite numbers (mm), a [housing] without a
    lumped stage, a [housing] key out of range: one line each."""
    for f in DATA.glob("two-pair-*.toml"):
        (tmp_path / f.name).write_text(f.read_text())
    text = CASE.read_text()
    table = text[text.index("\n[housing]\n"):text.index("\n[whine]\n")]  # [housing] and its points
    no_housing = text.replace(table, "")
    torsional = (DATA / "two-pair-whine.toml").read_text()
    bad = {
        no_housing: r"\[stages\[1\]\] housing_position_mm = \[0(\.0)?, 150(\.0)?, 0(\.0)?\]: "
        r"allowed on a model = \"lumped3d\" or a planetary stage of a gearbox with "
        r"\[housing\] only",
        text.replace("housing_seats = [2, 6, 3, 7]", "housing_seats = [2, 6, 3]"): (
            r"\[stages\[1\]\] housing_seats = \[2, 6, 3\]: allowed 4 integers >= -1"),
        text.replace("housing_seats = [2, 6, 3, 7]", "housing_seats = [2, 6, 3, 8]"): (
            r"\[stages\[1\]\] housing_seats = \[2, 6, 3, 8\]: out of range, allowed -1..7"),
        text.replace("[0.0, 150.0, 0.0]", "[0.0, 150.0]"): (
            r"\[stages\[1\]\] housing_position_mm = \[0(\.0)?, 150(\.0)?\]: must be an array of "
            r"3 numbers"),
        text.replace("[0.0, 150.0, 0.0]", "[0.0, nan, 0.0]"): (
            r"\[stages\[1\]\] housing_position_mm = \[0(\.0)?, nan, 0(\.0)?\]: must be an array "
            r"of finite numbers"),
        text.replace("cutoff_Hz = 6000.0", "cutoff_Hz = -1.0"): r"\[housing\] cutoff_Hz = -1",
        torsional.replace("\n[whine]\n", table + "\n[whine]\n"): (
            r"\[housing\]: allowed with at least one model = \"lumped3d\" stage"),
    }
    assert_one_line_errors(bad, tmp_path)


def test_gearbox_box_refused_at_load_in_the_files_words(tmp_path):
    """two-pair-housed.toml's box (220 x 280 mm, 10 mm walls, 70 mm bores round 60 mm shafts;
    stage 1's axes at x = 0 and 96 mm, stage 2's 150 mm above at 0 and 99 mm) refused at load,
    naming the file's key: stage 2 5 m above (the axes' span 5000 mm + two walls + a bore:
    height_mm >= 5090 mm), stage 2 on stage 1's axes (its housing_position_mm), stage 2's own
    500 mm bores (limited by its two axes 99 mm apart: (60, 99] mm), a [housing] bore of 20 mm
    below the shafts (stage 1's axes 96 mm apart: (60, 96] mm), walls too thick for the default
    length (the span 120 mm + a wall), a length without room for two walls, the named point
    10 m away or in the cavity, a cut-off whose band (cut-off / 1.5) leaves out stage 1's
    mesh frequency at 30 rad/s, 24 x 30 / 2π = 114.6 Hz (allowed >= 171.9 Hz): one line each,
    before anything is meshed."""
    for f in DATA.glob("two-pair-*.toml"):
        (tmp_path / f.name).write_text(f.read_text())
    text = CASE.read_text()

    def swap(old, new):
        assert old in text
        return text.replace(old, new)

    f1 = 24 * 30.0 / (2 * math.pi)
    assert f"{f1:.4g}" == "114.6" and f"{1.5 * f1:.4g}" == "171.9"
    seats = "housing_seats = [2, 6, 3, 7]"
    bad = {
        swap("[0.0, 150.0, 0.0]", "[0.0, 5000.0, 0.0]"): (
            r"^\[housing\] height_mm = 280: the housed axes span 5000 mm along scene y \(stage "
            r"1's pinion shaft axis at 0 mm to stage 2's pinion shaft axis at 5000 mm\): allowed "
            r">= 5090 mm .*; or move \[stages\[1\]\] housing_position_mm$"),
        swap("[0.0, 150.0, 0.0]", "[0.0, 0.0, 0.0]"): (
            r"^\[stages\[1\]\] housing_position_mm = \[0, 0, 0\]: puts stage 2's pinion shaft "
            r"axis at \(0, 0\) mm, on stage 1's pinion shaft axis"),
        swap(seats, seats + "\nhousing_bore_diameter_mm = 500.0"): (
            r"^\[stages\[1\]\] housing_bore_diameter_mm = 500: the bore round stage 2's pinion "
            r"shaft axis at \(0, 150\) mm does not fit: allowed \(60, 99\] mm there \(two bores "
            r"of one diameter round stage 2's pinion shaft axis and stage 2's gear shaft axis, "
            r"99 mm apart\)$"),
        swap("bore_diameter_mm = 70.0", "bore_diameter_mm = 20.0"): (
            r"^\[housing\] bore_diameter_mm = 20: the bore round stage 1's pinion shaft axis "
            r"does not clear its 60 mm shaft: allowed \(60, 96\] mm$"),
        swap("wall_thickness_mm = 10.0", "wall_thickness_mm = 130.0"): (
            r"^\[housing\] wall_thickness_mm = 130: allowed < 120 mm \(the box's default "
            r"length, the bearings' span 120 mm \+ a wall"),
        swap("wall_thickness_mm = 10.0", "wall_thickness_mm = 10.0\nlength_mm = 10.0"): (
            r"^\[housing\] length_mm = 10: allowed > 20 mm"),
        swap("top = [50.0, 215.0, 0.0]", "top = [50.0, 10215.0, 0.0]"): (
            r"^\[housing\.points_mm\] top = \[50, 10215, 0\]: outside the housing, 1e\+04 mm "
            r"from its outer faces"),
        swap("top = [50.0, 215.0, 0.0]", "top = [50.0, 100.0, 0.0]"): (
            r"^\[housing\.points_mm\] top = \[50, 100, 0\]: in the housing's cavity"),
        swap("cutoff_Hz = 6000.0", "cutoff_Hz = 1.0"): (
            r"^\[housing\] cutoff_Hz = 1: the housing's band, cut-off / 1\.5 = 0\.6667 Hz, "
            r"leaves out stage 1's mesh frequency at \[operating\] speed_rad_s = 30, 114\.6 Hz "
            r".*: allowed >= 171\.9 Hz"),
        swap("cutoff_Hz = 6000.0", "highest_mesh_frequency_Hz = 100.0"): (
            r"^\[housing\] highest_mesh_frequency_Hz = 100: .*: allowed >= 114\.6 Hz$"),
    }
    assert_one_line_errors(bad, tmp_path)
    path = tmp_path / "edge.toml"  # the band's edge: 1.5 x 114.6 Hz loads
    path.write_text(swap("cutoff_Hz = 6000.0", f"cutoff_Hz = {1.5 * f1 * (1 + 1e-9)!r}"))
    assert jio.load_case(str(path)).housing.cutoff == pytest.approx(1.5 * f1)


@pytest.mark.slow  # the box's condensation, the torus grid with the housing's coordinates, twice:
# a few minutes on the loaded host; fast twins: the two tests above
def test_jaxgear_run_whine_of_the_housed_gearbox(tmp_path):
    """``jaxgear run``'s whine of the housed file (gearbox_whine_outputs) equals gearbox_whine
    on the hand-built housed gearbox within 1e-10 of the largest mesh force line, and writes the housing's files
    through the pair's writers (housing.json: the ERP per speed and order finite and
    non-negative, the named point ``top`` read at a skin node within a cell of it)."""
    case = jio.load_case(str(CASE))
    summary = gearbox_whine_outputs(case.form, case, str(tmp_path))
    folder = tmp_path / "whine"
    data = json.loads((folder / "whine.json").read_text())
    chain, run = _by_hand()
    w = gb.gearbox_whine(chain, run, [30.0, 80.0], QuasiPeriodicBalance(4, 1), positions=24)
    a = np.asarray(data["mesh_force_N"]["amplitude"])
    got = a * np.exp(1j * np.radians(np.asarray(data["mesh_force_N"]["phase_deg"])))
    ref = np.asarray(w.mesh_force)
    assert np.max(np.abs(got - ref)) < 1e-10 * np.max(np.abs(ref))
    assert "housing" in summary and (folder / "housing.json").is_file()
    housing = json.loads((folder / "housing.json").read_text())
    erp = np.asarray(housing["erp_W"])
    assert erp.shape == (2, len(data["orders"]) - 1) and np.all(np.isfinite(erp))
    assert np.all(erp >= 0.0)
    assert housing["points"]["top"]["moved_mm"] < 50.0  # a skin node within a cell (50 mm)


# -- a planetary stage's held ring in the gearbox's [housing] --------------------------------
# tests/data/gearbox/planetary-pair-housed.toml: examples/gearbox_two_stage.py's planetary
# stage (ring held, carrier in, sun out; the same stage as tests/data/gearbox/
# two-stage-gearbox-planetary.toml) whose sun drives the 41-tooth wheel of the lumped 25/41 pair
# (stage 2 of two-pair-housed.toml), its scene 150 mm above the planetary's axis; the ring on
# seat 0 (the -z wall's bore round the planetary's axis), the pair's bearings on the nearest.
PLANETARY_CASE = DATA / "planetary-pair-housed.toml"
P_TORQUE, P_SHAFT, RING_SEAT = 2000.0, 2e5, 0


def _planetary_box(ring_bore=0.07):
    """The box the file asks for, in numbers: 130 x 220 x 280 mm round the axes (0, 0) (the
    planetary's), (0, 150) and (99, 150) mm (the pair's pinion and gear shafts), its origin at
    scene (-60.5, -65, -65) mm; bores round the three axes, the -z wall's first: ``ring_bore``
    (m) round the planetary's, 70 mm round the pair's shafts."""
    axes = [(0.0, 0.0, ring_bore), (0.0, 0.15, 0.07), (0.099, 0.15, 0.07)]
    return _box_round(axes)


def _planar_supports(stage):
    """The example's stage with the in-plane supports of two-stage-gearbox-planetary-planar.toml
    (which the planar kind reads, the torsional one not): the carrier's and the ring's radial
    bearings and the planets' pins (radial, tangential), all 1000 N/µm; the sun floats."""
    for name in ("carrier", "ring", "planet"):
        stage = eqx.tree_at(lambda s, n=name: getattr(s, n).bearing_stiffness, stage,
                            jnp.array([1e9, 1e9]))
    return stage


def _planetary_by_hand(ch, off, kind=None, **run):
    """The file's gearbox built here: the example's planetary stage of ``kind`` (default the torsional one; the planar one on the stage with its in-plane
    supports) on a mount of the box (placed once, in the planetary's frame) with the ring on
    seat 0, the pair's lumped scene on the nearest seats of the same box at its place
    ``STAGE2``; ``ch``
    None: the same gearbox on the ground (the ring held by its torsional spring, the pair's
    bearings grounded)."""
    planetary = load_example("gearbox_two_stage").two_stage()[0].stages[0]
    kind = jp.TorsionalPlanetary() if kind is None else kind
    stage = (planetary.stage if isinstance(kind, jp.TorsionalPlanetary)
             else _planar_supports(planetary.stage))
    hp = None if ch is None else Housing.of(ch, loss_factor=0.02, rotation=R, offset=off)
    mount = None if ch is None else HousingMount.on_axis(hp, (("ring", RING_SEAT),))
    housed = gb.PlanetaryGearboxStage(stage, planetary.input, planetary.output,
                                      planetary.meshes, model=kind, mount=mount)
    lumped = lumped_pair_stage(TEETH[1], POLAR[1], input=1, housing=hp,
                               housing_position=None if ch is None else STAGE2)
    opts = {"mean_positions": COUPLED_RUN["mean_positions"]} | run
    return (gb.GearboxTorsional((housed, lumped), [P_SHAFT], housing=hp),
            gb.GearboxRun(P_TORQUE, P_SHAFT, **opts))


# default tier: tests/test_gearbox_case_housing.py::test_the_file_builds_the_hand_built_housed_gearbox (the same claim, the pairs in the box) and ::test_file_planetary_ring_seat_carries_the_ring_torque (this file's chain run)
@pytest.mark.slow
def test_the_file_builds_the_hand_built_planetary_in_the_box():
    """A planetary stage with ``housing_seat``: the reader's coupled chain (the ring on seat 0
    of the box round the planetary's axis and the pair's shafts, the pair's bearings on seats
    1, 2, 4, 5) has the hand-built chain's coordinates, coupled modes (1e-10) and housing
    energies (1e-8); ``jaxgear run``'s modes (chain_modes) are these, with the kinetic shares
    (stages + housing) summing to 1."""
    case = jio.load_case(str(PLANETARY_CASE))
    assert case.form.housed() == (0, 1)
    coupled = case.form.coupled()
    assert [s.housing_seats() for s in coupled.stages] == [(0,), (1, 2, 4, 5)]
    chain, run = _planetary_by_hand(*_planetary_box())
    _same_coupled_modes(case.form, coupled, chain, run)


@pytest.fixture(scope="module")
def planetary_file_run():
    """(case, its coupled chain, a Newmark run of it at a carrier speed of 2 rad/s:
    quasi-static, the planetary mesh at 25 Hz, the lowest mode at 257 Hz)."""
    case = jio.load_case(str(PLANETARY_CASE))
    chain = case.form.coupled()
    run = gb.GearboxRun(P_TORQUE, P_SHAFT, steps_per_period=16, periods=6, keep_periods=2)
    return case, chain, gb.gearbox_dynamics(chain, run, 2.0)


def test_file_planetary_ring_seat_carries_the_ring_torque(planetary_file_run):
    """A Newmark run (``gearbox_dynamics``) of the file's coupled chain at a carrier speed of
    2 rad/s (quasi-static: the planetary mesh at 25 Hz, the lowest mode at 257 Hz): over the
    recorded window the box's elastic moment at the ring's seat about the stage axis (K_h q at
    the seat's rotations, along R's last row) is the ring torque of the stage's torque balance,
    T_c r_br / (r_bs + r_br) (Willis), within 1e-3 (measured 2.2e-4: the window's residue),
    equal to the ring spring's k_t (θ_r − θ_seat); the seat's other force and moment components
    stay below 1e-3 of it; each mesh's mean force is its static force (1e-3)."""
    case, chain, out = planetary_file_run
    ch = case.form.housing_body.condensed
    assert int(out.result) == 0
    assert np.all(np.isfinite(np.asarray(out.displacement)))
    np.testing.assert_allclose(np.asarray(out.mesh_forces).mean(axis=0),
                               np.asarray(out.static_forces), rtol=1e-3)
    x = np.asarray(out.displacement).mean(axis=0)
    q = x[len(gb.coordinate_names(chain)) - ch.K.shape[0]:]
    seat = (np.asarray(ch.K) @ q)[6 * RING_SEAT:6 * RING_SEAT + 6]
    moment = float(R[2] @ seat[3:])
    st = chain.stages[0].stage
    r_s, r_r = float(st.sun.base_radius), float(st.ring.base_radius)
    expected = P_TORQUE * r_r / (r_s + r_r)
    names = gb.coordinate_names(chain)
    theta_seat = float(R[2] @ q[6 * RING_SEAT + 3:6 * RING_SEAT + 6])
    spring = float(st.ring.torsional_stiffness) * (x[names.index("1:theta_r")] - theta_seat)
    print("file's ring seat moment", moment, "ring spring", spring, "ring torque", expected,
          "relative", abs(abs(moment) / expected - 1))
    np.testing.assert_allclose(abs(moment), expected, rtol=1e-3)
    np.testing.assert_allclose(moment, spring, rtol=1e-3)
    rest = np.concatenate([seat[:3], seat[3:] - moment * R[2]])
    assert np.abs(rest).max() < 1e-3 * expected


def _skew(a):
    return np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])


def test_housing_signals_read_the_housed_file(planetary_file_run):
    """``housing_signals`` on the file's quasi-static run (the ring on its seat of the box, the
    pair in lumped 3D form, driven on its gear shaft: its output the pinion shaft):

    * the bearing signal is the pinion shaft's two bearings' in-plane force along its mean,
      written out here: K_b d, d = u − G q (u the bearing's shaft node, K_b its block of the
      scene's bearing stiffness, G = [[R, −S(p − c) R], [0, R]] the lever of its seat, the
      nearest: 1 and 4), to 1e-9 of the static mesh force; its mean is the pair's mean mesh
      force (the shaft's static balance) within 1e-3 (its fluctuation is not: the shaft's
      mass lies between the mesh and the bearings);
    * the ring's support reaction k_t (θ_r − θ_seat) / r_br is the ring meshes' summed force
      (the ring's static balance: mean within 1e-3); θ_r alone (the ring read as if grounded)
      would be far off, the seat turning under the 1e9 N m/rad spring's load."""
    case, chain, out = planetary_file_run
    sig = gb.housing_signals(chain, out, 2.0)
    f = np.asarray(out.mesh_forces)
    X = np.asarray(out.displacement)
    n = chain.stages[0].stage.n_planets
    static = float(np.mean(f[:, -1]))
    # the pinion shaft's bearings by hand (its first two bearing blocks, z = -60, +60 mm)
    body = case.form.housing_body
    ch, offset = body.condensed, body.offset - STAGE2  # the box in the pair's scene frame
    scene = chain.stages[1].scene
    o = len(chain.stages[0].coordinates()) - ch.K.shape[0]  # the pair's first coordinate
    q0 = X.shape[1] - ch.K.shape[0]
    part = np.asarray(scene.structure.stiffness_parts()["bearings"])
    blocks = [u for u in range(0, scene.structure.size - ch.K.shape[0], 6)
              if np.any(part[u:u + 6, u:u + 6] != 0)][:2]
    plane = np.zeros((X.shape[0], 2))
    for u, z, seat in zip(blocks, (-0.06, 0.06), (1, 4), strict=True):
        c = R @ np.asarray(ch.seat_positions[seat]) + offset
        G = np.zeros((6, 6))
        G[:3, :3] = G[3:, 3:] = R
        G[:3, 3:] = -_skew(np.array([0.0, 0.0, z]) - c) @ R
        d = X[:, o + u:o + u + 6] - X[:, q0 + 6 * seat:q0 + 6 * seat + 6] @ G.T
        plane += (d @ part[u:u + 6, u:u + 6].T)[:, :2]
    mean = plane.mean(axis=0)
    by_hand = plane @ (mean / np.linalg.norm(mean))
    bearing = np.asarray(sig.bearing)
    err_hand = float(np.max(np.abs(bearing - by_hand)) / static)
    err_mean = abs(float(np.mean(bearing)) / static - 1)
    ring = f[:, n:2 * n].sum(axis=1)
    err_r = abs(float(np.mean(sig.ring_support)) / float(np.mean(ring)) - 1)
    st = chain.stages[0].stage
    grounded = float(st.ring.torsional_stiffness) * float(np.mean(
        X[:, gb.coordinate_names(chain).index("1:theta_r")])) / float(st.ring.base_radius)
    print("lumped pair's bearing: vs by hand", err_hand, "; mean vs the mesh force", err_mean,
          "; ring support vs the ring meshes", err_r, "; theta_r alone",
          grounded / float(np.mean(ring)))
    assert err_hand < 1e-9 and err_mean < 1e-3 and err_r < 1e-3
    assert abs(abs(grounded) / float(np.mean(ring)) - 1) > 0.5


@pytest.mark.slow  # one Newmark run of the housed chain over two carrier revolutions: about a
# minute on the loaded host; fast twin: test_housing_signals_read_the_housed_file
def test_jaxgear_run_housing_spectrum_of_the_housed_file(tmp_path):
    """``jaxgear run``'s housing spectrum (housing_point_spectrum) on the housed planetary file:
    the ring mount of stage 1 and the lumped pair's bearing (stage 2) read from one run, every
    line finite; the bearing signal's mean (the spectrum's DC line) is the pair's static mesh
    force from the torque ratios, T_c / (1 + z_r/z_s) / r_b2 (the sun's torque on the 41-tooth
    wheel's base radius), within 1e-3."""
    from jaxgear.cli.gearbox import housing_point_spectrum

    case = jio.load_case(str(PLANETARY_CASE))
    summary = housing_point_spectrum(case.form, case, str(tmp_path))
    assert summary["ring_stage"] == 1 and summary["bearing_stage"] == 2
    data = json.loads((tmp_path / "housing_spectrum.json").read_text())
    assert data["result"] == 0
    assert all(math.isfinite(r["ring"]) and math.isfinite(r["bearing"]) for r in data["lines"])
    r_b2 = 0.5 * 41 * 3e-3 * math.cos(math.radians(20.0))
    static = P_TORQUE / (1 + 80 / 20) / r_b2
    dc = data["spectrum"]["bearing_N"][0]
    print("housed file's bearing DC", dc, "static mesh force", static)
    assert dc == pytest.approx(static, rel=1e-3)


def test_planetary_housing_seat_errors_one_line(tmp_path):
    """``housing_seat`` out of the box's 6 seats, on a seat the pair's bearings take (their
    nearest: 1, 2, 4, 5), negative, without a gearbox [housing], on a pair stage; a planetary
    stage's ``housing_position_mm`` without it: one line each, naming the key and value."""
    for name in ("two-stage-gearbox-planetary.toml", "two-pair-lumped-stage2.toml"):
        (tmp_path / name).write_text((DATA / name).read_text())
    text = PLANETARY_CASE.read_text()
    seat = "housing_seat = 0 "
    no_housing = text[:text.index("\n[housing]\n")]
    bad = {
        text.replace(seat, "housing_seat = 6 "): (
            r"\[stages\[0\]\] housing_seat = 6: out of range, allowed 0\.\.5"),
        text.replace(seat, "housing_seat = 4 "): (
            r"\[stages\[0\]\] housing_seat = 4: a seat a lumped stage's bearing takes"),
        text.replace(seat, "housing_seat = -1 "): (
            r"\[stages\[0\]\] housing_seat = -1: allowed an integer >= 0"),
        no_housing: (r"\[stages\[0\]\] housing_seat = 0: allowed on a model = \"lumped3d\" or "
                     r"a planetary stage of a gearbox with \[housing\] only"),
        text.replace(seat, 'housing_position_mm = [0.0, 0.0, 10.0] '): (
            r"\[stages\[0\]\] housing_position_mm = .*: allowed on a planetary stage with "
            r"housing_seat only"),
        text.replace('input = "gear"', 'input = "gear"\nhousing_seat = 5'): (
            r"\[stages\[1\]\] housing_seat = 5: allowed on a planetary stage only"),
    }
    assert_one_line_errors(bad, tmp_path)


# -- a planetary stage of the planar kind, its ring's bore of its own diameter ---------------
# tests/data/gearbox/planar-pair-housed.toml: planetary-pair-housed.toml with model = "planar"
# on the planetary stage (its case two-stage-gearbox-planetary-planar.toml: the same stage with
# radial bearings on carrier and ring) and housing_bore_diameter_mm = 75 on it (the ring's bore;
# the pair's shafts' bores the [housing]'s 70 mm).
PLANAR_CASE = DATA / "planar-pair-housed.toml"
RING_BORE = 0.075


@pytest.fixture(scope="module")
def planar_box():
    return _planetary_box(RING_BORE)


# default tier: tests/test_gearbox_case_housing.py::test_the_file_builds_the_hand_built_housed_gearbox (the same claim, the pairs in the box); the file's planetary in the box: ::test_file_planetary_ring_seat_carries_the_ring_torque; the planar kind on a mount: ::test_planar_ring_on_a_stiff_box_is_the_grounded_gearbox
@pytest.mark.slow
def test_the_file_builds_the_hand_built_planar_planetary_in_the_box(planar_box):
    """``model = "planar"`` and ``housing_bore_diameter_mm`` on a housed planetary stage: the
    reader's coupled chain (the planar kind on a mount of the box, the box with a 75 mm bore
    round the planetary's axis and 70 mm ones round the pair's shafts) has the coordinates,
    coupled modes (1e-10) and housing energies (1e-8) of the gearbox built here (the box in
    numbers, the example's stage with the file's in-plane supports, PlanarPlanetary() on
    a HousingMount), and ``jaxgear run``'s modes are these."""
    case = jio.load_case(str(PLANAR_CASE))
    assert case.form.stages[0].housing_bore_diameter == pytest.approx(RING_BORE)
    coupled = case.form.coupled()
    assert isinstance(coupled.stages[0].model, jp.PlanarPlanetary)
    assert coupled.stages[0].mount() is not None
    assert [s.housing_seats() for s in coupled.stages] == [(0,), (1, 2, 4, 5)]
    chain, run = _planetary_by_hand(*planar_box, kind=jp.PlanarPlanetary())
    ref = _same_coupled_modes(case.form, coupled, chain, run)
    print("planar planetary in the box: coupled modes", ref.analysis.frequency.size,
          "lowest", np.asarray(ref.analysis.frequency)[:4])


def test_planar_ring_on_a_stiff_box_is_the_grounded_gearbox(planar_box):
    """The file's box (75 mm ring bore) 1000 and 10 000 x stiffer (its condensed K scaled: the
    condensation of a box of that modulus and steel's density on the same modes): the coupled
    modes below 5 kHz of the planar planetary and the pair in it tend to those of the same
    gearbox on the ground (ring held by its torsional spring, the pair's bearings grounded),
    as the box's compliance: the difference falls about tenfold, within 2.5e-3 at x 10 000."""
    ch, off = planar_box
    grounded, run = _planetary_by_hand(None, off, kind=jp.PlanarPlanetary())
    f0 = np.asarray(gb.gearbox_coupled_modes(grounded, run).analysis.frequency)
    f0 = f0[f0 < 5000.0]
    errs = []
    for scale in (1e3, 1e4):
        stiff = dataclasses.replace(ch, K=np.asarray(ch.K) * scale,
                                    modes_hz=np.asarray(ch.modes_hz) * math.sqrt(scale))
        chain, _ = _planetary_by_hand(stiff, off, kind=jp.PlanarPlanetary())
        f = np.asarray(gb.gearbox_coupled_modes(chain, run).analysis.frequency)[:f0.size]
        errs.append(float(np.abs(f / f0 - 1).max()))
    print("planar ring on a stiff box: modes below 5 kHz", f0.size,
          "max relative difference at x 1000, x 10 000", errs)
    assert errs[0] / errs[1] > 8.0 and errs[1] < 2.5e-3


def test_a_planar_planetary_stage_on_the_ground(tmp_path):
    """``model = "planar"`` on a planetary stage of a gearbox without ``[housing]``
    (two-stage-gearbox.toml with its planetary stage case the planar one): the reader's coupled
    chain has the coupled modes of the example's gearbox (examples/gearbox_two_stage.py) with
    its planetary stage on PlanarPlanetary and the file's in-plane supports, to 1e-10."""
    for f in DATA.glob("two-stage-gearbox*.toml"):
        (tmp_path / f.name).write_text(f.read_text())
    path = tmp_path / "planar.toml"
    path.write_text((DATA / "two-stage-gearbox.toml").read_text().replace(
        'case = "two-stage-gearbox-planetary.toml"',
        'case = "two-stage-gearbox-planetary-planar.toml"\nmodel = "planar"'))
    coupled = jio.load_case(str(path)).form.coupled()
    assert coupled.housing is None and isinstance(coupled.stages[0].model, jp.PlanarPlanetary)
    example, run = load_example("gearbox_two_stage").two_stage()
    p = example.stages[0]
    planar = gb.PlanetaryGearboxStage(_planar_supports(p.stage), p.input, p.output, p.meshes,
                                      model=jp.PlanarPlanetary())
    chain = gb.GearboxTorsional((planar, example.stages[1]), example.shaft_stiffnesses)
    got, ref = (np.asarray(gb.gearbox_coupled_modes(c, run).analysis.frequency)
                for c in (coupled, chain))
    print("planar planetary stage on the ground: coupled modes", ref.size, "lowest", ref[:3])
    np.testing.assert_allclose(got, ref, rtol=1e-10)


def test_planetary_model_and_bore_diameter_errors_one_line(tmp_path):
    """A planetary stage's ``model`` not "torsional" or "planar"; ``housing_bore_diameter_mm``
    not positive, too large for its wall (the planetary's axis: 101 mm of room to the box's
    inner face), on a planetary stage without ``housing_seat``, with a mesh file's
    ``[housing]``; a gearbox ``bore_diameter_mm`` that does not fit; a bore the box's feet
    reach (when the box is meshed): one line each, naming the key and value."""
    for name in ("two-stage-gearbox-planetary-planar.toml", "two-pair-lumped-stage2.toml"):
        (tmp_path / name).write_text((DATA / name).read_text())
    text = PLANAR_CASE.read_text()
    bore = "housing_bore_diameter_mm = 75.0 "
    mesh_file = ('[housing]\nmesh_file = "box.msh"\ncutoff_Hz = 6000.0\n[[housing.seats]]\n'
                 "centre_mm = [0.0, 0.0, 0.0]\ndiameter_mm = 80.0\nwidth_mm = 10.0\n")
    bad = {
        text.replace('model = "planar" ', 'model = "spatial" '): (
            r"\[stages\[0\]\] model = .spatial.: .*torsional.*planar"),
        text.replace(bore, "housing_bore_diameter_mm = -5.0 "): (
            r"\[stages\[0\]\] housing_bore_diameter_mm = -5(\.0)?: out of range, allowed \(0, 100000\]"),
        text.replace(bore, "housing_bore_diameter_mm = 120.0 "): (
            r"\[stages\[0\]\] housing_bore_diameter_mm = 120(\.0)?: the bore round stage 1's "
            r"axis at \(0, 0\) mm does not fit: allowed \(0, 101\] mm there"),
        text.replace("housing_seat = 0 ", ""): (
            r"\[stages\[0\]\] housing_bore_diameter_mm = 75(\.0)?: allowed on a planetary "
            r"stage with housing_seat only"),
        text[:text.index("\n[housing]\n") + 1] + mesh_file: (
            r"\[stages\[0\]\] housing_bore_diameter_mm = 75(\.0)?: allowed with a box "
            r"\[housing\] only"),
        text.replace(bore, "").replace("bore_diameter_mm = 70.0", "bore_diameter_mm = 250.0"): (
            r"\[housing\] bore_diameter_mm = 250(\.0)?: the bore round stage 2's pinion shaft "
            r"axis at \(0, 150\) mm does not fit: allowed \(60, 99\] mm there \(two bores of "
            r"one diameter round stage 2's pinion shaft axis and stage 2's gear shaft axis, 99 mm "
            r"apart\)"),
    }
    assert_one_line_errors(bad, tmp_path)
    path = tmp_path / "box.toml"  # 90 mm: within the wall, but its seat reaches a foot
    path.write_text(text.replace(bore, "housing_bore_diameter_mm = 90.0 "))
    with pytest.raises(SchemaError, match=r"\[housing\]: seat seat0: its bore touches a foot"
                       ) as err:
        jio.load_case(str(path)).form.coupled()
    assert "\n" not in str(err.value)
