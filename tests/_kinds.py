"""Small case files of every scene kind a case file accepts, as TOML text (:data:`KINDS`): a
pair rigid (no ``[scene]``), torsional, 1-DOF relative (modal damping), lumped 3D and hybrid (a
condensed wheel); a train rigid, torsional, lumped 3D, a lumped two-stage train (its meshes repeat
every 2 periods of the first) and a hybrid train (a condensed idler). Shared by
tests/test_every_kind.py (each kind's commands end to end) and tests/test_regression.py (their
numbers against records).

Smallest settings: 2 slices, 8 positions per pitch, 16 or 32 steps per mesh period, 6 periods;
the hybrid kinds name the small test body tests/data/hybrid-test-wheel.toml (a test that runs
them asks for the ``fem_prep_cache`` fixture: condensed once per session)."""

from __future__ import annotations

from pathlib import Path

DATA = Path(__file__).parent / "data"

INTEGRATION = """
[scene.integration]
steps_per_period = {steps}
periods = 6
keep_periods = {keep}
"""

def small_pair(name: str, *, pinion_face_mm: float = 10.0, ppp: int = 8) -> str:
    """The small spur pair the CLI tests run (m_n 2 mm, 20/30 teeth, Weber, 2 slices): the
    TOML text without modifications or ``[scene]``."""
    return f"""
name = "{name}"
[pair]
normal_module_mm = 2.0
normal_pressure_angle_deg = 20.0
[pinion]
teeth = 20
face_width_mm = {float(pinion_face_mm)!r}
[gear]
teeth = 30
face_width_mm = 10.0
[operating]
torque_Nm = 60.0
[mesh]
stiffness = "weber"
slices = 2
positions_per_pitch = {ppp}
"""


TIP_RELIEF = """[modifications]
tip_relief = { depth_um = 8.0, extent = 0.3, shape = "linear" }
"""


def _pair(name: str) -> str:
    """The pair of every pair kind: :func:`small_pair` with a 12 mm pinion and tip relief."""
    return small_pair(name, pinion_face_mm=12.0) + TIP_RELIEF

PAIR_SHAFTS = """
[scene.pinion_shaft]
length_mm = 80.0
diameter_mm = 25.0
gear_position_mm = 40.0
torque_position_mm = 0.0
bearings = [{ position_mm = 0.0, radial_N_per_um = 200.0, axial_N_per_um = 100.0 },
            { position_mm = 80.0, radial_N_per_um = 200.0 }]
[scene.gear_shaft]
length_mm = 80.0
diameter_mm = 25.0
gear_position_mm = 40.0
torque_position_mm = 80.0
bearings = [{ position_mm = 0.0, radial_N_per_um = 300.0, axial_N_per_um = 100.0 },
            { position_mm = 80.0, radial_N_per_um = 300.0 }]
"""

GEAR = """
[[gears]]
name = "{name}"
{shaft}teeth = {teeth}
normal_module_mm = 2.0
normal_pressure_angle_deg = 20.0
{shift}face_width_mm = {face}
"""

TRAIN_HEAD = """
name = "{name}"
[material]
youngs_modulus_GPa = 210.0
poisson_ratio = 0.3
density_kg_m3 = 7800.0
"""

TRAIN_TAIL = """
[operating]
torque_Nm = {torque}
[mesh]
stiffness = "weber"
slices = 2
positions_per_pitch = {ppp}
[modifications]
tip_relief = {{ depth_um = 8.0, extent = 0.3, shape = "linear" }}
"""


def _shaft(name: str, gears: dict, torque: float | None, d: float = 25.0, k: float = 300.0) -> str:
    """A ``[[scene.shafts]]`` entry of an 80 mm shaft on two bearings at its ends."""
    pos = ", ".join(f"{g} = {z}" for g, z in gears.items())
    t = "" if torque is None else f"torque_position_mm = {torque}\n"
    return (
        f'\n[[scene.shafts]]\nshaft = "{name}"\nlength_mm = 80.0\ndiameter_mm = {d}\n'
        f"gear_positions_mm = {{ {pos} }}\n{t}"
        f"bearings = [{{ position_mm = 0.0, radial_N_per_um = {k}, axial_N_per_um = 100.0 }},\n"
        f"            {{ position_mm = 80.0, radial_N_per_um = {k} }}]\n"
    )


