"""A planetary stage's, a gearbox's and a housing's tables read through their typed sections
(``[planetary]`` and its member tables, a stage's ``[deviations]``, a gearbox's
``[operating]`` and ``[[stages]]``, ``[housing]``: :mod:`jaxgear.io._sections`), through the
readers ``jaxgear run`` loads a file with: a table given as a number is one line (never a
``TypeError``), and a file mutated at any key of those tables loads or is one
:class:`~fem_prep.checks.SchemaError` line. Load only: nothing is meshed or solved (the cheap
cases: Lin & Parker's lumped stage, the housed NREL stage, the two-stage test gearbox, the
housed helical pair, the hunting-span example's ``[deviations]``)."""

from __future__ import annotations

import copy
import functools
import pathlib
import tomllib
import warnings

import pytest
from hypothesis import HealthCheck, given, settings, strategies as st

from fem_prep import checks as sc
from jaxgear.io import _load

ROOT = pathlib.Path(__file__).resolve().parents[1]
FILES = {
    "lumped": ROOT / "jaxgear/cases/lin-parker-1999.toml",
    "housed-stage": ROOT / "jaxgear/cases/nrel-5mw-planetary-housed.toml",
    "gearbox": ROOT / "tests/data/gearbox/two-stage-gearbox.toml",
    "housed-pair": ROOT / "jaxgear/cases/power-helical-housed.toml",
    "hunting": ROOT / "examples/planetary-hunting.toml",
}


@functools.cache
def _data(name: str) -> dict:
    return tomllib.loads(FILES[name].read_text("utf-8"))


def _load_data(name: str, data: dict):
    """``data`` read as :func:`jaxgear.io.load_case` reads the file ``name`` (its folder the
    base of the files it names)."""
    base = str(FILES[name].parent)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        if _load.is_gearbox(data):
            return _load.parse_gearbox(data, name, base,
                                       functools.partial(_load._load, chain=()))
        read = _load.parse_train if _load.is_train(data) else _load.parse_case
        case = read(data, name, base)
        _load.check_case(case)
        return case


def _one_line(name: str, data: dict) -> str:
    with pytest.raises(sc.SchemaError) as err:
        _load_data(name, data)
    msg = str(err.value)
    assert "\n" not in msg and "validation error" not in msg, msg
    return msg


def test_the_files_load():
    for name in FILES:
        _load_data(name, copy.deepcopy(_data(name)))


@pytest.mark.parametrize(("name", "path", "value", "words"), [
    ("lumped", ("planetary",), 3, "planetary = 3: must be a table ([planetary]), not a number"),
    ("housed-stage", ("planetary",), 3,
     "planetary = 3: must be a table ([planetary]), not a number"),
    ("lumped", ("planetary", "sun"), 3,
     "[planetary] sun = 3: must be a table ([planetary.sun]), not a number"),
    ("lumped", ("planetary", "ring"), [1.0],
     "[planetary] ring = [1]: must be a table ([planetary.ring]), not an array"),
    ("housed-stage", ("housing",), 2, "housing = 2: must be a table ([housing]), not a number"),
    ("housed-pair", ("housing",), 2, "housing = 2: must be a table ([housing]), not a number"),
    ("housed-pair", ("housing", "points_mm"), 2,
     "[housing] points_mm = 2: must be a table ([housing.points_mm]), not a number"),
    ("gearbox", ("stages",), 1,
     "stages = 1: must be an array of tables ([[stages]]), not a number"),
    ("gearbox", ("stages", 0), 3, ("'stages[0]' = 3: must be a table ([[stages]] entry), not a "
     "number")),
    ("gearbox", ("operating",), 2,
     "operating = 2: must be a table ([operating]), not a number"),
    ("gearbox", ("housing",), 2, "housing = 2: must be a table ([housing]), not a number"),
    ("hunting", ("deviations",), 2,
     "deviations = 2: must be a table ([deviations]), not a number"),
    ("hunting", ("deviations", "planet_2"), 2,
     "[deviations] planet_2 = 2: must be a table ([deviations.planet_2]), not a number"),
])
def test_a_table_given_as_a_value_is_one_line(name, path, value, words):
    data = copy.deepcopy(_data(name))
    node = data
    for part in path[:-1]:
        node = node[part]
    node[path[-1]] = value
    assert _one_line(name, data).startswith(words)


