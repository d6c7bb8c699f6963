"""Property-based test of the whole input schema: case files (``jaxgear/cases``, the trains,
``[scene]`` and ``[optimise]`` included, and bases with ``[deviations]`` (a grade, given
per-tooth values), backlash (tooth thickness allowances, a centre distance) and ``[robust]``)
and fem_prep body files (``fem_prep/bodies``), mutated at any key path with numeric extremes
(denormals, ±1e308, ±inf, NaN, huge integers), wrong types, random text, deleted and unknown
keys, give a valid object or the project's own one-line :class:`~fem_prep.schema.SchemaError`,
never anything else; so do the static pieces the CLI builds from a valid case before any work
(geometry summary, mesh model, optimisation settings, the ``[robust]`` settings).

The stage after loading: mildly mutated train, deviation, backlash and ``[robust]`` cases that
load are built (2 slices) and solved quasi-statically at 3 positions; only a one-line
``ValueError``, finite results or the solver's own result codes may come out.

The default suite runs 100 derandomised examples per schema test and 10 of the model stage
(reproducible; each key at each numeric extreme besides); the slow suite runs 10 000 per
schema and 300 of the model stage with a fixed seed.
"""

from __future__ import annotations

import copy
import datetime
import importlib.resources
import math
import tomllib
import warnings
from pathlib import Path

import jax
import numpy as np
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

# deviation, backlash and [robust] tables on the accessory pair (45 and 86 teeth); the trains
# (two-stage, accessory-idler-train, flexible-idler) are among the embedded cases already
_PITCH = [1.0, -1.0] * 22 + [0.0]  # 45 single pitch deviations that close (µm)
CASES["accessory-spur+deviations"] = {
    **CASES["accessory-spur"],
    "deviations": {
        "grade": 6,
        "seed": 3,
        "revolutions": 1,
        "positions_per_pitch": 4,
        "pinion": {"runout_um": 5.0, "runout_phase_deg": 30.0, "helix_slope_um": 1.0},
        "gear": {"profile_form_um": 0.5},
    },
}
CASES["accessory-spur+given-deviations"] = {
    **CASES["accessory-spur"],
    "deviations": {
        "revolutions": 2,
        "pinion": {"pitch_um": list(_PITCH), "profile_slope_um": [0.5] * 45},
        "gear": {"runout_um": 4.0, "helix_form_um": -1.0},
    },
}
CASES["accessory-spur+backlash"] = {
    **CASES["accessory-spur"],
    "pair": {**CASES["accessory-spur"]["pair"], "center_distance_mm": 99.5},
    "pinion": {**CASES["accessory-spur"]["pinion"], "tooth_thickness_allowance_um": -40.0},
    "gear": {**CASES["accessory-spur"]["gear"], "tooth_thickness_allowance_um": -30.0},
}
CASES["accessory-spur+robust"] = {
    **CASES["accessory-spur"],
    "robust": {
        "grade": 6,
        "samples": 8,
        "seed": 1,
        "members": ["pinion", "gear"],
        "kinds": ["pitch", "runout", "profile", "helix"],
        "revolutions": 1,
        "positions_per_pitch": 4,
        "speeds_rad_s": [100.0, 200.0],
        "steps_per_period": 16,
        "transient_periods": 2,
        "batch_size": 4,
        "percentiles": [5.0, 50.0, 95.0],
        "confidence": 0.9,
    },
}
# the bases of the second stage (building the model for a few positions); the train with a
# lumped 3D scene (two-stage) compiles for long: the slow suite only
STAGE_BASES = {
    k: CASES[k]
    for k in (
        "accessory-spur",
        "power-helical",
        "accessory-idler-train",
        "accessory-spur+deviations",
        "accessory-spur+given-deviations",
        "accessory-spur+backlash",
        "accessory-spur+robust",
    )
}

