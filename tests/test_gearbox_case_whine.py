"""A gearbox case file's ``[whine]`` (jaxgear.io.GearboxForm.whine) and ``jaxgear run`` writing
the coupled gearbox's whine (jaxgear.cli.gearbox.gearbox_whine_outputs; docs/whine.md, "A
gearbox"). tests/data/gearbox/two-pair-whine.toml writes tests/test_gearbox_whine.py's two
relieved spur pairs as case files.

References, each apart from the code under test:

* the model built by hand in Python (tests/test_gearbox_whine.py's stages, the shaft and output
  hold of the file, the run's mean positions as ``jaxgear run``'s): the same coupled modes and
  the same whine lines (a check of the reader and of the writers' round trip);
* each mesh's static force from the torque ratios, worked out here from the teeth;
* the coupled model's own time integration (``gearbox_dynamics``, Newmark with unilateral
  contact), its mesh forces Fourier analysed at each stage's mesh frequency (slow).
"""

import json
import math
import pathlib

import numpy as np
import pytest
from test_gearbox_whine import TEETH, _stage

import jaxgear.io as jio
from fem_prep.schema import SchemaError
from jaxgear import gearbox as gb
from jaxgear.cli import main
from jaxgear.cli.gearbox import COUPLED_RUN, gearbox_whine_outputs
from jaxgear.dynamics import QuasiPeriodicBalance

DATA = pathlib.Path(__file__).parent / "data" / "gearbox"
CASE = DATA / "two-pair-whine.toml"
TORQUE, SHAFT = 200.0, 2e5  # the file's input torque (N m) and shaft (= the output hold)
MODULE, ALPHA = 3e-3, math.radians(20.0)


def _by_hand(**run):
    """The file's gearbox built in Python: the pairs of tests/test_gearbox_whine.py (24/40,
    25/41, tip relief 10 µm over 0.3), the shaft, the output hold the last shaft's stiffness,
    the modal damping's mean over jaxgear run's positions."""
    stages = tuple(_stage(*t, 10e-6)[0] for t in TEETH)
    chain = gb.GearboxTorsional(stages, [SHAFT])
    return chain, gb.GearboxRun(TORQUE, SHAFT, mean_positions=COUPLED_RUN["mean_positions"],
                                **run)


def test_whine_table_parses_and_the_chain_is_the_hand_built_one():
    """The file's [whine] as the pair's table (speeds of stage 1's input, H, S, positions),
    the method quasi-periodic; the coupled chain the reader builds has the hand-built chain's
    coupled modes to 1e-10."""
    case = jio.load_case(str(CASE))
    w = case.form.whine
    assert w.speeds == [30.0, 80.0] and w.positions == 24
    assert isinstance(w.method, QuasiPeriodicBalance)
    assert (w.method.harmonics, w.method.sidebands) == (4, 1)
    chain, run = _by_hand()
    got = np.asarray(gb.gearbox_coupled_modes(case.form.coupled(), run).analysis.frequency)
    ref = np.asarray(gb.gearbox_coupled_modes(chain, run).analysis.frequency)
    np.testing.assert_allclose(got, ref, rtol=1e-10)


def test_the_whine_size_before_work_is_the_gearboxs():
    """``jaxgear run``'s size check before work (:func:`jaxgear.io.check_case_whine`, printed
    beside the housing's) takes a gearbox's size from its stages: its torus grid is the
    positions per period to the power of its two stages' mesh-frequency groups, 24² = 576
    static points, at its 2 speeds. (It used to read the case's pair-form mesh orders and
    stop ``jaxgear run`` with "zip() argument 2 is shorter than argument 1".)"""
    size = jio.check_case_whine(jio.load_case(str(CASE)))
    assert (size.speeds, size.static_points) == (2, 24 * 24)


