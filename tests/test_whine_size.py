"""A whine's size before work (docs/whine.md, "Size before work"): the balance's harmonics
counted against the enumerated harmonic set, a grid beyond the work limit refused by
``whine_response`` before its static solves, the method a model kind declares, and a case
file's ``[whine]`` checked at load (its size, its positions groups, its method for the case's
model kind), each in one line before any work (the work replaced by a function that fails the
test if it is reached)."""

import numpy as np
import pytest

import jaxgear.dynamics._whine as whine_module
import jaxgear.io as jio
from jaxgear import Uniform
from jaxgear.cli import main
from jaxgear.dynamics import (
    HarmonicBalance,
    QuasiPeriodicBalance,
    TransmissionErrorSource,
    balance_harmonics,
    dynamic_model,
    harmonic_set,
    whine_response,
    whine_size,
)
from jaxgear.io import SchemaError
from jaxgear.planetary import PlanetaryModel
from jaxgear.scenes import TorsionalDynamics, disc_inertia


def _fail(*args, **kwargs):
    raise AssertionError("the work started: the refusal must come before it")


@pytest.mark.parametrize("G", [1, 2, 3])
def test_the_balance_harmonics_count_the_enumerated_set(G):
    for H in range(1, 5):
        for S in range(H + 1):
            assert balance_harmonics(QuasiPeriodicBalance(H, S), G) == len(harmonic_set(G, H, S))
        assert balance_harmonics(HarmonicBalance(H)) == len(harmonic_set(1, H, H)) == 2 * H + 1


def test_the_size_of_a_torsional_pair_by_hand():
    """Two coordinates, H = 8: the balance couples 17 harmonics x 2 = 34 unknowns; 36 speeds
    of (34³ + 9 × 2³) work; the time-invariant method solves each of its 9 harmonics alone."""
    s = whine_size(36, HarmonicBalance(8), 64, 2, 12)
    assert (s.harmonics, s.unknowns, s.static_points) == (17, 34, 64)
    assert s.work == 36 * (34**3 + 9 * 2**3)
    t = whine_size(36, TransmissionErrorSource(8), 64, 2, 12)
    assert (t.unknowns, t.work) == (2, 36 * 9 * 2**3)


def _torsional_pair():
    case = jio.load_case("accessory-spur").replace(slices=4, stiffness=Uniform(14e9))
    p = case.pair
    i1 = disc_inertia(case.density, p.tip_radii[0], p.pinion.face_width)
    i2 = disc_inertia(case.density, p.tip_radii[1], p.gear.face_width)
    return dynamic_model(TorsionalDynamics(case.mesh_model(), i1, i2), case.modifications,
                         case.torque)


def test_whine_response_refuses_a_grid_beyond_the_work_limit_before_its_static_solves(
        monkeypatch):
    """2 000 speeds x 256 harmonics x 8 192 positions (each in its range) on a torsional pair:
    a balance of 513 x 2 unknowns per speed, 2.2e12 work over 1e12."""
    monkeypatch.setattr(whine_module, "_prep", _fail)
    with pytest.raises(ValueError, match=r"^len\(speeds\) = 2000, method.harmonics = 256: out "
                       r"of range: 2000 speeds x a balance of 1026 unknowns \(513 harmonics\) is "
                       r"about 2.16e\+12 work .* allowed <= 1e\+12 .*: fewer speeds or "
                       r"harmonics$") as err:
        whine_response(_torsional_pair(), np.linspace(10.0, 1000.0, 2000), HarmonicBalance(256),
                       positions=8192)
    assert "\n" not in str(err.value)


def test_a_planetary_stage_declares_no_quasi_periodic_whine_and_refuses_it_before_work(
        monkeypatch):
    assert QuasiPeriodicBalance not in PlanetaryModel.whine_methods
    model, _ = jio.build_dynamic_model(jio.load_case("examples/planetary-whine.toml"))
    assert isinstance(model, PlanetaryModel)
    monkeypatch.setattr(PlanetaryModel, "whine", _fail)
    with pytest.raises(TypeError, match=r"^method = QuasiPeriodicBalance\(...\): not for a "
                       r"PlanetaryModel \(its whine methods: HarmonicBalance\(...\), "
                       r"TransmissionErrorSource\(...\)\)$"):
        whine_response(model, 10.0, QuasiPeriodicBalance(4, 1), positions=64)