DEFAULT = settings(
    max_examples=100,
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


ANY_MUTATION = ("extreme", "extreme", "replace", "scale", "delete", "add")
ANY_FACTOR = (-1, 0, 1e-300, 1e-9, 0.5, 2, 1e9, 1e300)
# mild mutations for the second stage: most mutants still load and reach the model
MILD_MUTATION = ("scale", "scale", "scale", "delete", "extreme")
MILD_FACTOR = (-1, 0, 0.5, 0.9, 1.1, 1.5, 2, 10)


@st.composite
def mutated(draw, bases: dict, kinds=ANY_MUTATION, factors=ANY_FACTOR, most: int = 4):
    """A deep copy of one base with 1 to ``most`` mutations drawn among ``kinds`` (numbers
    scaled by one of ``factors``); returns (data, description)."""
    name = draw(st.sampled_from(sorted(bases)))
    data = copy.deepcopy(bases[name])
    done = [name]
    for _ in range(draw(st.integers(1, most))):
        kind = draw(st.sampled_from(kinds))
        if kind == "add":
            path, table = draw(st.sampled_from(list(_tables(data))))
            key = draw(st.sampled_from(UNKNOWN_KEYS) | st.text(max_size=8))
            table[key] = draw(value)
            done.append(f"add {path + (key,)} = {table[key]!r:.60}")
            continue
        places = list(_places(data))
        numeric = kind == "extreme" or (kind == "scale" and kinds == MILD_MUTATION)
        if numeric:  # a number at a numeric key: the extremes most of the time
            places = [x for x in places if isinstance(x[1][x[2]], (int, float))] or places
        if not places:
            break
        path, node, key = draw(st.sampled_from(places))
        old = node[key]
        if kind == "delete":
            del node[key]
            done.append(f"delete {path}")
        elif kind == "scale" and isinstance(old, (int, float)) and not isinstance(old, bool):
            factor = draw(st.sampled_from(factors))
            node[key] = old * factor if abs(old) < 1e300 else old  # (int * float overflows)
            done.append(f"{path} *= {factor!r}")
        elif kind == "extreme":
            node[key] = draw(st.sampled_from(EXTREMES))
            done.append(f"{path} = {node[key]!r:.60}")
        else:
            node[key] = draw(value)
            done.append(f"{path} = {node[key]!r:.60}")
    return data, "; ".join(done)


def _toml_str(text: str) -> str:
    """A TOML basic string: quotes, backslashes and control characters escaped, the rest as is
    (``json.dumps`` writes a character beyond the BMP as a surrogate pair, which TOML refuses)."""
    out = []
    for c in text:
        if c in '"\\':
            out.append("\\" + c)
        elif ord(c) < 0x20 or c == "\x7f":
            out.append(f"\\u{ord(c):04x}")
        else:
            out.append(c)
    return '"' + "".join(out) + '"'


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
        return _toml_str(v)
    if isinstance(v, list):
        return "[" + ", ".join(_dump(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{" + ", ".join(f"{_toml_str(str(k))} = {_dump(x)}" for k, x in v.items()) + "}"
    return v.isoformat()


def _dumps(data: dict) -> str:
    return "".join(f"{_toml_str(str(k))} = {_dump(v)}\n" for k, v in data.items())


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
                if isinstance(small.form, jio.TrainForm):
                    small.mesh_models()
                    small.layout()
                else:
                    small.mesh_model()
        except ValueError as err:
            assert "\n" not in str(err).strip(), (what, str(err))
        except BaseException as err:
            raise AssertionError(f"{what}: static pieces: {type(err).__name__}: {err}") from err


def _robust_settings(case, what: str):
    """The ``[robust]`` table of a loaded pair case, as ``jaxgear robust`` reads it: its
    settings or None after a one-line SchemaError (anything else fails the test)."""
    if isinstance(case.form, jio.TrainForm) or not isinstance(case.raw, dict):
        return None
    if "robust" not in case.raw:
        return None
    grade = None if case.deviation_settings is None else case.deviation_settings.get("grade")
    teeth = (case.pair.pinion.teeth, case.pair.gear.teeth)
    return _one_line(
        lambda: jio.parse_robust(case.raw["robust"], teeth, grade_from_deviations=grade),
        f"{what} [robust]",
    )


def _parsed_and_checked(parse, data):
    case = parse(data)
    jio.check_case(case)
    return case


def _check_case(data, what: str, tmp: Path, *, build: bool = False) -> None:
    text = _dumps(data)
    path = tmp / "case.toml"
    path.write_text(text, "utf-8")
    from_file = _one_line(lambda: jio.load_case(path), f"{what} (from a file)")
    if "stages" in data:
        # a gearbox case names its stages' case files: it is read from a file only (its stages
        # load relative to it), no dict parser to compare with
        case = from_file
    else:
        # the loader's own choice: a train or a planetary stage (parse_train reads both), else a
        # pair
        train = any(k in data for k in ("gears", "meshes", "planetary"))
        parse = jio.parse_train if train else jio.parse_case
        # the dict's case, checked as load_case checks a file's against its geometry
        case = _one_line(lambda: _parsed_and_checked(parse, copy.deepcopy(data)), what)
        assert (case is None) == (from_file is None), what
    if case is not None:
        _static_pieces(case, what)
        robust = _robust_settings(case, what)
        if build:
            _built(case, robust, what)


def _built(case, robust, what: str) -> None:
    """The stage after loading: the case's model built small (2 slices) and solved
    quasi-statically at 3 positions (deviations and backlash included; a [robust] table's
    sampler drawing one realisation). Only a one-line ValueError (the project's refusal) may
    come out, and every position gives either a finite result or one of the solver's own
    result codes (:class:`jaxgear.ContactResult`)."""
    if case.stiffness_model == "fe2d" or getattr(case, "flexible", False):
        return  # FE meshing: minutes, and another test's subject
    if getattr(case, "scene", None) is not None and case.scene.model == "hybrid":
        return
    with warnings.catch_warnings(record=True):
        warnings.simplefilter("always")
        try:
            small = case.replace(slices=2, positions_per_pitch=8)
            if isinstance(small.form, jio.TrainForm):
                scene = small.static_train()
                mods = small.mesh_modifications()
                plane = scene.base_planes[0]
            else:
                scene = plane = small.mesh_model()
                mods = small.modifications
                deviations = small.deviations
                if robust is not None and robust.get("grade") is not None:
                    sampler = jg.DeviationSampler.for_grade(
                        small.pair,
                        robust["grade"],
                        members=tuple(robust["members"]),
                        kinds=jio.deviation_kinds_from_names(robust["kinds"]),
                    )
                    deviations = sampler(jax.random.PRNGKey(robust["seed"]))
                if deviations is not None:
                    mods = jg.Modifications(mods.pinion, mods.gear, deviations=deviations)
            theta = jg.mesh_positions(plane, 3)
            res = jg.quasi_static(scene, mods, small.torque, theta, throw=False)
            codes = np.asarray(res.result)
        except ValueError as err:
            assert "\n" not in str(err).strip(), (what, str(err))
            return
        except BaseException as err:
            raise AssertionError(f"{what}: model: {type(err).__name__}: {err}") from err
    known = {int(c) for c in (jg.ContactResult.successful, jg.ContactResult.max_iterations,
                              jg.ContactResult.no_contact, jg.ContactResult.non_finite)}
    assert set(codes.tolist()) <= known, (what, codes)
    ok = codes == 0
    for m in res.meshes:
        te = np.asarray(m.transmission_error)
        assert np.all(np.isfinite(te[ok])), (what, te, codes)
    assert np.all(np.isfinite(np.asarray(res.x)[ok])), (what, codes)


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


STAGE = settings(
    max_examples=10,
    deadline=None,
    derandomize=True,
    database=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
)


@STAGE
@given(mutated(STAGE_BASES, MILD_MUTATION, MILD_FACTOR, 2))
def test_mutated_cases_build_and_solve_or_refuse_in_one_line(tmp, example):
    """Train, deviation, backlash and [robust] files mutated: the loader gives a case or one
    SchemaError; a case gives a model that solves 3 positions (finite, or the solver's own
    result codes) or one ValueError line. Few examples: each one that loads compiles a model."""
    _check_case(*example, tmp, build=True)


@DEFAULT
@given(mutated(BODIES))
def test_mutated_bodies_give_a_body_or_one_schema_error(tmp, example):
    _check_body(*example, tmp)


@settings(DEFAULT, max_examples=300)  # cheap, and no slow twin
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
@settings(SLOW, max_examples=300)
@seed(18)
@given(mutated({**STAGE_BASES, "two-stage": CASES["two-stage"]}, MILD_MUTATION, MILD_FACTOR, 2))
def test_mutated_cases_build_slow(tmp, example):
    _check_case(*example, tmp, build=True)


@pytest.mark.slow
@SLOW
@seed(18)
@given(mutated(BODIES))
def test_mutated_bodies_slow(tmp, example):
    _check_body(*example, tmp)
