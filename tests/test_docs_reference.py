"""The generated case-file and body-file references (docs/_gen/schema_reference.py) hold exactly
the keys the validators accept.

The references are read from the validators' declarations; this test asks the validators
directly, as a user would find out: it puts an unknown key into each table of a valid file and
reads the list of allowed keys from the one-line error (``[pinion] unknown key 'zz_not_a_key',
allowed: addendum_coeff, …``). Starting from the top level and walking into every sub-table
the sample files hold, each table's allowed keys must be the reference's keys of that table and
every such table must be in the reference; a key the reference lists that the validator refuses
fails too. About 3 s.
"""

import copy
import re
import tomllib
import warnings

import pytest

import jaxgear.io as jio
from docs._gen import schema_reference as sr
from fem_prep import schema as body_schema

UNKNOWN = "zz_not_a_key"
# an inline table's keys are written with its name in front: [body] unknown key 'holes.zz…'
ALLOWED = re.compile(
    r"unknown key '(?:[\w.-]+\.)?" + UNKNOWN + r"'(?: \(did you mean .*?\))?, allowed: (.*)$"
)


def _allowed(parse, data, path) -> set[str]:
    """The keys the validator allows in the table at ``path`` (a list of keys and indices) of
    ``data``: read from its error for an unknown key there."""
    data = copy.deepcopy(data)
    table = data
    for part in path:
        table = table[part]
    table[UNKNOWN] = 1.0
    with warnings.catch_warnings(), pytest.raises(ValueError) as err:
        warnings.simplefilter("ignore")
        parse(data)
    m = ALLOWED.search(str(err.value))
    assert m, (path, str(err.value))
    return {k.rpartition(".")[2] for k in m.group(1).split(", ")}


def _gear_names(data) -> set:
    """The gear names a file gives (``[[gears]] name``)."""
    return {g["name"] for g in data.get("gears", []) if isinstance(g, dict) and "name" in g}


def _walk(data, path=()):
    """Every table of ``data`` (dicts, arrays of dicts) with its path; a per-gear value (an
    inline table keyed by the file's gear names, ``{ sun2 = 1500.0, ring2 = 700.0 }``) is a
    value, not a table."""
    yield path
    table = data
    for part in path:
        table = table[part]
    names = _gear_names(data)
    for key, value in table.items():
        if isinstance(value, dict) and value and names and set(value) <= names:
            continue
        if isinstance(value, dict):
            yield from _walk(data, (*path, key))
        elif isinstance(value, list) and value and all(isinstance(v, dict) for v in value):
            yield from _walk(data, (*path, key, 0))


def _name(path) -> str:
    """The validator's own spelling of a table's path (``scene.shafts[0]``)."""
    text = ""
    for part in path:
        text += f"[{part}]" if isinstance(part, int) else (f".{part}" if text else part)
    return text


def _probe(schema, samples, parse_of, found=None) -> dict:
    """{table: the keys the validators accept there}, over ``samples`` (a table that several
    kinds of file hold, e.g. [rating] of a train and of a planetary stage, gets the union)."""
    found = {} if found is None else found
    for data in samples:
        parse = parse_of(data)
        names = schema.names
        for path in _walk(data):
            table = sr.table_path(_name(path), names)
            table = _merged(schema, table)
            if table in sr.NAMED_KEYS:
                continue
            assert table in schema.tables, f"table [{table}] missing from the reference"
            found.setdefault(table, set()).update(
                sr.NAME if k in names else sr.MESH if sr.table_path(k, names) == sr.MESH else k
                for k in _allowed(parse, data, path)
            )
    return found


def _compare(schema, found: dict) -> set:
    """Each probed table's accepted keys are the reference's keys of that table."""
    for table, allowed in found.items():
        assert allowed == set(schema.tables[table]), (
            table,
            allowed ^ set(schema.tables[table]),
        )
    return set(found)


def _check(schema, samples, parse_of):
    return _compare(schema, _probe(schema, samples, parse_of))


def _merged(schema, table):
    """``gears.<name>`` as the reference names it (``gears[]``)."""
    if table in schema.tables:
        return table
    head, _, tail = table.partition("." + sr.NAME)
    return head + "[]" + tail if head + "[]" in schema.tables else table


@pytest.fixture(scope="module")
def references():
    return sr.trace_cases()


def case_samples(train: bool):
    for data, base in sr.case_samples():
        if sr.is_train(data) == train:
            yield data, base


def test_pair_reference_holds_the_validators_keys(references):
    pair, _ = references
    samples = list(case_samples(train=False))
    by_id = {id(d): b for d, b in samples}
    seen = _check(
        pair,
        [d for d, _ in samples],
        lambda d: lambda x: jio.parse_case(x, "probe", by_id[id(d)]),
    )
    # every table of the reference was probed: none is listed that no file can hold
    assert seen == set(pair.tables) - set(sr.NAMED_KEYS), set(pair.tables) - seen