def _with(text, tmp_path):
    for f in DATA.glob("two-pair-whine-stage*.toml"):
        (tmp_path / f.name).write_text(f.read_text())
    path = tmp_path / "box.toml"
    path.write_text(text)
    return str(path)


def test_whine_table_defaults_and_errors_one_line(tmp_path):
    """Without ``method`` a gearbox's [whine] is quasi-periodic; positions_per_period as a list
    is one per stage; a single-frequency method, a torus grid beyond 1e6 static solves, a list
    of another length or an entry below 4H + 1, the pair table's own range errors and an unknown key:
    one line naming the key, its value and the allowed range."""
    text = CASE.read_text()
    plain = text.replace('method = "quasi-periodic"\n', "").replace("sidebands = 1\n", "")
    w = jio.load_case(_with(plain, tmp_path)).form.whine
    assert isinstance(w.method, QuasiPeriodicBalance) and w.method.sidebands == 1
    per_stage = text.replace("positions_per_period = 24", "positions_per_period = [24, 20]")
    assert jio.load_case(_with(per_stage, tmp_path)).form.whine.positions == (24, 20)
    bad = {
        text.replace('"quasi-periodic"', '"harmonic-balance"').replace("sidebands = 1\n", ""): (
            r"\[whine\] method = 'harmonic-balance': allowed \"quasi-periodic\" in a gearbox"),
        text.replace("positions_per_period = 24", "positions_per_period = 2000"): (
            r"\[whine\] positions_per_period = 2000: out of range for 2 stages: allowed "
            r"\[17, 1000\]"),
        text.replace("positions_per_period = 24", "positions_per_period = 12"): (
            r"positions_per_period = 12: out of range, allowed >= 4 harmonics \+ 1 = 17"),
        text.replace("positions_per_period = 24", "positions_per_period = [24]"): (
            r"\[whine\] positions_per_period = \[24\]: allowed one integer, or a list of 2 "
            r"\(one per stage\)"),
        text.replace("positions_per_period = 24", "positions_per_period = [24, 12]"): (
            r"positions_per_period = \[24, 12\]: out of range, allowed >= 4 harmonics \+ 1 = "
            r"17 per stage's mesh period"),
        text.replace("positions_per_period = 24", "positions_per_period = [2000, 1000]"): (
            r"positions_per_period = \[2000, 1000\]: out of range: 2000000 static solves"),
        text.replace("speeds = 2", "speeds = 1"): r"\[whine\] speeds = 1",
        text.replace("speeds = 2", "speedz = 2"): r"unknown key 'speedz'",
    }
    for t, needle in bad.items():
        with pytest.raises(SchemaError, match=needle) as err:
            jio.load_case(_with(t, tmp_path))
        assert "\n" not in str(err.value)


def whine_lines(section, key):
    """The complex lines of ``whine.json``'s ``key`` (amplitude at its phase)."""
    a = np.asarray(section[key]["amplitude"])
    return a * np.exp(1j * np.radians(np.asarray(section[key]["phase_deg"])))


def assert_order1_as_newmark(data, chain, run, speeds, tol):
    """Each mesh's order 1 of ``whine.json`` (``data``) at each of ``speeds`` is the mesh
    force's Fourier coefficient at that frequency over the kept periods of a Newmark run
    (``gearbox_dynamics`` of ``chain``, ``run``) within ``tol`` in amplitude and 1.5°."""
    fm = whine_lines(data, "mesh_force_N")
    g, o = np.asarray(data["order_group"]), np.asarray(data["group_order"])
    for i, speed in enumerate(speeds):
        r = gb.gearbox_dynamics(chain, run, speed)
        assert int(r.result) == 0
        t, f = np.asarray(r.time), np.asarray(r.mesh_forces)
        for mesh in (0, 1):
            j = int(np.flatnonzero((g == mesh) & (o == 1))[0])
            nu = 2 * math.pi * data["fundamental_Hz"][i] * data["orders"][j]
            ref = 2 * np.mean(f[:, mesh] * np.exp(-1j * nu * t))
            got = fm[i, j, mesh]
            assert abs(abs(got) / abs(ref) - 1) < tol, (speed, mesh, got, ref)
            assert abs(math.degrees(np.angle(got / ref))) < 1.5, (speed, mesh)


