"""Whole-file validation before any work: one schema mechanism (fem_prep.schema) for
case files ([scene], [optimise] included) and body files; one-line errors in file units; one
integer rule; plausibility warnings; fuzzing; the CLI exits 2 without writing anything."""

from __future__ import annotations

import copy
import datetime
import importlib.resources
import json
import math
import os
import random
import re
import tomllib
import warnings

import pytest

import jaxgear.io as jio
from fem_prep import parse_body
from fem_prep.schema import SchemaError

CASE_TEXT = (importlib.resources.files("jaxgear") / "cases" / "accessory-spur.toml").read_text(
    "utf-8"
) + (
    "\n[optimise]\n"
    'objective = "robust_te_rms"\n'
    'vars = ["tip_relief.depth", "tip_relief.extent"]\n'
    "torques = [40.0, 120.0, 5]\n"
    'reduce = "max"\n'
    'method = "lbfgs"\n'
    "max_iterations = 50\n"
    "bounds = { 'tip_relief.depth' = [0.0, 2.5] }\n"
)
BODY_TEXT = (importlib.resources.files("fem_prep") / "bodies" / "accessory-wheel.toml").read_text(
    "utf-8"
)


def _case(**changes):
    """The base case dict with ``{"section.key": value}`` changes (value None deletes)."""
    d = tomllib.loads(CASE_TEXT)
    for path, value in changes.items():
        *tables, key = path.split("/")
        t = d
        for name in tables:
            t = t[name]
        if value is None:
            del t[key]
        else:
            t[key] = value
    return d


def _error(data) -> str:
    with pytest.raises(SchemaError) as info:
        jio.parse_case(data)
    msg = str(info.value)
    assert "\n" not in msg and isinstance(info.value, ValueError)
    return msg


_DECIMAL = re.compile(r"(?<![\w.'])-?(\d+\.\d+|\d+)(?:e[-+]?\d+)?(?![\w'])")


def _max_significant_digits(msg: str) -> int:
    digits = [len(m.group(1).replace(".", "").lstrip("0")) for m in _DECIMAL.finditer(msg)]
    return max(digits, default=0)


# ---------------------------------------------------------------------------------------------
# (b) messages: key path, value in file units, allowed range, <= 6 significant digits


def test_base_case_with_optimise_table_is_valid_and_normalised():
    case = jio.parse_case(tomllib.loads(CASE_TEXT))
    assert case.optimise == {
        "objective": "robust_te_rms",
        "reduce": "max",
        "method": "lbfgs",
        "max_iterations": 50,
        "vars": ["tip_relief.depth", "tip_relief.extent"],
        "torques": [40.0, 120.0, 5],
        "bounds": {"tip_relief.depth": (0.0, 2.5)},
    }
    from jaxgear.cli import range_values, settings_from_case

    s = settings_from_case(case)
    assert list(range_values(s["torques"], "--torques")) == [40.0, 60.0, 80.0, 100.0, 120.0]
    assert s["bounds"] == {"tip_relief.depth": (0.0, 2.5)}


