"""TOML fragments shared by the tests that write case files."""

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
