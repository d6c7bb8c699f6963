"""``jaxgear bench`` finds ``benchmarks/`` of a source checkout: next to the ``jaxgear`` package
(an editable install) or in the current folder; without one, one line and exit status 2."""

from __future__ import annotations

import pathlib

import benchmarks
import jaxgear
from jaxgear.cli import main

ROOT = pathlib.Path(__file__).resolve().parents[1]
MESSAGE = (
    "jaxgear: error: jaxgear bench runs from a source checkout (no benchmarks/ folder next to "
    "the jaxgear package or in the current folder)"
)


def _installed_elsewhere(monkeypatch, tmp_path):
    """jaxgear as if installed into a site-packages folder without benchmarks/."""
    site = tmp_path / "site-packages"
    (site / "jaxgear").mkdir(parents=True)
    (site / "jaxgear" / "__init__.py").write_text("")
    monkeypatch.setattr(jaxgear, "__file__", str(site / "jaxgear" / "__init__.py"))


def _bench_runs_the_checkouts_benchmarks(monkeypatch, tmp_path):
    """``jaxgear bench stiffness`` calls ``bench_stiffness`` of the ``benchmarks`` package that
    pytest imported from ``ROOT/benchmarks`` (a spy in its place: the benchmark itself does not
    run): the checkout's folder was found, and the package was not loaded a second time."""
    calls = []
    monkeypatch.setattr(benchmarks, "bench_stiffness", lambda out, quick: calls.append(out))
    assert pathlib.Path(benchmarks.__file__).parent == ROOT / "benchmarks"
    out = tmp_path / "out"
    assert main(["bench", "stiffness", "--quick", "--out", str(out)]) == 0
    return calls == [str(out)]


def test_the_editable_install_finds_the_checkout(monkeypatch, tmp_path):
    assert _bench_runs_the_checkouts_benchmarks(monkeypatch, tmp_path)


def test_the_current_folder_of_a_checkout_is_found(monkeypatch, tmp_path):
    _installed_elsewhere(monkeypatch, tmp_path)
    monkeypatch.chdir(ROOT)
    assert _bench_runs_the_checkouts_benchmarks(monkeypatch, tmp_path)


def test_without_a_checkout_one_line_and_exit_2(monkeypatch, tmp_path, capsys):
    _installed_elsewhere(monkeypatch, tmp_path)
    work = tmp_path / "work"
    (work / "benchmarks").mkdir(parents=True)  # someone else's benchmarks/: not a checkout
    (work / "benchmarks" / "__init__.py").write_text("raise RuntimeError('must not be imported')")
    monkeypatch.chdir(work)
    out = work / "out"  # no folder found: the one-line message below says so
    assert main(["bench", "stiffness", "--quick", "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.strip().splitlines() == [MESSAGE], err
    assert not out.exists()
