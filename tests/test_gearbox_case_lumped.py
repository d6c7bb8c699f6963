"""A gearbox case file's lumped 3D pair stage (``[[stages]] model = "lumped3d"``: the stage case's
``[scene]`` as a jaxgear.gearbox.LumpedPairGearboxStage; docs/gearbox.md).
tests/data/gearbox/two-pair-lumped.toml is tests/data/gearbox/two-pair-whine.toml with its second
pair on 60 mm shafts and bearings.

References, apart from the code under test: the same gearbox built by hand in Python
(jaxgear.scenes.lumped_pair of the shafts, bearings and gear bodies the file states, the gear
bodies' diametral inertia of a disc I_p/2 + m b²/12 as the case-file reference gives it): the
same coupled modes and chain modes (a check of the reader); Newmark on it for the whine (slow).
"""

import json
import math
import pathlib

import numpy as np
import pytest
from _toml import assert_one_line_errors
from test_gearbox_case_whine import assert_order1_as_newmark, whine_lines
from test_gearbox_whine import TEETH, B, _stage

import jaxgear as jg
import jaxgear.io as jio
from fem_prep.schema import SchemaError
from jaxgear import gearbox as gb
from jaxgear.cli.gearbox import COUPLED_RUN, gearbox_whine_outputs
from jaxgear.dynamics import QuasiPeriodicBalance
from jaxgear.scenes import Bearing, ShaftSpec, lumped_pair

DATA = pathlib.Path(__file__).parent / "data" / "gearbox"
CASE = DATA / "two-pair-lumped.toml"
TORQUE, SHAFT = 200.0, 2e5
MASSES = (1.5, 2.5)
POLAR = (0.0007315362629828136, 0.005291895403577801)  # the file's pinion and gear, kg m^2
TOL_ORDER1 = 0.015  # measured 0.77 % (and 0.66 deg) at H = 4, 24 positions


def lumped_pair_stage(teeth, polar, *, input=0, housing=None, seats=None,
                      housing_position=None):
    """The pair ``teeth`` (tests/test_gearbox_whine.py's, 10 µm tip relief) as the gearbox files'
    lumped 3D stage, built by hand: its two 120 mm, 60 mm steel shafts (2 elements), bearings of
    2e8 N/m radial at both ends and 1e8 N/m axial at the first, the pinion shaft driven at z = 0,
    the gear shaft's output at its end; ``polar``: the pinion's and the gear's polar moments
    (kg m^2, the file's); ``input``: the member driven; ``housing``/``seats``/
    ``housing_position``: the bearings' seats and the scene's place in the housing's frame
    (:func:`jaxgear.scenes.lumped_pair`)."""
    s, mesh = _stage(*teeth, 10e-6)
    pair = jg.GearPair(jg.Member(teeth[0], face_width=B), jg.Member(teeth[1], face_width=B),
                       3e-3, math.radians(20.0))

    def shaft(torque_z):
        return ShaftSpec(0.12, 0.06, 0.06, (Bearing(0.0, 2e8, 1e8, 0.0),
                                            Bearing(0.12, 2e8, 0.0, 0.0)),
                         torque_z=torque_z, elements=2)

    inertias = tuple((ip / 2 + m * B * B / 12, ip) for ip, m in zip(polar, MASSES, strict=True))
    scene = lumped_pair(pair, mesh, shaft(0.0), shaft(0.12), masses=MASSES, inertias=inertias,
                        housing=housing, seats=seats, housing_position=housing_position)
    return gb.LumpedPairGearboxStage(scene, input=input, modifications=s.modifications)


def _by_hand(**run):
    """Stage 1 torsional (tests/test_gearbox_whine.py's), stage 2 the 25/41 pair as the lumped
    stage of :func:`lumped_pair_stage`."""
    s1 = _stage(*TEETH[0], 10e-6)[0]
    lumped = lumped_pair_stage(TEETH[1], POLAR)
    return (gb.GearboxTorsional((s1, lumped), [SHAFT]),
            gb.GearboxRun(TORQUE, SHAFT, mean_positions=COUPLED_RUN["mean_positions"], **run))


