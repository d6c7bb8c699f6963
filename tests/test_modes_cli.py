"""``jaxgear modes CASE`` (jaxgear/cli/modes.py): natural frequencies with their mode types, for
every kind of case.

* a torsional pair (the embedded ``power-helical``, no ``[scene]``: the torsional model): its
  one elastic mode against the closed form ω² = k̄ cos²β_b (r_b1²/I_1 + r_b2²/I_2) (k̄ the mean
  loaded mesh stiffness along the flank normal, the inertias the solid discs of the tip radius
  and face width that a case without inertias gets: I = ρ π b r_a⁴ / 2), to 1e-9;
* a planetary stage (``lin-parker-1999``): the modes and types of Lin & Parker's Table 1
  system built here by hand (tests/test_planetary.py) with :func:`jaxgear.planetary.classify_modes`, and
  the paper's printed frequencies;
* a lumped 3D pair: the kinetic-energy shares of each mode sum to 1, its type is the largest;
* every embedded case lists modes (slow: the models of the trains and the flexible cases take
  tens of seconds to build; the fast twins above).
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from test_planetary import PRINTED, lin_parker_stage

import jaxgear as jg
import jaxgear.io as jio
import jaxgear.planetary as jp
from jaxgear.cli import main, modes as cm


def test_a_torsional_pair_against_the_closed_form():
    # on the theoretical path: the closed form takes every loaded cell's vector as
    # cos β_b (r_b1, −r_b2); beyond the path (the case file's default) a corner cell's entry of
    # its tip owner is λ r_bT (docs/extended-contact.md, "Where it acts")
    case = jio.load_case("power-helical").replace(contact_geometry=jg.TheoreticalPath())
    data = cm.case_modes(case.form, case)
    assert [m["type"] for m in data["modes"]] == ["rigid", "torsional"]
    pair = case.pairs[0]
    r1, r2 = pair.base_radii
    i1, i2 = (
        math.pi * case.density * m.face_width * r**4 / 2
        for m, r in zip((pair.pinion, pair.gear), pair.tip_radii, strict=True)
    )
    k = data["mesh_stiffness_mean_N_per_m"] * math.cos(pair.base_helix_angle) ** 2
    f = math.sqrt(k * (r1**2 / i1 + r2**2 / i2)) / (2 * math.pi)
    assert data["modes"][1]["frequency_Hz"] == pytest.approx(f, rel=1e-9)
    assert data["modes"][0]["frequency_Hz"] == 0.0


def test_a_planetary_stage_against_the_classification_and_the_paper(tmp_path, capsys):
    out = tmp_path / "modes"
    assert main(["modes", "lin-parker-1999", "--out", str(out)]) == 0
    printed = capsys.readouterr().out
    assert "743.164  translational × 2" in printed and f"written to {out}/" in printed
    data = json.loads((out / "modes.json").read_text())
    stage = lin_parker_stage(3)
    for name, model in (("planar", jp.PlanarPlanetary()), ("torsional", jp.TorsionalPlanetary())):
        m = jp.planetary_modes(model, stage)
        types = jp.classify_modes(m, model, stage)
        got = data[name]
        np.testing.assert_allclose([r["frequency_Hz"] for r in got], m.frequencies, rtol=1e-9,
                                   atol=1e-3)
        assert [(r["type"], r["multiplicity"]) for r in got] == [(t.value, k) for t, k in types]
    rot, trans, _ = PRINTED[3]
    planar = data["planar"]
    for typ, printed_f in (("rotational", rot[1:]), ("translational", trans)):
        f = sorted({round(r["frequency_Hz"], 6) for r in planar if r["type"] == typ})
        f = [v for v in f if v > 1.0]
        np.testing.assert_allclose(f, printed_f, atol=0.06)


def test_shares_sum_to_one_and_type_is_the_largest():
    # a two-node scene written here: node 1 a shaft node (6 coordinates), node 2 another; the
    # modes of a diagonal system are its coordinates, each typed by its own group
    mass = np.diag([1.0, 2.0, 3.0, 4.0, 5.0, 6.0] * 2)
    k = np.diag(np.arange(1.0, 13.0))
    _, vec = np.linalg.eigh(np.linalg.solve(np.sqrt(mass), np.linalg.solve(np.sqrt(mass), k).T))
    phi = np.linalg.solve(np.sqrt(mass), vec)
    names, shares = cm.group_shares(mass, phi, 6)
    assert names == ("bending", "axial", "torsional")
    np.testing.assert_allclose(shares.sum(axis=0), 1.0, rtol=1e-12)
    dof = np.argmax(np.abs(phi), axis=0) % 6
    expect = [cm.DOF_GROUPS[6][d] for d in dof]
    assert [names[g] for g in np.argmax(shares, axis=0)] == expect


NON_FLEXIBLE = [
    "accessory-spur",
    "accessory-idler-train",
    "two-stage",
    "nrel-5mw-planetary",
    "nrel-5mw-stage2",
    "nrel-5mw-stage3",
]
FLEXIBLE = ["accessory-spur-flexible", "flexible-idler", "power-helical-flexible"]


@pytest.mark.slow  # 10-20 s each on the loaded 2-core CPU (building the models)
@pytest.mark.parametrize("name", NON_FLEXIBLE + FLEXIBLE)
def test_every_embedded_case_lists_modes(name):
    case = jio.load_case(name)
    data = cm.case_modes(case.form, case)
    lists = [v for v in data.values() if isinstance(v, list)]
    assert lists and all(len(v) >= 2 for v in lists)
    for rows in lists:
        f = [r["frequency_Hz"] for r in rows]
        assert all(np.isfinite(f)) and f == sorted(f) and max(f) > 10.0
        assert all(r["type"] for r in rows)
    assert cm.mode_table(data)[0].startswith(f"{name}: natural frequencies")
