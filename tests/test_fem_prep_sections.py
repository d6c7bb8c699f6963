"""The body file's and the ring-gear file's tables as typed sections (fem_prep.sections): an
unknown key, a table given as a number, a string or an array, and a wrong value each give the
one line of fem_prep.checks naming the key, its value as written and what is allowed (the
messages written out here by hand), never a TypeError or pydantic's many-line report."""

import tomllib

import pytest

from fem_prep import checks, embedded_ring_text, schema

BODY = schema.embedded_body_text("accessory-wheel")  # rim 9.5 mm wide, web 3 mm thick


def _ring_text() -> str:
    return embedded_ring_text("seq-test-ring")


def _toml(data: dict) -> str:
    """A minimal TOML writer for these files (numbers, strings, booleans, arrays, tables)."""

    def value(v):
        if isinstance(v, bool):
            return "true" if v else "false"
        if isinstance(v, str):
            return '"' + v + '"'
        if isinstance(v, list):
            return "[" + ", ".join(value(x) for x in v) + "]"
        if isinstance(v, dict):
            return "{ " + ", ".join(f"{k} = {value(x)}" for k, x in v.items()) + " }"
        return str(v)

    lines = [f"{k} = {value(v)}" for k, v in data.items()]
    return "\n".join(lines) + "\n"


def _error(parse, data: dict) -> str:
    with pytest.raises(checks.SchemaError) as info:
        parse(_toml(data))
    msg = str(info.value)
    assert "\n" not in msg and len(msg) < 400
    return msg


def _tables(data):
    """(path, table) of every table of a parsed file; an array of tables' entries by index."""
    yield (), data
    for key, v in data.items():
        if isinstance(v, dict):
            yield from (((key, *p), t) for p, t in _tables(v))
        elif isinstance(v, list) and v and all(isinstance(x, dict) for x in v):
            for i, x in enumerate(v):
                yield from (((key, i, *p), t) for p, t in _tables(x))


def _where(path) -> str:
    text = ""
    for p in path:
        text += f"[{p}]" if isinstance(p, int) else (f".{p}" if text else p)
    return text


@pytest.mark.parametrize("kind", ["body", "ring"])
def test_unknown_key_in_every_table_is_named(kind):
    """A key no table declares, put into each table of an embedded file, is refused naming it
    and its table (the file's words: ``[mesh] unknown key 'zz_not_a_key', allowed: ...``)."""
    parse, text = (schema.parse_body, BODY) if kind == "body" else (schema.parse_ring_body,
                                                                    _ring_text())
    data = tomllib.loads(text)
    seen = 0
    for path, _ in list(_tables(data)):
        bad = tomllib.loads(text)
        t = bad
        for p in path:
            t = t[p]
        t["zz_not_a_key"] = 1.0
        msg = _error(parse, bad)
        head = f"[{_where(path)}] " if path else ""
        assert msg.startswith(f"{head}unknown key 'zz_not_a_key', allowed: "), msg
        seen += 1
    assert seen >= (7 if kind == "body" else 5)


def test_misspelt_key_is_reported_before_what_it_leaves_missing():
    """A misspelt required key: the unknown key with its closest allowed name, not the missing
    key it leaves (the table's keys are checked first)."""
    data = tomllib.loads(BODY)
    data["body"]["bore_radius"] = data["body"].pop("bore_radius_mm")
    msg = _error(schema.parse_body, data)
    assert msg.startswith("[body] unknown key 'bore_radius' (did you mean 'bore_radius_mm'?), "
                          "allowed: bore_radius_mm, holes, hub_outer_radius_mm, ")


@pytest.mark.parametrize("value, what", [(3, "a number"), ("x", "a string"), ([1.0], "an array"),
                                         (True, "a boolean")])