@pytest.mark.parametrize(
    "changes,expected",
    [
        (
            {"pinion/face_width_mm": -3.0},
            "[pinion] face_width_mm = -3: out of range, allowed > 0",
        ),
        (
            {"pair/normal_pressure_angle_deg": 50.0},
            "[pair] normal_pressure_angle_deg = 50: out of range, allowed [10, 40]",
        ),
        (
            {"pair/normal_pressure_angle_deg": 45.123456789},
            "[pair] normal_pressure_angle_deg = 45.1235: out of range, allowed [10, 40]",
        ),
        (
            {"pair/helix_angle_deg": -5},
            "[pair] helix_angle_deg = -5: out of range, allowed [0, 45)",
        ),
        (
            {"modifications/tip_relief": {"depth_um": -2.5}},
            "[modifications.tip_relief] depth_um = -2.5: out of range, allowed [0, 1500] (µm; "
            "up to 1 × normal_module_mm)",
        ),
        (
            {"modifications/crowning": {"depth_um": "3"}},
            "[modifications.crowning] depth_um = '3': must be a number, not a string",
        ),
        ({"pinion/teeth": 45.5}, "[pinion] teeth = 45.5: must be an integer"),
        ({"pinion/teeth": True}, "[pinion] teeth = true: must be an integer, not a boolean"),
        ({"gear/teeth": 4}, "[gear] teeth = 4: out of range, allowed [5, 10000]"),
        ({"mesh/slices": 0.0}, "[mesh] slices = 0: out of range, allowed [1, 10000]"),
        ({"mesh/slices": float("nan")}, "[mesh] slices = nan: must be a finite integer"),
        (
            {"operating/torque_Nm": float("inf")},
            "[operating] torque_Nm = inf: must be a finite number",
        ),
        ({"pinion/teeth": None}, "[pinion] teeth: missing required key"),
        ({"operating": None}, "[operating]: missing required table"),
        ({"pinion": 3}, "pinion = 3: must be a table ([pinion]), not a number"),
        (
            {"mesh/foundation": 1},
            (
                "[mesh] foundation = 1: allowed 'weber', 'sainsot', 'none' (or true = 'weber', "
                "false = 'none')"
            ),
        ),
        (
            {"mesh/foundation": "winkler"},
            (
                "[mesh] foundation = 'winkler': allowed 'weber', 'sainsot', 'none' (or true = "
                "'weber', false = 'none')"
            ),
        ),
        ({"pinion/bore_radius_mm": 0}, "[pinion] bore_radius_mm = 0: out of range, allowed > 0"),
        (
            {"mesh/stiffness": "fem"},
            "[mesh] stiffness = 'fem': allowed 'weber', 'uniform', 'iso6336', 'fe2d'",
        ),
        (
            {"material/poisson_ratio": 0.5},
            "[material] poisson_ratio = 0.5: out of range, allowed [0, 0.5)",
        ),
        (
            {"pair/center_distance_mm": 99.0},
            (
                "[pair] center_distance_mm = 99: out of range, allowed >= 99.450 mm (the "
                "zero-backlash distance, to 1 µm; closer, the teeth jam)"
            ),
        ),
        (
            {"scene/integration": {"step_per_period": 16}},
            (
                "[scene.integration] unknown key 'step_per_period' (did you mean 'steps_per_period'?), "
                "allowed: atol, contact, keep_periods, modal_basis, periods, rotating_frame, rtol, solver, steps_per_period"
            ),
        ),
        (
            {"scene/pinion_shaft/gear_position_mm": 500.0},
            (
                "[scene.pinion_shaft] gear_position_mm = 500: out of range, allowed [0, 100] (not "
                "beyond the shaft length)"
            ),
        ),
        (
            {"scene/damping": {"ratio": 2}},
            "[scene.damping] ratio = 2: out of range, allowed [0, 1]",
        ),
        (
            {"optimise/objective": "te_max"},
            (
                "[optimise] objective = 'te_max': allowed 'te_rms', 'te_ptp', 'robust_te_rms', "
                "'max_line_load', 'load_centroid', 'line_load_lp', 'dynamic_factor', "
                "'least_safety', 'power_loss', 'efficiency_loss', 'min_specific_film', "
                "'max_flash_temperature', 'erp', 'sound_power'"
            ),
        ),
        (
            {"optimise/torques": [120.0, 40.0, 5]},
            (
                "[optimise] torques = [120, 40, 5]: allowed [start, stop, n] in N·m with 0 < start < "
                "stop and an integer n in [2, 10000]"
            ),
        ),
        (
            {"optimise/max_iterations": 0},
            "[optimise] max_iterations = 0: out of range, allowed [1, 1e+06]",
        ),
        ({"optimise/method": "bfgs"}, "[optimise] method = 'bfgs': allowed 'lbfgs', 'adam'"),
    ],
)
def test_error_messages_name_key_value_in_file_units_and_range(changes, expected):
    msg = _error(_case(**changes))
    assert msg == expected
    assert _max_significant_digits(msg) <= 6, msg