@pytest.mark.parametrize(("name", "change", "words"), [
    ("gearbox", lambda d: d["stages"][1].pop("shaft_Nm_per_rad"),
     "[stages[1]] shaft_Nm_per_rad: missing required key"),
    ("gearbox", lambda d: d["stages"][1].pop("input"), "[stages[1]] input: missing required key"),
    ("gearbox", lambda d: d["stages"][1].update(model="planar"),
     "[stages[1]] model = 'planar': allowed 'torsional', 'lumped3d'"),
    ("gearbox", lambda d: d["stages"][0].update(model="lumped3d"),
     ("[stages[0]] model = 'lumped3d': only for a pair stage (a planetary stage's model: allowed "
     "'torsional', 'planar')")),
    ("gearbox", lambda d: d["stages"][0].update(input="gear"),
     "[stages[0]] input = 'gear': only for a pair stage"),
    ("gearbox", lambda d: d["stages"][1].update(pinion_inertia_kg_m2="heavy"),
     "[stages[1]] pinion_inertia_kg_m2 = 'heavy': must be a number, not a string"),
    ("gearbox", lambda d: d["operating"].update(torque_Nm=1e-6),
     "[operating] torque_Nm = 1e-06: out of range, allowed ["),
    ("lumped", lambda d: d["planetary"].update(sun_gear="sun"),
     "[planetary] sun_gear = 'sun': allowed only with [[gears]] (the gear form)"),
    ("lumped", lambda d: d["planetary"].pop("sun_teeth"),
     "[planetary] sun_teeth: missing required key"),
    ("lumped", lambda d: d["planetary"]["sun"].pop("base_radius_mm"),
     "[planetary.sun] base_radius_mm: missing required key"),
    ("lumped", lambda d: d["planetary"].update(housing_seat=0),
     "[planetary] housing_seat = 0: allowed only with a [housing]"),
    ("lumped", lambda d: d["planetary"].update(tangential_pin_errors_um=[1.0, 2.0]),
     "[planetary] tangential_pin_errors_um = [1, 2]: must hold one value per planet ("),
    ("housed-stage", lambda d: d["planetary"].update(housing_seat=2),
     ("[planetary] housing_seat = 2: out of range, allowed [0, 1] (a box: 0 its x- wall's bore, "
     "1 its x+ wall's)")),
    ("housed-stage", lambda d: d["housing"].update(mesh_unit="mm"),
     "[housing] mesh_unit = 'mm': a mesh file's key: allowed with mesh_file only"),
])
def test_what_follows_the_stage_is_refused_in_its_words(name, change, words):
    """The checks a section cannot make (which form, which stage kind, the housing's seats,
    the planets' count) where the stage is read, in the words the hand-written checks used."""
    data = copy.deepcopy(_data(name))
    change(data)
    msg = _one_line(name, data)
    assert msg.startswith(words), msg


def test_a_planetary_file_reaches_the_stage_as_given():
    """The lumped file's numbers on the stage in SI (mm → m, N/µm → N/m, I/r² × r²): against
    the file's own values (Lin & Parker 1999, Table 1)."""
    data = copy.deepcopy(_data("lumped"))
    spec = _load_data("lumped", data).form.spec
    t = data["planetary"]
    assert spec.teeth == (t["sun_teeth"], None, t["ring_teeth"])
    assert spec.n_planets == t.get("planets", len(t.get("planet_angles_deg", ())))
    for m in ("sun", "ring", "carrier", "planet"):
        r = t[m]["base_radius_mm"] * 1e-3
        member = spec.members[m]
        assert float(member.base_radius) == pytest.approx(r, rel=1e-15)
        assert float(member.mass) == pytest.approx(t[m]["mass_kg"], rel=1e-15)
        assert float(member.polar_inertia) == pytest.approx(
            t[m]["inertia_over_r2_kg"] * r**2, rel=1e-15)
    k = spec.mesh_stiffness
    assert (k.sun, k.ring) == pytest.approx(
        (t["sun_mesh_stiffness_N_per_um"] * 1e6, t["ring_mesh_stiffness_N_per_um"] * 1e6),
        rel=1e-15)


VALUES = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.integers(min_value=-(2**70), max_value=2**70),
    st.sampled_from([0, -1, 1, 2, 3, 10**400, 5e-324, "ring", "sun", "carrier", "gear"]),
    st.booleans(),
    st.text(max_size=6),
    st.lists(st.one_of(st.floats(), st.integers(min_value=-3, max_value=3)), max_size=4),
    st.dictionaries(st.sampled_from(["mass_kg", "x", "top"]), st.integers(), max_size=2),
)

#: (file, table path) mutated: [planetary] and its members, a gearbox's tables, [housing]
PLACES = [
    ("lumped", ("planetary",)), ("lumped", ("planetary", "sun")),
    ("lumped", ("planetary", "ring")), ("lumped", ("planetary", "carrier")),
    ("lumped", ("planetary", "planet")), ("housed-stage", ("planetary",)),
    ("housed-stage", ("housing",)), ("housed-pair", ("housing",)),
    ("gearbox", ("operating",)), ("gearbox", ("stages", 0)), ("gearbox", ("stages", 1)),
    ("hunting", ("deviations",)), ("hunting", ("deviations", "planet_2")),
]


@settings(max_examples=40, deadline=None, derandomize=True, database=None,
          suppress_health_check=[HealthCheck.too_slow])
@given(place=st.sampled_from(PLACES), key=st.integers(min_value=0), value=VALUES,
       unknown=st.booleans())
def test_a_mutated_stage_file_is_one_line(place, key, value, unknown):
    """A key of one of the tables (or an unknown key) given any TOML value: the file loads or
    is refused in one line, never another exception."""
    name, path = place
    data = copy.deepcopy(_data(name))
    table = data
    for part in path:
        table = table[part]
    keys = sorted(table)
    table["speed_mm_s" if unknown else keys[key % len(keys)]] = value
    try:
        _load_data(name, data)
    except sc.SchemaError as err:
        assert "\n" not in str(err), str(err)
        assert not unknown or "unknown key 'speed_mm_s'" in str(err), str(err)