def test_a_table_given_as_a_value_is_one_line(value, what):
    """Each table of a body and a ring file given as a value (a number, a string, an array, a
    boolean): one line naming it, never a TypeError."""
    shown = checks.fmt(value)
    for key in ("body", "material", "mesh", "condensation", "centrifugal", "modal", "pinion_rim"):
        data = tomllib.loads(BODY) | {key: value}
        assert _error(schema.parse_body, data) == (
            f"{key} = {shown}: must be a table ([{key}]), not {what}")
    data = tomllib.loads(BODY)
    data["body"]["holes"] = value
    assert _error(schema.parse_body, data) == (
        f"[body] holes = {shown}: must be a table ([body.holes]), not {what}")
    data = tomllib.loads(BODY) | {"bearings": [value]}
    assert _error(schema.parse_body, data) == (
        f"'bearings[0]' = {shown}: must be a table ([[bearings]] entry), not {what}")
    for key in ("ring", "support", "material", "mesh", "condensation"):
        data = tomllib.loads(_ring_text()) | {key: value}
        assert _error(schema.parse_ring_body, data) == (
            f"{key} = {shown}: must be a table ([{key}]), not {what}")


def test_missing_tables_and_bearings():
    data = tomllib.loads(BODY)
    del data["body"]
    assert _error(schema.parse_body, data) == "[body]: missing required table"
    for bearings in ([], 3):
        data = tomllib.loads(BODY) | {"bearings": bearings}
        assert _error(schema.parse_body, data) == (
            "[[bearings]]: at least one [[bearings]] table is required (axial_position_mm, "
            "coupling)")
    for key in ("ring", "support", "condensation"):
        data = tomllib.loads(_ring_text())
        del data[key]
        assert _error(schema.parse_ring_body, data) == f"[{key}]: missing required table"


@pytest.mark.parametrize(
    "table, key, value, message",
    [
        ("mesh", "size_mm", 0.0, "[mesh] size_mm = 0: out of range, allowed [0.001, 1e+06]"),
        ("mesh", "size_mm", True, "[mesh] size_mm = true: must be a number, not a boolean"),
        ("mesh", "size_mm", float("nan"), "[mesh] size_mm = nan: must be a finite number"),
        ("mesh", "element", "tet10", "[mesh] element = 'tet10': allowed 'hex20', 'hex27'"),
        ("condensation", "modes", 50.5, "[condensation] modes = 50.5: must be an integer"),
        ("condensation", "modes", 2001,
         "[condensation] modes = 2001: out of range, allowed [0, 2000] (the seed: 50)"),
        ("condensation", "teeth", "86",
         "[condensation] teeth = '86': must be an integer, not a string"),
        ("centrifugal", "spin_softening", 1, "[centrifugal] spin_softening = 1: must be true or false"),
        ("modal", "vtu_modes", 21,
         "[modal] vtu_modes = 21: out of range, allowed [0, 20] (<= n_frequencies)"),
        ("body", "rim_width_mm", 10**400,
         "[body] rim_width_mm = 1e+400: out of range, allowed [0.001, 1e+06]"),
        ("body", "web_offset_mm", -1e300,
         ("[body] web_offset_mm = -1e+300: out of range, allowed [-3.25, 3.25] (the web inside "
          "the rim: |offset| <= (rim_width - web_thickness)/2)")),
    ],
)
def test_wrong_values_in_the_files_words(table, key, value, message):
    data = tomllib.loads(BODY)
    data.setdefault(table, {})[key] = value
    assert _error(schema.parse_body, data) == message


def test_integral_floats_are_integers_and_the_spec_unchanged():
    """``modes = 50.0`` is the integer 50: the same body, the same cache key."""
    data = tomllib.loads(BODY)
    data["condensation"]["modes"] = 50.0
    data["condensation"]["teeth"] = float(data["condensation"]["teeth"])
    body = schema.parse_body(_toml(data))
    ref = schema.parse_body(BODY)
    assert type(body.condensation.modes) is int and body.condensation.modes == 50
    assert body == ref and body.sha256 == ref.sha256


def test_ring_support_needs_its_kinds_keys():
    data = tomllib.loads(_ring_text())
    data["support"] = {"kind": "elastic_foundation", "radial_N_per_mm3": 1.0,
                       "axial_N_per_mm3": 1.0}
    assert _error(schema.parse_ring_body, data) == (
        "[support] tangential_N_per_mm3: missing required key")
    data["support"] = {"kind": "bolted_flange", "seat_arc_mm": 5.0}
    assert _error(schema.parse_ring_body, data) == "[support] bolts: missing required key"
    data["support"] = {"kind": "glued"}
    assert _error(schema.parse_ring_body, data) == (
        "[support] kind = 'glued': allowed 'bolted_flange', 'elastic_foundation', 'free'")