def test_unknown_optimise_variable_and_bounds():
    msg = _error(_case(**{"optimise/vars": ["tip_relief.dpeth"]}))
    assert msg.startswith(
        "[optimise] vars = ['tip_relief.dpeth']: unknown variable 'tip_relief.dpeth'"
    )
    assert "optionally prefixed 'pinion.' or 'gear.'" in msg
    ok = jio.parse_case(
        _case(
            **{
                "optimise/vars": ["pinion.tip_relief.depth", "crowning.depth"],
                "optimise/bounds": None,
            }
        )
    )
    assert ok.optimise["vars"] == ["pinion.tip_relief.depth", "crowning.depth"]
    msg = _error(_case(**{"optimise/bounds": {"tip_relief.extent": [0.5, 0.2]}}))
    assert msg.startswith("[optimise.bounds] tip_relief.extent = [0.5, 0.2]: out of range")
    msg = _error(_case(**{"optimise/objective": "te_rms"}))
    assert msg.startswith(
        "[optimise] torques = [40, 120, 5]: applies to objective = 'robust_te_rms'"
    )
    msg = _error(_case(**{"optimise/bounds": {"crowning.depth": [0.0, 1.0]}}))
    assert "is not a design variable" in msg


def test_geometry_errors_are_in_file_units():
    msg = _error(
        _case(**{"pinion/teeth": 12, "pinion/addendum_coeff": 1.6, "pinion/profile_shift": 0.6})
    )
    assert msg.startswith("[pinion] addendum_coeff = 1.6: out of range (tip thickness")
    assert "pointed tooth" in msg and " mm" in msg and _max_significant_digits(msg) <= 6
    msg = _error(_case(**{"pinion/addendum_coeff": 0.3, "gear/addendum_coeff": 0.3}))
    assert "total contact ratio ε_γ = " in msg and ">= 1" in msg
    msg = _error(_case(**{"pinion/fillet_radius_coeff": 1.5}))
    assert (
        msg
        == "[pinion] fillet_radius_coeff = 1.5: out of range, allowed [0, 1.1933) (below dedendum_coeff)"
    )


def test_integer_rule_is_one_rule_for_case_and_body_files():
    case = jio.parse_case(_case(**{"mesh/slices": 4.0, "pinion/teeth": 45.0}))
    assert case.slices == 4 and type(case.slices) is int
    assert case.pair.pinion.teeth == 45 and type(case.pair.pinion.teeth) is int
    assert _error(_case(**{"pinion/teeth": 45.5})) == "[pinion] teeth = 45.5: must be an integer"
    body = parse_body(BODY_TEXT.replace("modes = 50", "modes = 50.0"))
    assert body.condensation.modes == 50 and type(body.condensation.modes) is int
    with pytest.raises(SchemaError, match=r"^\[condensation\] modes = 50.5: must be an integer$"):
        parse_body(BODY_TEXT.replace("modes = 50", "modes = 50.5"))
    with pytest.raises(SchemaError, match=r"^\[condensation\] teeth = true: must be an integer"):
        parse_body(BODY_TEXT.replace("teeth = 86", "teeth = true"))


def test_body_messages_in_file_units():
    with pytest.raises(SchemaError) as info:
        parse_body(BODY_TEXT.replace("bore_radius_mm = 15.0", "bore_radius_mm = 30.0"))
    assert str(info.value) == (
        "[body] bore_radius_mm = 30: out of range, allowed (0, 22) (below hub_outer_radius_mm)"
    )
    with pytest.raises(
        SchemaError, match=r"^\[body\] web_inclination_deg = 75: out of range, allowed \(-60, 60\)$"
    ):
        parse_body(BODY_TEXT.replace("web_inclination_deg = 0.0", "web_inclination_deg = 75.0"))
    with pytest.raises(
        SchemaError, match=r"^\[bearings\[1\]\] coupling = 'glue': allowed 'rigid', 'averaging'$"
    ):
        head, sep, tail = BODY_TEXT.rpartition('coupling = "rigid"')  # the second bearing
        assert sep
        parse_body(head + 'coupling = "glue"' + tail)
    with pytest.raises(
        SchemaError, match=r"^\[mesh\] unknown key 'sise_mm' \(did you mean 'size_mm'\?\)"
    ):
        parse_body(BODY_TEXT.replace("size_mm = 3.5", "sise_mm = 3.5"))


