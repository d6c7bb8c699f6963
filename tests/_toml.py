"""TOML fragments shared by the tests that write case files, and a writer of parsed cases."""

import json

# The seed's accessory pair (Tab. III-1) at 80 N·m: [pair], [pinion], [gear], [operating].
ACCESSORY_PAIR = """
[pair]
normal_module_mm = 1.5
normal_pressure_angle_deg = 25.0
[pinion]
teeth = 45
profile_shift = 0.341
addendum_coeff = 0.9447
dedendum_coeff = 1.1933
face_width_mm = 11.5
[gear]
teeth = 86
profile_shift = 0.481
addendum_coeff = 0.9447
dedendum_coeff = 1.1933
face_width_mm = 9.5
[operating]
torque_Nm = 80.0
"""


def small_helical_pair(
    name: str, *, pinion: str = "", gear: str = "", slices: int = 12, positions_per_pitch: int = 16
) -> str:
    """A small 15° helical pair (m_n 2 mm, α_n 20°, 23/41 teeth, faces 20/22 mm, ISO 6336
    stiffness, 120 N·m) as case TOML named ``name``: [pair], [pinion] and [gear] (``pinion``,
    ``gear``: more lines of those tables), [operating] and [mesh] (``slices``,
    ``positions_per_pitch``); tables after it may follow."""
    return f"""
name = "{name}"
[pair]
normal_module_mm = 2.0
normal_pressure_angle_deg = 20.0
helix_angle_deg = 15.0
[pinion]
teeth = 23
face_width_mm = 20.0
{pinion}[gear]
teeth = 41
face_width_mm = 22.0
{gear}[operating]
torque_Nm = 120.0
[mesh]
stiffness = "iso6336"
slices = {slices}
positions_per_pitch = {positions_per_pitch}
"""


def case_toml(data: dict) -> str:
    """A small TOML writer for the case tables used here (tables, arrays of tables, inline
    tables of numbers and strings)."""

    def value(v):
        if isinstance(v, str):
            return json.dumps(v)
        if isinstance(v, bool):
            return "true" if v else "false"
        if isinstance(v, dict):
            return "{ " + ", ".join(f"{k} = {value(x)}" for k, x in v.items()) + " }"
        if isinstance(v, list):
            return "[" + ", ".join(value(x) for x in v) + "]"
        return repr(v)

    def tables(v) -> bool:  # an array of tables (an array of anything else is a value)
        return isinstance(v, list) and all(isinstance(t, dict) for t in v)

    lines = []
    scalars = {k: v for k, v in data.items() if not isinstance(v, dict) and not tables(v)}
    lines += [f"{k} = {value(v)}" for k, v in scalars.items()]

    def table(name, t):
        lines.append(f"[{name}]")
        subs = {k: v for k, v in t.items() if isinstance(v, dict) and name != "modifications"}
        for k, v in t.items():
            if k not in subs:
                lines.append(f"{k} = {value(v)}")
        for k, v in subs.items():
            table(f"{name}.{k}", v)

    for key, v in data.items():
        if tables(v):
            for t in v:
                lines.append(f"[[{key}]]")
                lines += [f"{k} = {value(x)}" for k, x in t.items()]
        elif isinstance(v, dict):
            table(key, v)
    return "\n".join(lines) + "\n"


def assert_one_line_errors(bad: dict, folder, name: str = "box.toml") -> None:
    """Each case text of ``bad`` ({TOML text: regular expression}), written to ``folder``/``name``,
    is refused by :func:`jaxgear.io.load_case` with a ``SchemaError`` of one line that matches
    its expression."""
    import pytest

    import jaxgear.io as jio

    path = folder / name
    for text, needle in bad.items():
        path.write_text(text)
        with pytest.raises(jio.SchemaError, match=needle) as err:
            jio.load_case(str(path))
        assert "\n" not in str(err.value), str(err.value)
