"""``jaxgear sweep`` refuses a ``--solver`` or ``--contact`` that the case's dynamic model kind
does not declare (:attr:`jaxgear.dynamics.AbstractDynamicModel.integrators`,
:attr:`~jaxgear.dynamics.AbstractDynamicModel.contact_laws`) in one line at load, for every
form, from the kind's class: no model is built (the builders are replaced here by one that
fails the test), and a solver the kind declares passes the check without a model either.
"""

from __future__ import annotations

import pathlib

import pytest

import jaxgear as jg
import jaxgear.io as jio
from jaxgear.cli import gearbox as cli_gearbox, main, planetary_sweep as cli_planetary, sweep
from jaxgear.planetary import PlanetaryModel

GEARBOX = str(pathlib.Path(__file__).parent / "data" / "gearbox" / "two-stage-gearbox.toml")


def _no_build(*args, **kwargs):
    raise AssertionError("a dynamic model was built to check the options")


@pytest.fixture
def no_build(monkeypatch):
    for module in (jio, cli_gearbox, cli_planetary):
        monkeypatch.setattr(module, "build_dynamic_model", _no_build)
    monkeypatch.setattr(jio.GearboxForm, "dynamic_model", _no_build)


def _refusal(capsys, argv, out) -> str:
    assert main([*argv, "--out", str(out), "--quiet"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    assert not out.exists()
    return err[0]


@pytest.mark.parametrize(
    ("case", "words"),
    [("lin-parker-1999", "--solver = tsit5: a PlanetaryModel does not run it (allowed: newmark)"),
     (GEARBOX, "--solver = tsit5: a GearboxModel does not run it (allowed: newmark)")],
    ids=["planetary", "gearbox"],
)
def test_a_solver_the_kind_does_not_declare_is_refused_without_a_model(
        no_build, tmp_path, capsys, case, words):
    argv = ["sweep", case, "--speeds", "60:120:2", "--solver", "tsit5"]
    assert _refusal(capsys, argv, tmp_path / "out").endswith(words)


def test_a_contact_law_the_kind_does_not_declare_is_refused_without_a_model(
        no_build, monkeypatch, tmp_path, capsys):
    """Every kind declares both laws; a planetary kind declaring the exact one alone refuses
    ``--contact smooth``, naming the names it allows."""
    monkeypatch.setattr(PlanetaryModel, "contact_laws", (jg.ExactContact,))
    argv = ["sweep", "lin-parker-1999", "--speeds", "150:900:2", "--contact", "smooth"]
    assert _refusal(capsys, argv, tmp_path / "out").endswith(
        "--contact = smooth: a PlanetaryModel does not run it (allowed: exact)")


@pytest.mark.parametrize("case", ["accessory-spur", "accessory-idler-train", "lin-parker-1999",
                                  GEARBOX], ids=["pair", "train", "planetary", "gearbox"])
def test_what_the_kind_declares_passes_the_check_without_a_model(no_build, case):
    """A pair's and a train's lumped model runs a diffrax solver; every kind runs both laws."""
    c = jio.load_case(case)
    lumped = jio.dynamic_model_kind(c.form, c) is jg.dynamics.DynamicModel
    for contact in ("exact", "smooth"):
        sweep.check_sweep(c.form, c, solver="tsit5" if lumped else "newmark", contact=contact)


def test_a_flexible_pair_refuses_a_diffrax_solver_in_its_own_words(no_build, tmp_path, capsys):
    """A scene with condensed bodies: the case's scene refuses first (its words kept), before
    its condensed bodies are loaded."""
    argv = ["sweep", "accessory-spur-flexible", "--speeds", "100:200:2", "--solver", "tsit5"]
    assert "sweeps independent speeds with Newmark only" in _refusal(
        capsys, argv, tmp_path / "out")
