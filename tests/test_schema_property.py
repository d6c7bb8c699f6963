"""Property-based test of the whole input schema: case files (``jaxgear/cases``,
``[scene]`` and ``[optimise]`` included) and fem_prep body files (``fem_prep/bodies``), mutated at
any key path with numeric extremes (denormals, ±1e308, ±inf, NaN, huge integers), wrong types,
random text, deleted and unknown keys, give a valid object or the project's own one-line
:class:`~fem_prep.schema.SchemaError`, never anything else; so do the static pieces the CLI
builds from a valid case before any work (geometry summary, mesh model, optimisation settings).

The default suite runs 300 derandomised examples per test (reproducible; about 20 s in all); the
slow suite runs 10 000 per schema with a fixed seed.
"""

from __future__ import annotations

import copy
import datetime
import importlib.resources
import json
import math
import tomllib
import warnings
from pathlib import Path

import pytest
from hypothesis import HealthCheck, example, given, seed, settings, strategies as st

import jaxgear as jg
import jaxgear.io as jio
from fem_prep import load_body, parse_body, schema as sc
from fem_prep.schema import SchemaError
from jaxgear.cli import check_settings, settings_from_case

CASE_FILES = sorted(Path(str(importlib.resources.files("jaxgear") / "cases")).glob("*.toml"))
BODY_FILES = sorted(Path(str(importlib.resources.files("fem_prep") / "bodies")).glob("*.toml"))
CASES = {p.stem: tomllib.loads(p.read_text("utf-8")) for p in CASE_FILES}
BODIES = {p.stem: tomllib.loads(p.read_text("utf-8")) for p in BODY_FILES}
# an [optimise] table on one base (the embedded cases have none)
CASES["accessory-spur+optimise"] = {
    **CASES["accessory-spur"],
    "optimise": {
        "objective": "robust_te_rms",
        "vars": ["tip_relief.depth", "tip_relief.extent"],
        "torques": [40.0, 120.0, 5],
        "reduce": "max",
        "method": "lbfgs",
        "max_iterations": 50,
        "bounds": {"tip_relief.depth": [0.0, 2.5]},
    },
}

DEFAULT = settings(
    max_examples=300,
    deadline=None,
    derandomize=True,
    database=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
)
SLOW = settings(
    max_examples=10_000,
    deadline=None,
    database=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
)

# numeric extremes: denormals, the float range, infinities, NaN, zeros, integers beyond floats
EXTREMES = [
    5e-324,
    -5e-324,
    2.2250738585072014e-308,
    1e-300,
    1e-9,
    1e308,
    -1e308,
    1.7976931348623157e308,
    math.inf,
    -math.inf,
    math.nan,
    0,
    0.0,
    -0.0,
    1,
    -1,
    2,
    4.0,
    0.5,
    1e6,
    10**20,
    2**63,
    10**400,
    -(10**400),
]
PATHS = [str(CASE_FILES[0]), str(BODY_FILES[0]), "../x", "/", "a/b", "x.toml", "x.npz", ".."]
NAMES = ["", " ", "auto", "weber", "fe2d", "accessory-wheel", "dynamic_factor", "rayleigh"]
UNKNOWN_KEYS = ["x", "slice", "face_widht_mm", "a.b", "ünïcode", "", "model", "speeds"]

leaf = st.one_of(
    st.sampled_from(EXTREMES),
    st.floats(),  # any double: denormals, NaN and the infinities included
    st.integers(),
    st.integers(min_value=-(10**500), max_value=10**500),
    st.booleans(),
    st.text(max_size=20),
    st.sampled_from(PATHS + NAMES),
    st.dates(min_value=datetime.date(1, 1, 1)),
)
value = st.one_of(
    leaf,
    st.lists(leaf, max_size=7),
    st.dictionaries(st.sampled_from(UNKNOWN_KEYS + ["depth_um", "position_mm"]), leaf, max_size=3),
)


