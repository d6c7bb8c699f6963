"""A gearbox-level ``[housing]`` in a gearbox case file (jaxgear.io.GearboxForm.housing): one box
shared by its lumped 3D pair stages (``model = "lumped3d"``), each stage placed by
``housing_position_mm`` and seated by ``housing_seats`` (docs/gearbox.md, "One housing for
several stages"). tests/data/gearbox/two-pair-housed.toml: tests/data/gearbox/two-pair-whine.toml's
pairs on 60 mm shafts, stage 2's scene 150 mm above stage 1's, in one steel box.

Reference, apart from the code under test: the same gearbox built by hand in Python: the box of
the housing table's rules written out here in numbers (its length the bearings' span plus a
wall, 130 mm; centred on the four axes across; a 50 mm bore round each axis in both end walls;
30 mm square feet), meshed and condensed by fem_prep, placed in each stage's scene frame with
jaxgear.scenes.Housing.of, the stages' lumped_pair scenes on it and the chain's shared housing:
the same coupled modes and housing energy (a check of the reader).
"""

import json
import math
import pathlib

import numpy as np
import pytest
from test_gearbox_whine import TEETH, B, _stage

import fem_prep
import jaxgear as jg
import jaxgear.io as jio
from fem_prep.housing import Bore, Foot, HousingBox, Tet4, condensed_housing, mesh_box
from fem_prep.schema import SchemaError
from jaxgear import gearbox as gb
from jaxgear.cli.gearbox import COUPLED_RUN, chain_modes, gearbox_whine_outputs
from jaxgear.dynamics import QuasiPeriodicBalance
from jaxgear.scenes import Bearing, Housing, ShaftSpec, lumped_pair

DATA = pathlib.Path(__file__).parent / "data" / "gearbox"
CASE = DATA / "two-pair-housed.toml"
TORQUE, SHAFT = 200.0, 2e5
MASSES = (1.5, 2.5)
POLAR = ((0.0006213278084797084, 0.004794196053084167),
         (0.0007315362629828136, 0.005291895403577801))
# the housing frame -> the scene frame: housing x (length) along scene z, y along scene x, z
# along scene y (docs/housing.md)
R = np.array([[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]])
STAGE2 = np.array([0.0, 0.15, 0.0])  # stage 2's scene origin in stage 1's frame (m)


def _box():
    """The box the file asks for, in numbers: 130 x 220 x 280 mm (length: the bearings' span
    120 mm + the 10 mm wall), centred across on the axes (x 0..99 mm, y 0..150 mm: the box's
    origin at scene (-60.5, -65, -65) mm); bores of 50 mm round the four axes, the -z wall's
    first (seats 0-3: stage 1's pinion and gear shafts, then stage 2's), then the +z wall's."""
    off = np.array([-0.0605, -0.065, -0.065])
    axes = [(0.0, 0.0), (0.096, 0.0), (0.0, 0.15), (0.099, 0.15)]
    bores = tuple(Bore(w, (x - off[0], y - off[1]), 0.025) for w in ("x-", "x+") for x, y in axes)
    feet = tuple(Foot(xr, yr) for xr in ((0.0, 0.03), (0.1, 0.13))
                 for yr in ((0.0, 0.03), (0.19, 0.22)))
    box = HousingBox(0.13, 0.22, 0.28, 0.01, bores=bores, feet=feet)
    mesh = mesh_box(box, 0.05, layers=1, element=Tet4())
    return condensed_housing(mesh, fem_prep.Material(210e9, 0.3, 7800.0), 6000.0,
                             coupling=fem_prep.Rigid()), off


