"""A gearbox's coupled dynamic factor set beside the K_v each rated stage's rating uses
(:func:`jaxgear.cli.gearbox.rating_dynamic_factors`, the lines ``jaxgear run`` prints): every
rated mesh matched with its stage's meshes of the coupled model (a planetary stage's two
ratings with its sun-planet and ring-planet meshes, the largest over the planets; a pair's
one), the coupled factor read at the rated input speed (or interpolated linearly between the
sweep's speeds, and said so), the K_v and its source the rating's own.

References: a hand-made summary (the keys ``jaxgear run`` writes), its expected rows picked out
by hand (the maxima and the linear interpolation written here)."""

import types

import numpy as np

from jaxgear.cli.gearbox import gearbox_run_lines, rating_dynamic_factors

NAMES = ["1:sun-planet 1", "1:sun-planet 2", "1:ring-planet 1", "1:ring-planet 2", "2:pair",
         "3:pair"]
DF = np.array([[1.01, 1.02, 1.03, 1.04, 1.05, 1.06],
               [1.20, 1.31, 1.12, 1.09, 1.50, 1.89],
               [1.40, 1.35, 1.30, 1.11, 1.70, 1.60]])
STAGE = {"input_speed_rad_s": 1.0, "input_torque_Nm": 2.0, "output_speed_rad_s": 3.0,
         "output_torque_Nm": 4.0}


def _summary():
    planetary = {"meshes": ["sun1-planet1", "planet1-ring1"],
                 "factors": {"K_v": {"value": [1.05, 1.03],
                                     "source": ["ISO 6336-1 method B"] * 2}},
                 "pitting": {"S_H": [[1.2, 1.3], [1.4, 1.5]]},
                 "bending": {"S_F": [[2.0, 2.1], [2.2, 2.3]]}}
    pair = {"factors": {"K_v": {"value": 1.092, "source": "given"}},
            "pitting": {"S_H": [1.81, 1.88]}, "bending": {"S_F": [3.26, 3.09]}}
    stages = [STAGE | {"stage": "stage1", "case": "planetary", "folder": "stage1",
                       "summary": {"rating": planetary}},
              STAGE | {"stage": "stage2", "case": "unrated", "folder": "stage2", "summary": {}},
              STAGE | {"stage": "stage3", "case": "helical", "folder": "stage3",
                       "summary": {"rating": pair}}]
    coupled = {"input_speeds_rad_s": [2.0, 4.0, 6.0], "dynamic_factor_mesh": DF.tolist(),
               "mesh_names": NAMES}
    return stages, coupled


def test_each_rated_mesh_beside_its_coupled_meshes_at_the_rated_speed():
    stages, coupled = _summary()
    rows = rating_dynamic_factors(stages, coupled, 4.0)
    assert [(r["stage"], r["mesh"]) for r in rows] == [
        ("stage1", "sun1-planet1"), ("stage1", "planet1-ring1"), ("stage3", "helical")]
    assert [r["coupled_meshes"] for r in rows] == [NAMES[:2], NAMES[2:4], NAMES[5:]]
    assert [r["coupled_dynamic_factor"] for r in rows] == [1.31, 1.12, 1.89]
    assert [(r["K_v_rated"], r["K_v_source"]) for r in rows] == [
        (1.05, "ISO 6336-1 method B"), (1.03, "ISO 6336-1 method B"), (1.092, "given")]
    assert {r["rated_with"] for r in rows} == {"K_v"}
    assert rows[0]["coupled_at"] == "at the rated input speed"
    between = rating_dynamic_factors(stages, coupled, 5.0)  # halfway between 4 and 6 rad/s
    want = [max(0.5 * (DF[1, j] + DF[2, j]) for j in cols) for cols in ((0, 1), (2, 3), (5,))]
    np.testing.assert_allclose([r["coupled_dynamic_factor"] for r in between], want,
                               rtol=1e-14)
    assert between[0]["coupled_at"].startswith("interpolated linearly")


def test_jaxgear_run_prints_the_coupled_factor_beside_the_rated_k_v():
    stages, coupled = _summary()
    coupled |= {"rating_dynamic_factors": rating_dynamic_factors(stages, coupled, 4.0),
                "max_dynamic_factor": 1.89, "worst_mesh": "3:pair", "modes": []}
    summary = {"gearbox": {"speed_ratio": 0.1, "step_up": 10.0,
                           "stage_speed_ratios": [0.5, 0.2, 1.0]},
               "stages": stages, "torsional_modes": [], "coupled": coupled}
    lines = gearbox_run_lines(types.SimpleNamespace(stages=(0, 0, 0)),
                              types.SimpleNamespace(name="box"), summary)
    kv = [line for line in lines if "rated with K_v" in line]
    assert kv == [
        ("stage1 sun1-planet1: rated with K_v 1.05 (ISO 6336-1 method B); the coupled "
         "gearbox's dynamic factor 1.31 (at the rated input speed) is not rated with "
         "(coupled.json rating_dynamic_factors)"),
        ("stage1 planet1-ring1: rated with K_v 1.03 (ISO 6336-1 method B); the coupled "
         "gearbox's dynamic factor 1.12 (at the rated input speed) is not rated with "
         "(coupled.json rating_dynamic_factors)"),
        ("stage3 helical: rated with K_v 1.092 (given); the coupled gearbox's dynamic factor "
         "1.89 (at the rated input speed) is not rated with (coupled.json "
         "rating_dynamic_factors)"),
    ]