def _places(node, path=()):
    """Every (path, container, key) of a parsed TOML tree (tables, arrays, values)."""
    if isinstance(node, dict):
        for k, v in node.items():
            yield path + (k,), node, k
            yield from _places(v, path + (k,))
    elif isinstance(node, list):
        for i, v in enumerate(node):
            yield path + (i,), node, i
            yield from _places(v, path + (i,))


def _tables(node, path=()):
    if isinstance(node, dict):
        yield path, node
        for k, v in node.items():
            yield from _tables(v, path + (k,))
    elif isinstance(node, list):
        for i, v in enumerate(node):
            yield from _tables(v, path + (i,))


@st.composite
def mutated(draw, bases: dict):
    """A deep copy of one base with 1 to 4 mutations; returns (data, description)."""
    name = draw(st.sampled_from(sorted(bases)))
    data = copy.deepcopy(bases[name])
    done = [name]
    for _ in range(draw(st.integers(1, 4))):
        kind = draw(st.sampled_from(["extreme", "extreme", "replace", "scale", "delete", "add"]))
        if kind == "add":
            path, table = draw(st.sampled_from(list(_tables(data))))
            key = draw(st.sampled_from(UNKNOWN_KEYS) | st.text(max_size=8))
            table[key] = draw(value)
            done.append(f"add {path + (key,)} = {table[key]!r:.60}")
            continue
        places = list(_places(data))
        if kind == "extreme":  # a number at a numeric key: the extremes most of the time
            places = [x for x in places if isinstance(x[1][x[2]], (int, float))] or places
        if not places:
            break
        path, node, key = draw(st.sampled_from(places))
        old = node[key]
        if kind == "delete":
            del node[key]
            done.append(f"delete {path}")
        elif kind == "scale" and isinstance(old, (int, float)) and not isinstance(old, bool):
            factor = draw(st.sampled_from([-1, 0, 1e-300, 1e-9, 0.5, 2, 1e9, 1e300]))
            node[key] = old * factor if abs(old) < 1e300 else old  # (int * float overflows)
            done.append(f"{path} *= {factor!r}")
        elif kind == "extreme":
            node[key] = draw(st.sampled_from(EXTREMES))
            done.append(f"{path} = {node[key]!r:.60}")
        else:
            node[key] = draw(value)
            done.append(f"{path} = {node[key]!r:.60}")
    return data, "; ".join(done)


