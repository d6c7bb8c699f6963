"""A table-valued key given as something else (a number, a boolean, a string) is refused at load
in one line naming the key, never a ``TypeError`` or ``AttributeError`` from the reader that
takes the table: every table of every sample case file (the embedded cases, the examples and
the case-file reference's samples, which between them hold every table the readers know) is
replaced in turn. Load only: nothing runs."""

from __future__ import annotations

import copy
import functools
import pathlib
import tempfile
import warnings

import pytest
from _toml import case_toml
from hypothesis import HealthCheck, given, settings, strategies as st

import jaxgear.io as jio
from fem_prep import schema as sc
from jaxgear.cli import main
from jaxgear.io._rating_table import PER_GEAR


def _table_paths(data, path=()):
    """The path (keys, array indices) of every table and array of tables in ``data``."""
    items = data.items() if isinstance(data, dict) else enumerate(data)
    for key, value in items:
        array = isinstance(value, list) and value and all(isinstance(v, dict) for v in value)
        if isinstance(value, dict) or array:
            yield (*path, key)
            yield from _table_paths(value, (*path, key))


@functools.cache
def _samples() -> tuple:
    """(data, base folder, its reader, kind) of every sample case file."""
    from docs._gen import schema_reference as sr

    out = []
    for data, base in sr.case_samples():
        train = sr.is_train(data)
        out.append((data, base, jio.parse_train if train else jio.parse_case, "train" * train))
    for data, base in sr.gearbox_samples():
        out.append((data, base, _load_gearbox, "gearbox"))
    return tuple(out)


def _load_gearbox(data, name, base):
    """A gearbox file's data loaded as a file (its stages are embedded cases' names)."""
    with tempfile.TemporaryDirectory() as folder:
        path = pathlib.Path(folder) / f"{name}.toml"
        path.write_text(case_toml(data), encoding="utf-8")
        return jio.load_case(path)


@functools.cache
def _tables() -> tuple:
    """(sample index, table path): each table once per file kind (array entries as the first)."""
    seen, out = set(), []
    for i, (data, _, _, kind) in enumerate(_samples()):
        for path in _table_paths(data):
            shape = (kind, *(0 if isinstance(p, int) else p for p in path))
            if shape not in seen:
                seen.add(shape)
                out.append((i, path))
    return tuple(out)


def _refused_in_one_line(i: int, path: tuple, value) -> str:
    data, base, read, _ = _samples()[i]
    data = copy.deepcopy(data)
    table = data
    for part in path[:-1]:
        table = table[part]
    table[path[-1]] = value
    with pytest.raises(sc.SchemaError) as info, warnings.catch_warnings():
        warnings.simplefilter("ignore")  # an absurd but valid neighbour's CaseWarning
        read(data, "case", base)
    msg = str(info.value)
    assert "\n" not in msg.strip(), msg
    key = next(p for p in reversed(path) if isinstance(p, str))
    assert key in msg, (path, msg)
    return msg


NON_TABLES = (0.0, False, "x")


def test_every_table_given_as_a_number_bool_or_string_is_one_line():
    """Each table of the samples (about a hundred) as a number, a boolean or a string (in
    turn): a one-line SchemaError naming it."""
    tables = _tables()
    assert len(tables) > 100  # the samples hold the readers' tables (a lost sample shows here)
    for k, (i, path) in enumerate(tables):
        _refused_in_one_line(i, path, NON_TABLES[k % len(NON_TABLES)])


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    pick=st.integers(min_value=0),
    value=st.one_of(
        st.floats(allow_nan=True, allow_infinity=True),
        st.integers(min_value=-(2**70), max_value=2**70),
        st.booleans(),
        st.text(max_size=8),
        st.lists(st.integers(), max_size=2),
    ),
)
def test_any_scalar_in_place_of_a_table_is_one_line(pick, value):
    """(The case files' tables: a gearbox file is read from a file, whose text these values
    may not survive.)"""
    tables = [(i, p) for i, p in _tables() if _samples()[i][3] != "gearbox"]
    i, path = tables[pick % len(tables)]
    if path[-1] in PER_GEAR and sc.finite(value):
        return  # a per-gear table by gear name: a number is one value for every gear
    if isinstance(value, list) and value == [] and isinstance(path[-1], str):
        # an empty array where an array of tables is optional is an empty array of tables
        data = _samples()[i][0]
        for part in path[:-1]:
            data = data[part]
        if isinstance(data[path[-1]], list):
            return
    _refused_in_one_line(i, path, value)


@pytest.mark.parametrize(
    ("path", "value", "words"),
    [
        (("lubricant",), 0.0, "lubricant = 0: must be a table ([lubricant]), not a number"),
        (
            ("housing", "seats"),
            5e-324,
            (
                "[housing] seats = 4.94066e-324: must be an array of tables ([[housing.seats]]), "
                "not a number"
            ),
        ),
        (("housing", "feet"), False, "[housing] feet = false: must be an array of tables"),
        (("housing", "seats", 0), 1.0, "[housing] 'seats[0]' = 1: must be a table"),
        (
            ("acoustics", "microphones"),
            "x",
            "[acoustics] microphones = 'x': must be an array of tables",
        ),
    ],
)
def test_the_reported_tables(path, value, words):
    """The tables the review gave as numbers (a ``TypeError`` before)."""
    for i, (data, *_) in enumerate(_samples()):
        try:
            functools.reduce(lambda t, p: t[p], path[:-1], data)[path[-1]]
        except (KeyError, IndexError, TypeError):
            continue
        assert words in _refused_in_one_line(i, path, value)
        return
    pytest.fail(f"no sample holds {path}")


def test_gearbox_without_stages_in_its_own_words(tmp_path):
    file = tmp_path / "box.toml"
    file.write_text('name = "box"\n[operating]\ntorque_Nm = 3.9e6\nspeed_rad_s = 1.27\n')
    with pytest.raises(sc.SchemaError, match=r"^\[\[stages\]\]: missing; a gearbox file lists"):
        jio.load_case(file)
    file.write_text("stages = []\n[operating]\ntorque_Nm = 3.9e6\nspeed_rad_s = 1.27\n")
    with pytest.raises(sc.SchemaError, match=r"stages = \[\]: must be a non-empty array"):
        jio.load_case(file)
    # a pair case that lacks its [pair] is still told so
    file.write_text("[operating]\ntorque_Nm = 80.0\n[pinion]\nteeth = 20\n")
    with pytest.raises(sc.SchemaError, match=r"^\[pair\]: missing required table"):
        jio.load_case(file)


def test_sweep_takes_a_gearbox_through_its_model(tmp_path, capsys):
    """``jaxgear sweep`` on a gearbox (``zip() argument 2 is shorter than argument 1`` once,
    then refused): its coupled model's (a GearboxModel) options checked by its contract, a
    continuation refused in one line, exit 2, no output folder (the sweep itself:
    tests/test_cli_sweep_forms.py)."""
    out = tmp_path / "out"
    argv = ["sweep", "nrel-5mw-gearbox", "--speeds", "1:2:3", "--direction", "up"]
    assert main([*argv, "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    assert "--direction = up: a GearboxModel sweeps independent speeds only" in err[0]
    assert not out.exists()