def _case(tmp_path, source, old, new):
    text = jio.embedded_case_text(source)
    assert old in text
    path = tmp_path / "case.toml"
    path.write_text(text.replace(old, new))
    return str(path)


BIG = ("speeds = 36\nharmonics = 8\npositions_per_period = 64",
       "speeds = 2000\nharmonics = 256\npositions_per_period = 8192")
REFUSED = {
    "2000 speeds x 256 harmonics x 8192 positions": ("power-helical-housed", *BIG, (
        r"^\[whine\] speeds = 2000, harmonics = 256: out of range: 2000 speeds x a balance of "
        r"6156 unknowns \(513 harmonics\) is about 4.67e\+14 work")),
    "3 groups on a 2-group train": (
        "two-stage-housed", "positions_per_period = 35", "positions_per_period = [140, 35, 10]",
        (r"^\[whine\] positions_per_period = \[140, 35, 10\]: allowed a positive int, or 2 "
         r"positive ints \(one per mesh-frequency group\)$")),
    "a group's period not in whole steps": (
        "two-stage-housed", "positions_per_period = 35", "positions_per_period = [140, 36]",
        (r"^\[whine\] positions_per_period = \[140, 36\]: group 1's \(period 127/35 of the "
         r"first mesh's\) allowed a multiple of 35")),
    "quasi-periodic on a planetary stage": (
        "nrel-5mw-planetary-housed", "\n[whine]\n", '\n[whine]\nmethod = "quasi-periodic"\n',
        (r"^\[whine\] method = 'quasi-periodic': not for a planetary stage \(PlanetaryModel\): "
         r'allowed "harmonic-balance", "te-source"$')),
}


@pytest.mark.parametrize(("source", "old", "new", "message"), REFUSED.values(), ids=REFUSED)
def test_a_whine_table_is_refused_at_load(tmp_path, monkeypatch, source, old, new, message):
    monkeypatch.setattr(jio, "build_dynamic_model", _fail)
    with pytest.raises(SchemaError, match=message) as err:
        jio.load_case(_case(tmp_path, source, old, new))
    assert "\n" not in str(err.value)


def test_a_whine_table_with_one_entry_per_group_loads(tmp_path):
    case = jio.load_case(_case(tmp_path, "two-stage-housed", "positions_per_period = 35",
                               "positions_per_period = [140, 35]"))
    assert jio.whine_of(case).positions == (140, 35)


def test_the_cli_refuses_a_whine_beyond_the_limit_in_one_line_before_any_output(
        tmp_path, capsys):
    path = _case(tmp_path, "power-helical-housed", *BIG)
    assert main(["run", path, "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err[-1].startswith("jaxgear: error: [whine] speeds = 2000, harmonics = 256: out of")
    assert not (tmp_path / "out").exists()


def test_a_gearbox_whine_beyond_the_limit_is_refused_at_load(tmp_path):
    """The two-pair gearbox's quasi-periodic whine at 2 000 speeds x 100 harmonics (401
    positions per stage: the fewest 4 H + 1 allows): 3 (3 + 4 x 99) = 1 197 harmonics of its 2
    mesh-frequency groups x 4 torsional coordinates."""
    import pathlib
    import shutil

    data = pathlib.Path(__file__).parent / "data" / "gearbox"
    for name in ("two-pair-whine-stage1.toml", "two-pair-whine-stage2.toml"):
        shutil.copy(data / name, tmp_path)
    text = (data / "two-pair-whine.toml").read_text()
    for old, new in (("speeds = 2\nharmonics = 4", "speeds = 2000\nharmonics = 100"),
                     ("positions_per_period = 24", "positions_per_period = 401")):
        assert old in text
        text = text.replace(old, new)
    (tmp_path / "gearbox.toml").write_text(text)
    with pytest.raises(SchemaError, match=r"^\[whine\] speeds = 2000, harmonics = 100: out of "
                       r"range: 2000 speeds x a balance of 4788 unknowns \(1197 harmonics\)"):
        jio.load_case(str(tmp_path / "gearbox.toml"))