def _dump(v) -> str:
    """A TOML value in inline form."""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if math.isnan(v):
            return "nan"
        return ("inf" if v > 0 else "-inf") if math.isinf(v) else repr(v)
    if isinstance(v, str):
        return json.dumps(v)
    if isinstance(v, list):
        return "[" + ", ".join(_dump(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{" + ", ".join(f"{json.dumps(str(k))} = {_dump(x)}" for k, x in v.items()) + "}"
    return v.isoformat()


def _dumps(data: dict) -> str:
    return "".join(f"{json.dumps(str(k))} = {_dump(v)}\n" for k, v in data.items())


def _one_line(fn, what: str):
    """``fn()``'s result, or None after a one-line SchemaError; anything else fails the test.
    Warnings must be one-line CaseWarnings."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            out = fn()
        except SchemaError as err:
            msg = str(err)
            assert msg and "\n" not in msg and "Traceback" not in msg, (what, msg)
            return None
        except BaseException as err:  # anything else is a bug: say which
            raise AssertionError(f"{what}: {type(err).__name__}: {err}") from err
    for w in caught:
        assert issubclass(w.category, jio.CaseWarning), (what, w.category, str(w.message))
        assert "\n" not in str(w.message), (what, str(w.message))
    return out


def _static_pieces(case, what: str) -> None:
    """What ``jaxgear run`` builds from a valid case before the work: the geometry summary, the
    optimisation settings; and the mesh model of the analytic stiffness models (small sizes).
    Only a one-line ValueError may come out."""
    with warnings.catch_warnings(record=True):
        warnings.simplefilter("always")
        try:
            for pair in getattr(case, "pairs", None) or (case.pair,):  # a train's, a pair's
                pair.summary()
            if case.optimise is not None:
                check_settings(settings_from_case(case), case)
            if case.stiffness_model != "fe2d":
                small = case.replace(slices=2, positions_per_pitch=8)
                if isinstance(small, jg.TrainCase):
                    small.mesh_models()
                    small.layout()
                else:
                    small.mesh_model()
        except ValueError as err:
            assert "\n" not in str(err).strip(), (what, str(err))
        except BaseException as err:
            raise AssertionError(f"{what}: static pieces: {type(err).__name__}: {err}") from err


def _check_case(data, what: str, tmp: Path) -> None:
    text = _dumps(data)
    parse = jio.parse_train if "gears" in data or "meshes" in data else jio.parse_case
    case = _one_line(lambda: parse(copy.deepcopy(data)), what)
    path = tmp / "case.toml"
    path.write_text(text, "utf-8")
    from_file = _one_line(lambda: jio.load_case(path), f"{what} (from a file)")
    assert (case is None) == (from_file is None), what
    if case is not None:
        _static_pieces(case, what)


def _check_body(data, what: str, tmp: Path) -> None:
    _one_line(lambda: parse_body(_dumps(data)), what)
    path = tmp / "body.toml"
    path.write_text(_dumps(data), "utf-8")
    _one_line(lambda: load_body(path), f"{what} (from a file)")


@pytest.fixture(scope="module")
def tmp(tmp_path_factory):
    return tmp_path_factory.mktemp("schema-property")


def _with(base: str, *changes) -> tuple[dict, str]:
    """An explicit example: ``base`` with ``(path, value)`` changes (``...`` deletes)."""
    data = copy.deepcopy(CASES[base])
    for path, v in changes:
        node = data
        for k in path[:-1]:
            node = node[k]
        if v is ...:
            del node[path[-1]]
        else:
            node[path[-1]] = v
    return data, f"{base}; {changes}"


@DEFAULT
@example(_with("accessory-spur", (("material", "youngs_modulus_GPa"), 5e-324)))  # ZeroDivision
@example(_with("accessory-spur", (("pinion", "teeth"), 10**400)))  # OverflowError in a message
@example(_with("accessory-spur", (("operating", "torque_Nm"), 10**400)))  # OverflowError
@example(  # KeyError in the message about the default fillet
    _with(
        "accessory-spur",
        (("pinion", "dedendum_coeff"), 0.2),
        (("pinion", "fillet_radius_coeff"), ...),
    )
)
@given(mutated(CASES))
def test_mutated_cases_give_a_case_or_one_schema_error(tmp, example):
    _check_case(*example, tmp)


def _numeric_places(data):
    return [path for path, node, key in _places(data) if sc.finite(node[key])]


@pytest.mark.parametrize("base", ["accessory-spur+optimise", "accessory-spur-flexible"])
def test_every_numeric_key_at_the_extremes(tmp, base):
    """Each numeric key of the base, one at a time, at each extreme (deterministic)."""
    extremes = [5e-324, -5e-324, 1e308, -1e308, math.inf, math.nan, 0, 10**400, -(10**400)]
    places = _numeric_places(CASES[base])
    assert len(places) >= 30
    for path in places:
        for v in extremes:
            _check_case(*_with(base, (path, v)), tmp)


@DEFAULT
@given(mutated(BODIES))
def test_mutated_bodies_give_a_body_or_one_schema_error(tmp, example):
    _check_body(*example, tmp)


@DEFAULT
@given(st.text(max_size=200) | st.binary(max_size=200))
def test_random_text_gives_one_schema_error(tmp, text):
    raw = text.encode("utf-8", "surrogatepass") if isinstance(text, str) else text
    for name, load in (("case.toml", jio.load_case), ("body.toml", load_body)):
        path = tmp / name
        path.write_bytes(raw)
        _one_line(lambda load=load, path=path: load(path), f"{name}: {raw!r}")


@pytest.mark.slow
@SLOW
@seed(18)
@given(mutated(CASES))
def test_mutated_cases_slow(tmp, example):
    _check_case(*example, tmp)


@pytest.mark.slow
@SLOW
@seed(18)
@given(mutated(BODIES))
def test_mutated_bodies_slow(tmp, example):
    _check_body(*example, tmp)