@pytest.mark.slow  # the torus grid's static solves and their compilation, twice, and Newmark:
# about a minute on the loaded 2-core host; fast twins: the two tests above
def test_jaxgear_run_writes_the_gearbox_whine(tmp_path):
    """``jaxgear run``'s whine section of the file (gearbox_whine_outputs: the coupled chain's
    gearbox_whine through the pair's writers) against (1) gearbox_whine on the hand-built
    model: every mesh force and TE line within 1e-10 of the largest; (2) the static forces
    from the torque ratios (stage 1: T / r_b1; stage 2: T z_2/z_1 / r_b1'); (3) Newmark (160
    steps per first-mesh period, 40 blocks of the second mesh's period, the last 5 kept: whole
    periods of both meshes) at both speeds: each mesh's order 1 within 1.5 % and 1.5° (H = 4,
    24 positions; measured 0.76 % and 0.66°)."""
    case = jio.load_case(str(CASE))
    summary = gearbox_whine_outputs(case.form, case, str(tmp_path))
    folder = tmp_path / "whine"
    assert {"whine.json", "whine.csv", "te_orders.png", "te_waterfall.png",
            "te_orders_stage1_pair.png", "te_orders_stage2_pair.png"} <= {
                p.name for p in folder.iterdir()}
    assert summary["speeds"] == 2 and summary["validity"] == "no contact loss over the range"
    data = json.loads((folder / "whine.json").read_text())
    assert data["meshes"] == ["stage1_pair", "stage2_pair"] and data["mesh_group"] == [0, 1]
    chain, run = _by_hand(steps_per_period=160, periods=40, keep_periods=5)
    w = gb.gearbox_whine(chain, run, [30.0, 80.0], QuasiPeriodicBalance(4, 1), positions=24)
    for key, ref in (("mesh_force_N", w.mesh_force), ("transmission_error_m",
                                                      w.transmission_error)):
        got, ref = whine_lines(data, key), np.asarray(ref)
        assert np.max(np.abs(got - ref)) < 1e-10 * np.max(np.abs(ref)), key
    np.testing.assert_allclose(data["orders"], np.asarray(w.orders), rtol=1e-12)
    rb = [0.5 * MODULE * z * math.cos(ALPHA) for z in (TEETH[0][0], TEETH[1][0])]
    np.testing.assert_allclose(data["static_force_N"], [TORQUE / rb[0],
                                                        TORQUE * TEETH[0][1] / TEETH[0][0]
                                                        / rb[1]], rtol=1e-9)
    for i, speed in enumerate((30.0, 80.0)):
        np.testing.assert_allclose(data["fundamental_Hz"][i], TEETH[0][0] * speed / (2 * math.pi),
                                   rtol=1e-12)
    assert_order1_as_newmark(data, chain, run, (30.0, 80.0), 0.015)


@pytest.mark.slow  # the whole command: each stage's own run, the chain's modes, the coupled
# sweep and the whine (minutes on the loaded host); fast twins: the tests above
def test_jaxgear_run_on_the_gearbox_case_prints_and_writes_the_whine(tmp_path, capsys):
    out = tmp_path / "run"
    assert main(["run", str(CASE), "--out", str(out), "--quiet"]) == 0
    printed = capsys.readouterr().out
    assert "whine (QuasiPeriodicBalance, H = 4, 2 speeds 30-80 rad/s)" in printed
    summary = json.loads((out / "summary.json").read_text())
    assert summary["complete"] is True and summary["whine"]["speeds"] == 2
    assert (out / "whine" / "whine.json").is_file() and (out / "coupled.json").is_file()