def _by_hand(**run):
    ch, off = _box()
    stages, shared = [], None
    for k, seats in ((0, None), (1, (2, 6, 3, 7))):
        s, mesh = _stage(*TEETH[k], 10e-6)
        z1, z2 = TEETH[k]
        pair = jg.GearPair(jg.Member(z1, face_width=B), jg.Member(z2, face_width=B), 3e-3,
                           math.radians(20.0))

        def shaft(torque_z):
            return ShaftSpec(0.12, 0.06, 0.06, (Bearing(0.0, 2e8, 1e8, 0.0),
                                                Bearing(0.12, 2e8, 0.0, 0.0)),
                             torque_z=torque_z, elements=2)

        inertias = tuple((ip / 2 + m * B * B / 12, ip) for ip, m in zip(POLAR[k], MASSES,
                                                                        strict=True))
        h = Housing.of(ch, loss_factor=0.02, rotation=R, offset=off - (STAGE2 if k else 0.0))
        shared = h if shared is None else shared
        scene = lumped_pair(pair, mesh, shaft(0.0), shaft(0.12), masses=MASSES,
                            inertias=inertias, housing=h, seats=seats)
        stages.append(gb.LumpedPairGearboxStage(scene, input=0, modifications=s.modifications))
    return (gb.GearboxTorsional(tuple(stages), [SHAFT], housing=shared),
            gb.GearboxRun(TORQUE, SHAFT, mean_positions=COUPLED_RUN["mean_positions"], **run))


def test_the_file_builds_the_hand_built_housed_gearbox():
    """The reader's coupled chain (both stages in the one box, its coordinates once) has the
    hand-built chain's coupled modes to 1e-10 and housing energies to 1e-8; ``jaxgear run``'s
    modes (chain_modes) are these, each with the stages' and the housing's kinetic shares
    summing to 1."""
    case = jio.load_case(str(CASE))
    assert case.form.housed() == (0, 1)
    coupled = case.form.coupled()
    assert coupled.housing is not None
    chain, run = _by_hand()
    assert gb.coordinate_names(coupled) == gb.coordinate_names(chain)
    got, ref = (gb.gearbox_coupled_modes(c, run) for c in (coupled, chain))
    np.testing.assert_allclose(np.asarray(got.analysis.frequency),
                               np.asarray(ref.analysis.frequency), rtol=1e-10)
    np.testing.assert_allclose(np.asarray(got.housing_energy), np.asarray(ref.housing_energy),
                               atol=1e-8)
    rows = chain_modes(case.form)
    np.testing.assert_allclose([r["frequency_Hz"] for r in rows],
                               np.asarray(ref.analysis.frequency), rtol=1e-10)
    for r in rows:
        assert sum(r["stage_energy"]) + r["housing_energy"] == pytest.approx(1.0, abs=1e-9)


def test_gearbox_housing_keys_errors_one_line(tmp_path):
    """The stage keys without a gearbox [housing] or on a torsional stage, seats of the wrong
    count or out of the box's 8, a position not of 3 numbers, a [housing] without a lumped
    stage, a [housing] key out of range: one line each."""
    for f in DATA.glob("two-pair-*.toml"):
        (tmp_path / f.name).write_text(f.read_text())
    text = CASE.read_text()
    table = text[text.index("\n[housing]\n"):text.index("\n[whine]\n")]  # [housing] and its points
    no_housing = text.replace(table, "")
    torsional = (DATA / "two-pair-whine.toml").read_text()
    bad = {
        no_housing: r"\[stages\[1\]\] housing_position_mm = \[0(\.0)?, 150(\.0)?, 0(\.0)?\]: "
        r"allowed on a model = \"lumped3d\" stage of a gearbox with \[housing\] only",
        text.replace("housing_seats = [2, 6, 3, 7]", "housing_seats = [2, 6, 3]"): (
            r"\[stages\[1\]\] housing_seats = \[2, 6, 3\]: allowed 4 integers >= -1"),
        text.replace("housing_seats = [2, 6, 3, 7]", "housing_seats = [2, 6, 3, 8]"): (
            r"\[stages\[1\]\] housing_seats = \[2, 6, 3, 8\]: out of range, allowed -1..7"),
        text.replace("[0.0, 150.0, 0.0]", "[0.0, 150.0]"): (
            r"\[stages\[1\]\] housing_position_mm = \[0(\.0)?, 150(\.0)?\]: must be an array of "
            r"3 numbers"),
        text.replace("cutoff_Hz = 6000.0", "cutoff_Hz = -1.0"): r"\[housing\] cutoff_Hz = -1",
        torsional.replace("\n[whine]\n", table + "\n[whine]\n"): (
            r"\[housing\]: allowed with at least one model = \"lumped3d\" stage"),
    }
    for t, needle in bad.items():
        path = tmp_path / "box.toml"
        path.write_text(t)
        with pytest.raises(SchemaError, match=needle) as err:
            jio.load_case(str(path))
        assert "\n" not in str(err.value)


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
