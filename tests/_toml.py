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

    lines = []
    scalars = {k: v for k, v in data.items() if not isinstance(v, dict | list)}
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
        if isinstance(v, list):
            for t in v:
                lines.append(f"[[{key}]]")
                lines += [f"{k} = {value(x)}" for k, x in t.items()]
        elif isinstance(v, dict):
            table(key, v)
    return "\n".join(lines) + "\n"