def test_the_file_builds_the_hand_built_lumped_stage():
    """The coupled chain the reader builds has the hand-built one's coupled modes, and its
    torsional chain (the lumped stage condensed on its torque nodes) the hand-built chain's
    modes, both to 1e-10; stage 2 is a LumpedPairGearboxStage driven on its pinion shaft."""
    case = jio.load_case(str(CASE))
    coupled = case.form.coupled()
    assert isinstance(coupled.stages[1], gb.LumpedPairGearboxStage)
    assert coupled.stages[1].input == 0
    chain, run = _by_hand()
    got = np.asarray(gb.gearbox_coupled_modes(coupled, run).analysis.frequency)
    ref = np.asarray(gb.gearbox_coupled_modes(chain, run).analysis.frequency)
    np.testing.assert_allclose(got, ref, rtol=1e-10)
    got = np.asarray(gb.gearbox_modes(case.form.torsional()).frequencies)[1:]
    ref = np.asarray(gb.gearbox_modes(chain).frequencies)[1:]
    np.testing.assert_allclose(got, ref, rtol=1e-10)


def test_lumped_stage_keys_errors_one_line(tmp_path):
    """``model`` out of its names, ``"lumped3d"`` with a torsional key, ``"lumped3d"`` on a
    stage case without a lumped 3D [scene], ``model`` on a planetary stage: one line naming
    the key, its value and what is allowed."""
    for f in DATA.glob("two-pair-*.toml"):
        (tmp_path / f.name).write_text(f.read_text())
    text = CASE.read_text()
    bad = {
        text.replace('model = "lumped3d"', 'model = "flexible"'): (
            r"\[stages\[1\]\] model = 'flexible'.*torsional.*lumped3d"),
        text.replace('model = "lumped3d"', 'model = "lumped3d"\ngear_inertia_kg_m2 = 1.0'): (
            r"\[stages\[1\]\] gear_inertia_kg_m2 = 1(\.0)?: only for model = \"torsional\""),
        text.replace("two-pair-lumped-stage2.toml", "two-pair-whine-stage2.toml"): (
            r"\[stages\[1\]\] model = 'lumped3d': allowed with a stage case whose \[scene\] has "
            r"model = \"lumped3d\".*no \[scene\]"),
    }
    assert_one_line_errors(bad, tmp_path)
    planetary = (DATA / "two-stage-gearbox.toml").read_text().replace(
        'case = "two-stage-gearbox-planetary.toml"',
        'case = "two-stage-gearbox-planetary.toml"\nmodel = "lumped3d"')
    for f in DATA.glob("two-stage-gearbox-*.toml"):
        (tmp_path / f.name).write_text(f.read_text())
    path = tmp_path / "planetary.toml"
    path.write_text(planetary)
    with pytest.raises(SchemaError, match=r"\[stages\[0\]\] model = 'lumped3d': only for a pair"):
        jio.load_case(str(path))


@pytest.mark.slow  # the torus grid's solves and their compilation, twice, and Newmark: about a
# minute on the loaded host; fast twins: the two tests above
def test_jaxgear_run_whine_of_the_lumped_stage_gearbox(tmp_path):
    """``jaxgear run``'s whine of the file (gearbox_whine_outputs) equals gearbox_whine on the
    hand-built gearbox within 1e-10 of the largest line, and each mesh's order 1 is within
    TOL_ORDER1 and 1.5° of Newmark on it (160 steps per first-mesh period, 40 blocks of the second
    mesh's period, the last 5: whole periods of both) at 30 and 80 rad/s (H = 4, 24
    positions)."""
    case = jio.load_case(str(CASE))
    gearbox_whine_outputs(case.form, case, str(tmp_path))
    data = json.loads((tmp_path / "whine" / "whine.json").read_text())
    chain, run = _by_hand(steps_per_period=160, periods=40, keep_periods=5)
    w = gb.gearbox_whine(chain, run, [30.0, 80.0], QuasiPeriodicBalance(4, 1), positions=24)
    got, ref = whine_lines(data, "mesh_force_N"), np.asarray(w.mesh_force)
    assert np.max(np.abs(got - ref)) < 1e-10 * np.max(np.abs(ref))
    assert_order1_as_newmark(data, chain, run, (30.0, 80.0), TOL_ORDER1)