def test_toml_syntax_and_encoding_errors_name_the_file(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text("[pair\nnormal_module_mm = 1")
    with pytest.raises(SchemaError) as info:
        jio.load_case(bad)
    assert str(info.value).startswith(f"case file {str(bad)!r} is not valid TOML:")
    bad.write_bytes(CASE_TEXT.encode().replace(b"accessory-spur", b"accessory-\xff\xfe"))
    with pytest.raises(SchemaError, match="is not valid UTF-8 text"):
        jio.load_case(bad)
    body = tmp_path / "wheel.toml"
    body.write_bytes(b"\xff" + BODY_TEXT.encode())
    from fem_prep import load_body

    with pytest.raises(
        SchemaError, match=f"^body file {re.escape(repr(str(body)))} is not valid UTF-8"
    ):
        load_body(body)


# ---------------------------------------------------------------------------------------------
# (c) plausibility warnings


def _warnings(data) -> list[str]:
    with pytest.warns(jio.CaseWarning) as record:
        jio.parse_case(data)
    msgs = [str(w.message) for w in record if issubclass(w.category, jio.CaseWarning)]
    assert all("\n" not in m for m in msgs)
    return msgs


def test_embedded_cases_are_plausible():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        for name in jio.list_cases():
            assert jio.plausibility(jio.load_case(name)) == []


def test_relief_far_deeper_than_the_mean_deflection_warns():
    (msg,) = _warnings(_case(**{"modifications/tip_relief": {"depth_um": 500.0}}))
    assert msg.startswith("[modifications] tip_relief.depth_um = 500: ")
    assert "× the mean static deflection" in msg and "more than 10 ×" in msg
    d = _case()
    d["modifications"]["pinion"] = {"crowning": {"depth_um": 400.0}}
    (msg,) = _warnings(d)
    assert msg.startswith("[modifications.pinion] crowning.depth_um = 400: ")


def test_tiny_torque_warns():
    msgs = _warnings(_case(**{"operating/torque_Nm": 1e-4}))
    assert any(
        m.startswith("[operating] torque_Nm = 0.0001: mean static deflection")
        and "below 0.01 µm" in m
        for m in msgs
    )


def test_line_load_beyond_steel_warns():
    msgs = _warnings(_case(**{"operating/torque_Nm": 3000.0}))
    assert any(
        m.startswith("[operating] torque_Nm = 3000: line load F_n/b = ")
        and "beyond what steel teeth carry" in m
        for m in msgs
    )


def test_absurd_torque_blames_the_torque_not_the_geometry():
    msg = _error(_case(**{"operating/torque_Nm": 1e9}))
    assert msg.startswith("[operating] torque_Nm = 1e+09: the line load F_n/b = ")
    assert "tooth geometry" not in msg and _max_significant_digits(msg) <= 6


# ---------------------------------------------------------------------------------------------
# (a) fuzzing: nothing but a Case or a one-line SchemaError


_VALUES = [
    -1.0,
    0.0,
    -0.0,
    0.5,
    45.5,
    4.0,
    1e300,
    -1e300,
    1e-300,
    float("nan"),
    float("inf"),
    float("-inf"),
    0,
    1,
    -7,
    3,
    10**30,
    True,
    False,
    "",
    "abc",
    "1.5",
    "linear",
    [],
    [1, 2],
    [1.0, "a"],
    [{"a": 1}],
    [40.0, 120.0, 5.0],
    {},
    {"x": 1},
    {"depth_um": 1e6},
    datetime.date(2020, 1, 1),
]
_NEW_KEYS = ["slice", "face_widht_mm", "x", "a.b", "ünïcode", "", "depth", "position_mm", "model"]


def _paths(node, prefix=()):
    """Every (container, key) in a parsed TOML tree (dicts and lists of dicts)."""
    if isinstance(node, dict):
        for k, v in node.items():
            yield node, k
            yield from _paths(v, prefix + (k,))
    elif isinstance(node, list):
        for i, v in enumerate(node):
            yield node, i
            yield from _paths(v, prefix + (i,))


def _tables(node):
    if isinstance(node, dict):
        yield node
        for v in node.values():
            yield from _tables(v)
    elif isinstance(node, list):
        for v in node:
            yield from _tables(v)


def _mutate(data, rng: random.Random) -> str:
    """Apply 1-3 random mutations in place; return a description."""
    done = []
    for _ in range(rng.randint(1, 3)):
        kind = rng.choice(["delete", "replace", "scale", "integral", "unknown"])
        paths = list(_paths(data))
        if kind == "unknown":
            t = rng.choice(list(_tables(data)))
            k = rng.choice(_NEW_KEYS)
            t[k] = rng.choice(_VALUES)
            done.append(f"add {k!r}")
            continue
        if not paths:
            continue
        node, key = rng.choice(paths)
        v = node[key]
        if kind == "delete":
            del node[key]
        elif kind == "replace":
            node[key] = copy.deepcopy(rng.choice(_VALUES))
        elif kind == "scale" and isinstance(v, (int, float)) and not isinstance(v, bool):
            node[key] = v * rng.choice([-1, 0, 1e6, 1e-6, 1e300, 10, 0.1])
        elif kind == "integral" and isinstance(v, (int, float)) and not isinstance(v, bool):
            node[key] = rng.choice([float(v), v + 0.5, int(v) if math.isfinite(v) else 0])
        done.append(f"{kind} {key!r}")
    return ", ".join(done)


def _insert_bytes(raw: bytes, rng: random.Random) -> bytes:
    i = rng.randrange(len(raw))
    kind = rng.choice(["insert", "replace", "delete", "toml"])
    if kind == "insert":
        return raw[:i] + rng.randbytes(rng.randint(1, 8)) + raw[i:]
    if kind == "replace":
        return raw[:i] + rng.randbytes(1) + raw[i + 1 :]
    if kind == "delete":
        return raw[:i] + raw[i + rng.randint(1, 20) :]
    return (
        raw[:i] + rng.choice([b"[", b"]", b"=", b'"', b"\n", b"{", b",", b"#", b"\x00"]) + raw[i:]
    )


def _dump(value) -> str:
    """A TOML value (inline form)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if math.isnan(value):
            return "nan"
        return ("inf" if value > 0 else "-inf") if math.isinf(value) else repr(value)
    if isinstance(value, str):
        return json.dumps(value)
    if isinstance(value, list):
        return "[" + ", ".join(_dump(v) for v in value) + "]"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{json.dumps(str(k))} = {_dump(v)}" for k, v in value.items()) + "}"
    return value.isoformat()


def _dumps(data: dict) -> str:
    return "".join(f"{json.dumps(str(k))} = {_dump(v)}\n" for k, v in data.items())


def _outcome(fn, what: str, check_digits: bool) -> str:
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            fn()
        except SchemaError as err:
            msg = str(err)
            assert msg and "\n" not in msg, (what, msg)
            if check_digits:
                assert _max_significant_digits(msg.split(": allowed")[0]) <= 6 or "'" in msg, (
                    what,
                    msg,
                )
            return "error"
        except BaseException as err:  # anything else is a bug: say which mutation
            raise AssertionError(f"{what}: {type(err).__name__}: {err}") from err
    for w in caught:
        assert issubclass(w.category, jio.CaseWarning), (what, w.category, str(w.message))
        assert "\n" not in str(w.message)
    return "ok"


def test_fuzz_case_files(tmp_path):
    rng = random.Random(20240608)
    base = tomllib.loads(CASE_TEXT)
    counts = {"ok": 0, "error": 0}
    for i in range(850):
        data = copy.deepcopy(base)
        what = f"case mutation {i}: {_mutate(data, rng)}"
        counts[_outcome(lambda data=data: jio.parse_case(data), what, True)] += 1
    raw = CASE_TEXT.encode()
    path = tmp_path / "fuzz.toml"
    for i in range(200):
        mutated = raw
        for _ in range(rng.randint(1, 3)):
            mutated = _insert_bytes(mutated, rng)
        path.write_bytes(mutated)
        counts[_outcome(lambda: jio.load_case(path), f"byte mutation {i}: {mutated!r}", False)] += 1
    assert sum(counts.values()) >= 1000
    assert counts["ok"] >= 100 and counts["error"] >= 300, counts


def test_fuzz_body_files(tmp_path):
    rng = random.Random(86)
    base = tomllib.loads(BODY_TEXT)
    counts = {"ok": 0, "error": 0}
    for i in range(300):
        data = copy.deepcopy(base)
        what = f"body mutation {i}: {_mutate(data, rng)}"
        counts[_outcome(lambda data=data: parse_body(_dumps(data)), what, True)] += 1
    from fem_prep import load_body

    path = tmp_path / "fuzz.toml"
    for i in range(100):
        path.write_bytes(_insert_bytes(BODY_TEXT.encode(), rng))
        counts[_outcome(lambda: load_body(path), f"body byte mutation {i}", False)] += 1
    assert counts["ok"] >= 30 and counts["error"] >= 100, counts


# ---------------------------------------------------------------------------------------------
# (d) the CLI: exit 2, one line, nothing written


@pytest.mark.parametrize(
    "edit,needle",
    [
        (("face_width_mm = 11.5", "face_width_mm = -3.0"), "[pinion] face_width_mm = -3"),
        (("[scene.integration]", "[scene.integration]\nstep_per_period = 8"), "'step_per_period'"),
        (('objective = "robust_te_rms"', 'objective = "te_max"'), "[optimise] objective"),
        (("torque_Nm = 80.0", "torque_Nm = 1e9"), "[operating] torque_Nm = 1e+09"),
        (("teeth = 45", "teeth = 45.5"), "[pinion] teeth = 45.5: must be an integer"),
        (("[pair]", "[pair"), "is not valid TOML"),
        (("accessory-spur", "accessory-\udcff"), "is not valid UTF-8"),
    ],
)
def test_cli_rejects_bad_files_before_any_work(tmp_path, capsys, edit, needle):
    from jaxgear.cli import main

    bad = tmp_path / "bad.toml"
    text = CASE_TEXT.replace(*edit)
    assert text != CASE_TEXT
    bad.write_bytes(text.encode("utf-8", "surrogateescape"))
    out = tmp_path / "o"
    assert main(["run", str(bad), "--out", str(out), "--quiet"]) == 2
    err = capsys.readouterr().err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("jaxgear: error: "), err
    assert needle in lines[0], err
    assert "Traceback" not in err
    # no output: the --out check creates nothing, validation runs before any work
    assert not out.exists()
    assert sorted(p.name for p in tmp_path.iterdir() if p.is_file()) == ["bad.toml"]


# ---------------------------------------------------------------------------------------------
# (e) extremes, names, culprits, late checks, centre distance, absurd physics

FLEXIBLE = tomllib.loads(
    (importlib.resources.files("jaxgear") / "cases" / "accessory-spur-flexible.toml").read_text(
        "utf-8"
    )
)


@pytest.mark.parametrize(
    "changes,expected",
    [
        (
            {"material/youngs_modulus_GPa": 5e-324},
            "[material] youngs_modulus_GPa = 4.94066e-324: out of range, allowed [0.1, 10000]",
        ),
        ({"pinion/teeth": 10**400}, "[pinion] teeth = 1e+400: out of range, allowed [5, 10000]"),
        (
            {"operating/torque_Nm": -(10**400)},
            "[operating] torque_Nm = -1e+400: out of range, allowed >= 2.91e-07 (a line load "
            "F_n/b of 1e-06 N/mm on this pair)",
        ),
        (
            {"operating/torque_Nm": 10**400},
            "[operating] torque_Nm = 1e+400: out of range (beyond ±1.79769e+308), "
            "allowed >= 2.91e-07 (a line load F_n/b of 1e-06 N/mm on this pair)",
        ),
        (
            {"optimise/torques": [40.0, 10**400, 5]},
            (
                "[optimise] torques = [40, 1e+400, 5]: allowed [start, stop, n] in N·m with 0 < start "
                "< stop and an integer n in [2, 10000]"
            ),
        ),
        (
            {"pinion/dedendum_coeff": 0.2, "pinion/fillet_radius_coeff": None},
            (
                "[pinion] dedendum_coeff = 0.2: out of range, allowed > 0.25 (above the default "
                "fillet_radius_coeff; or give a smaller fillet_radius_coeff)"
            ),
        ),
        # the culprit, not a downstream quantity
        (
            {"pinion/face_width_mm": 1e-9},
            "[pinion] face_width_mm = 1e-09: out of range, allowed [0.15, 150] (0.1 to 100 × "
            "normal_module_mm)",
        ),
        (
            {"pair/normal_pressure_angle_deg": 1.0},
            "[pair] normal_pressure_angle_deg = 1: out of range, allowed [10, 40]",
        ),
        (
            {"pair/normal_module_mm": 1e308},
            "[pair] normal_module_mm = 1e+308: out of range, allowed [0.01, 100]",
        ),
        (
            {"mesh/smooth_width_um": 1e6},
            (
                "[mesh] smooth_width_um = 1e+06: out of range, allowed [0.0001, 15] (µm; up to 1 % of "
                "the normal module)"
            ),
        ),
        (
            {"mesh/stiffness": "fe2d", "mesh/stiffness_per_length_N_per_mm_per_um": 13.0},
            (
                "[mesh] stiffness_per_length_N_per_mm_per_um = 13: belongs to stiffness = 'uniform', "
                "not 'fe2d' (remove it or change the model)"
            ),
        ),
        (
            {
                "mesh/stiffness": "uniform",
                "mesh/stiffness_per_length_N_per_mm_per_um": 13.0,
                "mesh/foundation": "sainsot",
            },
            (
                "[mesh] foundation = 'sainsot': belongs to stiffness = 'weber' or 'fe2d', not "
                "'uniform' (remove it or change the model)"
            ),
        ),
        (
            {"mesh/fe2d_size_um": 250.0},
            (
                "[mesh] fe2d_size_um = 250: belongs to stiffness = 'fe2d', not 'weber' (remove it or "
                "change the model)"
            ),
        ),
    ],
)
def test_extremes_and_culprits_give_one_line_naming_the_key(changes, expected):
    assert _error(_case(**changes)) == expected


def test_integers_beyond_the_toml_reader_and_float_range_in_files(tmp_path):
    path = tmp_path / "huge.toml"
    path.write_text(CASE_TEXT.replace("teeth = 45", "teeth = " + "9" * 5000))
    with pytest.raises(SchemaError, match=r"^case file .* is not valid TOML: Exceeds the limit"):
        jio.load_case(path)
    path.write_text(CASE_TEXT.replace("teeth = 45", "teeth = " + "9" * 400))
    with pytest.raises(SchemaError, match=r"^\[pinion\] teeth = 1e\+400: out of range"):
        jio.load_case(path)


@pytest.mark.parametrize("name", ["../x", "/tmp/x", "..", "a/b", "a b", "-x", ".hidden", ""])
def test_a_name_is_a_name_not_a_path(name, tmp_path):
    msg = _error({**_case(), "name": name})
    assert msg.startswith(f"name = {name!r}: ")
    if name.strip():
        assert "a name, not a path: 1 to 100 letters, digits, '-', '_', '.' allowed" in msg
    body = BODY_TEXT.replace('name = "accessory-wheel"', f"name = {json.dumps(name)}")
    with pytest.raises(SchemaError, match=re.escape(f"name = {name!r}: ")):
        parse_body(body)
    assert jio.parse_case({**_case(), "name": "my-pair_2.v1"}).name == "my-pair_2.v1"


def test_clear_outputs_deletes_only_what_a_run_wrote(tmp_path):
    from fem_prep.schema import atomic_open
    from jaxgear.cli import clear_outputs

    out = tmp_path / "out"
    out.mkdir()
    (out / "te.csv").write_text("the user's own file with an output name")
    (out / "notes.txt").write_text("mine")
    assert clear_outputs(out, "run") == []  # no list of an earlier run: nothing is deleted
    assert (out / "te.csv").read_text().startswith("the user's")
    for name in ("summary.json", "sweep/sweep.json"):  # this run writes two files
        (out / name).parent.mkdir(exist_ok=True)
        with atomic_open(out / name) as f:
            f.write("{}")
    assert (out / ".jaxgear-outputs").read_text().splitlines()[1:] == [
        "summary.json",
        "sweep/sweep.json",
    ]
    removed = clear_outputs(out, "run")  # the next run deletes those two only
    assert sorted(os.path.relpath(p, out) for p in removed) == ["summary.json", "sweep/sweep.json"]
    assert sorted(p.name for p in out.iterdir()) == ["notes.txt", "sweep", "te.csv"]
    # a list naming something else than the command's outputs deletes nothing else
    (out / ".jaxgear-outputs").write_text("notes.txt\n../x\n")
    assert clear_outputs(out, "run") == [] and (out / "notes.txt").exists()


def test_body_file_of_the_wrong_kind_is_an_error_at_load(tmp_path):
    case_file = importlib.resources.files("jaxgear") / "cases" / "accessory-spur.toml"
    for ref, why in (
        (str(case_file), "is a jaxgear case file ([pair]), not a fem_prep body file"),
        ("bad.npz", "not a condensed body file"),
        ("notes.toml", "not a fem_prep body file"),
    ):
        (tmp_path / "bad.npz").write_bytes(b"not a zip")
        (tmp_path / "notes.toml").write_text("colour = 'red'\n")
        data = copy.deepcopy(FLEXIBLE)
        data["scene"]["gear_body"]["body"] = ref
        with pytest.raises(SchemaError) as info:
            jio.parse_case(data, base_dir=str(tmp_path))
        msg = str(info.value)
        assert msg.startswith("[scene.gear_body] body = ") and why in msg and "\n" not in msg
        assert os.path.basename(ref) in msg


@pytest.mark.parametrize(
    "where,key,value,expected",
    [
        ("pinion_shaft", "diameter_mm", 5e-324, "allowed [1, 10000]"),
        ("gear_shaft", "length_mm", 1e-300, "allowed [1, 100000]"),
        (
            "pinion_shaft/bearings/0",
            "radial_N_per_um",
            5e-324,
            "allowed 0 (free) or [0.001, 1e+09]",
        ),
        ("gear_shaft/bearings/1", "tilt_Nm_per_rad", 1e-9, "allowed 0 (free) or [1, 1e+15]"),
    ],
)
def test_denormal_shafts_and_bearings_are_rejected(where, key, value, expected):
    data = copy.deepcopy(FLEXIBLE)
    t = data["scene"]
    for part in where.split("/"):
        t = t[int(part)] if part.isdigit() else t[part]
    t[key] = value
    msg = _error(data)
    assert f"{key} = {value:.6g}: out of range, {expected}" in msg, msg


def test_optimise_speed_band_from_the_case_file():
    from jaxgear.cli import check_settings, settings_from_case

    data = copy.deepcopy(FLEXIBLE)
    data["optimise"] = {"objective": "dynamic_factor", "speeds": [2800.0, 3200.0, 3]}
    case = jio.parse_case(data)
    assert case.optimise["speeds"] == [2800.0, 3200.0, 3]
    settings = check_settings(settings_from_case(case), case)
    assert settings["speeds"] == "2800.0:3200.0:3" and settings["objective"] == "dynamic_factor"
    del data["optimise"]["speeds"]
    assert _error(data).startswith(
        "[optimise] objective = 'dynamic_factor': 'dynamic_factor' needs speeds = [start, stop, n]"
    )
    data["optimise"] = {"objective": "te_rms", "speeds": [2800.0, 3200.0, 3]}
    assert "applies to objective = 'dynamic_factor' only, not 'te_rms'" in _error(data)
    rigid = _case(**{"optimise/objective": "dynamic_factor", "optimise/torques": None})
    rigid["optimise"]["speeds"] = [100.0, 200.0, 2]
    assert "needs a case with condensed bodies" in _error(rigid)


def test_readme_case_block_is_a_valid_case():
    text = (importlib.resources.files("jaxgear").joinpath("..", "README.md")).read_text("utf-8")
    block = text.split("## Case file", 1)[1].split("```toml\n", 1)[1].split("```", 1)[0]
    case = jio.parse_case(tomllib.loads(block))
    assert case.stiffness_model == "fe2d" and not hasattr(case.stiffness, "k0")


def test_centre_distance_at_the_printed_zero_backlash_distance_is_accepted():
    a0 = jio.parse_case(_case()).pair.zero_backlash_center_distance * 1e3  # 99.450280 mm
    for printed in (round(a0, 3), round(a0, 4), a0 - 0.9e-3):
        case = jio.parse_case(_case(**{"pair/center_distance_mm": printed}))
        assert case.pair.center_distance * 1e3 == pytest.approx(max(printed, a0), abs=1e-9)
    msg = _error(_case(**{"pair/center_distance_mm": a0 - 2e-3}))
    assert msg == (
        "[pair] center_distance_mm = 99.4483: out of range, allowed >= 99.450 mm (the "
        "zero-backlash distance, to 1 µm; closer, the teeth jam)"
    )


def test_absurd_damping_and_smooth_width_warn():
    data = copy.deepcopy(FLEXIBLE)
    data["scene"]["damping"] = {"model": "rayleigh", "beta_s": 1e6}
    (msg,) = _warnings(data)
    assert msg.startswith("[scene.damping] beta_s = 1e+06: the Rayleigh damping ratio at the mesh")
    data["scene"]["damping"] = {"model": "rayleigh", "alpha_per_s": 20.0, "beta_s": 1e-6}
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        jio.parse_case(data)  # the usual values: no warning
    (msg,) = _warnings(_case(**{"mesh/smooth_width_um": 14.0}))  # δ_m = 11.7 µm
    assert msg.startswith("[mesh] smooth_width_um = 14: above the mean static deflection 11.7")