def _idler_train(name: str, scene: str, ppp: int = 8) -> str:
    """The idler train of tests/data/hybrid-test-train.toml: 20 → 30 (idler) → 24 teeth."""
    gears = "".join(
        GEAR.format(name=n, shaft="", teeth=z, shift="", face=b)
        for n, z, b in (("input", 20, 12.0), ("idler", 30, 10.0), ("output", 24, 12.0))
    )
    meshes = (
        '\n[[meshes]]\ndriving = "input"\ndriven = "idler"\nangle_deg = 0.0\n'
        '[[meshes]]\ndriving = "idler"\ndriven = "output"\nangle_deg = 120.0\n'
    )
    return (
        TRAIN_HEAD.format(name=name)
        + gears
        + meshes
        + TRAIN_TAIL.format(torque=60.0, ppp=ppp)
        + scene
    )


def _lumped_idler_scene(extra: str = "") -> str:
    return (
        '\n[scene]\nmodel = "lumped3d"\n'
        + _shaft("input", {"input": 40.0}, 0.0, k=200.0)
        + _shaft("idler", {"idler": 40.0}, 40.0)
        + _shaft("output", {"output": 40.0}, 80.0)
        + extra
        + INTEGRATION.format(steps=32, keep=2)
    )


def _two_stage(name: str) -> str:
    """The two-stage train of tests/data/hybrid-test-two-stage.toml on lumped shafts (rigid
    gears): 20 → 30 on the intermediate shaft with a 15-tooth pinion → 24; its meshes repeat
    together every 2 periods of the first."""
    gears = "".join(
        GEAR.format(name=n, shaft=s, teeth=z, shift=x, face=b)
        for n, s, z, x, b in (
            ("input", "", 20, "", 12.0),
            ("wheel", 'shaft = "intermediate"\n', 30, "", 10.0),
            ("pinion", 'shaft = "intermediate"\n', 15, "profile_shift = 0.3\n", 12.0),
            ("output", "", 24, "", 12.0),
        )
    )
    meshes = (
        '\n[[meshes]]\ndriving = "input"\ndriven = "wheel"\nangle_deg = 0.0\n'
        '[[meshes]]\ndriving = "pinion"\ndriven = "output"\nangle_deg = 90.0\n'
    )
    scene = (
        '\n[scene]\nmodel = "lumped3d"\n'
        + _shaft("input", {"input": 40.0}, 0.0, k=200.0)
        + _shaft("intermediate", {"wheel": 30.0, "pinion": 52.0}, None, d=30.0)
        + _shaft("output", {"output": 40.0}, 80.0)
        + INTEGRATION.format(steps=32, keep=2)
    )
    return TRAIN_HEAD.format(name=name) + gears + meshes + TRAIN_TAIL.format(torque=30.0, ppp=8) + scene


WHEEL = (DATA / "hybrid-test-wheel.toml").as_posix()

# kind → case file text; the hybrid kinds are marked (they need the condensed test bodies)
KINDS = {
    "pair-rigid": _pair("pair-rigid"),
    "pair-torsional": _pair("pair-torsional")
    + '\n[scene]\nmodel = "torsional"\n'
    + INTEGRATION.format(steps=16, keep=2),
    "pair-relative": _pair("pair-relative")
    + '\n[scene]\nmodel = "torsional"\nreduction = "relative"\n'
    + '[scene.damping]\nmodel = "modal"\nratio = 0.05\n'
    + INTEGRATION.format(steps=16, keep=2),
    "pair-lumped3d": _pair("pair-lumped3d")
    + '\n[scene]\nmodel = "lumped3d"\n'
    + PAIR_SHAFTS
    + INTEGRATION.format(steps=32, keep=2),
    "pair-hybrid": _pair("pair-hybrid")
    + '\n[scene]\nmodel = "lumped3d"\n'
    + f'[scene.gear_body]\nbody = "{WHEEL}"\n'
    + PAIR_SHAFTS
    + INTEGRATION.format(steps=16, keep=2),
    "train-rigid": _idler_train("train-rigid", ""),
    "train-torsional": _idler_train(
        "train-torsional",
        '\n[scene]\nmodel = "torsional"\n' + INTEGRATION.format(steps=16, keep=2),
    ),
    "train-lumped3d": _idler_train("train-lumped3d", _lumped_idler_scene()),
    "train-two-stage": _two_stage("train-two-stage"),
    "train-hybrid": _idler_train(
        "train-hybrid",
        _lumped_idler_scene(f'[scene.bodies.idler]\nbody = "{WHEEL}"\n').replace(
            "steps_per_period = 32", "steps_per_period = 16"
        ),
    ),
}