def test_train_reference_holds_the_validators_keys(references):
    _, train = references
    samples = list(case_samples(train=True))
    found: dict = {}
    for data, base in samples:
        names = sr.gear_and_shaft_names(data)
        train.names = names
        _probe(train, [data], lambda d, b=base: lambda x: jio.parse_train(x, "probe", b), found)
    _compare(train, found)
    assert {"", "gears[]", "meshes[]", "scene", "scene.shafts[]"} <= set(train.tables)


def test_body_reference_holds_the_validators_keys():
    bodies = sr.trace_bodies()
    for name in body_schema.embedded_bodies():
        data = tomllib.loads(body_schema.embedded_body_text(name))

        def parse(x):
            body_schema.parse_body(_toml(x), default_name=name)

        _check(bodies, [data], lambda d: parse)


def _toml(data) -> str:
    """A minimal TOML writer for the body files (numbers, strings, booleans, arrays, tables,
    arrays of tables): enough to write a probe back."""

    def value(v):
        if isinstance(v, bool):
            return "true" if v else "false"
        if isinstance(v, str):
            return '"' + v.replace("\\", "\\\\").replace('"', '\\"') + '"'
        if isinstance(v, list):
            return "[" + ", ".join(value(x) for x in v) + "]"
        if isinstance(v, dict):
            return "{ " + ", ".join(f'"{k}" = {value(x)}' for k, x in v.items()) + " }"
        return repr(v)

    lines, tables = [], []
    for k, v in data.items():
        if isinstance(v, dict):
            tables.append((f"[{k}]", v))
        elif isinstance(v, list) and v and all(isinstance(x, dict) for x in v):
            tables += [(f"[[{k}]]", x) for x in v]
        else:
            lines.append(f'"{k}" = {value(v)}')
    for head, t in tables:
        lines.append(head)
        lines += [f'"{k}" = {value(x)}' for k, x in t.items()]
    return "\n".join(lines) + "\n"


def test_reference_pages_list_every_key(references):
    """The generated markdown has a row per key of each table, its heading per table."""
    pair, _ = references
    page = sr.markdown(pair, "t", "")
    for table, keys in pair.tables.items():
        assert f"## `{sr.heading(table)}`" in page
        if table not in sr.NAMED_KEYS:
            for key in keys:
                assert f"| `{key}` |" in page, (table, key)


def test_every_key_says_what_it_allows(references):
    """No row of the references is empty: each key has a type (number, integer, string, table,
    …) or the validator's own words for what it allows (a key checked by its table's code, such
    as a train gear's ``hand``: 'right', 'left')."""
    for schema in (*references, sr.trace_bodies()):
        for table, keys in schema.tables.items():
            for key, info in keys.items():
                assert info.kind or info.allowed, (table, key)
    _, train = references
    assert train.tables["gears[]"]["hand"].allowed == {"'right', 'left'"}


@pytest.mark.parametrize(
    "key, printed",
    [
        ("viscosity_40C_mm2_s", "mm²/s"),
        ("mesh_stiffness_N_per_um", "N/µm"),
        ("torsional_stiffness_Nm_per_rad", "N·m/rad"),
        ("c_N_per_mm_per_um", "N/mm/µm"),
        ("damping_per_s", "1/s"),
        ("inertia_kg_m2", "kg·m²"),
        ("density_kg_m3", "kg/m³"),
        ("speed_rad_s", "rad/s"),
        ("face_width_mm", "mm"),
        ("life_h", "h"),
        ("teeth", ""),
        ("min_safety_pitting", ""),
    ],
)
def test_units_are_read_from_the_whole_suffix(key, printed):
    """A key's unit is the run of unit words at its end (a compound unit whole: mm²/s, not the
    last word's s)."""
    assert sr.unit(key) == printed


def test_train_reference_says_k_gamma_is_for_planetary_stages():
    assert "planetary stages only" in sr.TRAIN_NOTES["rating"]


def test_committed_reference_pages_are_the_validators():
    """docs/reference/{case,train,gearbox,body}-file.md are committed (the docs link to them in
    the repository, not only on the built site) and must be what the validators declare today:
    after a change to a validator, ``python -m docs._gen.schema_reference docs/reference``."""
    folder = sr.ROOT / "docs" / "reference"
    for name, text in sr.pages().items():
        committed = (folder / name).read_text(encoding="utf-8")
        assert committed == text, (
            f"docs/reference/{name} is stale: run python -m docs._gen.schema_reference "
            "docs/reference"
        )
