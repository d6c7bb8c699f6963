"""``jaxgear run``'s rim and web stresses of a condensed body (``jaxgear.cli.body_stress_outputs``)
on a thin rotating annular disc written and read back as its ``.npz``: the reported largest rim
hoop stress is the plane-stress (Timoshenko & Goodier, Theory of Elasticity, Sec. 32) hoop stress
at that element's radius, and the summary's numbers are the ones in the stress VTU."""

import json
from pathlib import Path
from types import SimpleNamespace

import meshio
import numpy as np
import pytest
from test_fem_prep_body_stress import A_MM, B_MM, _condensed_centrifugal, _disc, _timoshenko

import fem_prep
from jaxgear import cli


def test_body_stress_outputs_rim_and_hub_against_timoshenko(tmp_path):
    p = _disc(10.0, 16.0)
    body, q = _condensed_centrifugal(p, tmp_path)
    # the scene's coordinates: the body's block placed after 5 other coordinates
    x = np.concatenate([np.full(5, np.nan), q, np.full(3, np.nan)])
    member = SimpleNamespace(body_dofs=5 + np.arange(body.n_dofs))
    section, files = cli.body_stress_outputs(str(tmp_path), [("gear", member, body)], x)
    assert files == ["body_gear_stress.vtu"]
    assert set(section["gear"]) == {"rim", "hub"}  # the plain disc has no web
    back = meshio.read(tmp_path / files[0])
    region = back.cell_data["region"][0]
    hoop_cells = back.cell_data["hoop_Pa"][0]
    for name, reg in (("rim", 2), ("hub", 0)):
        got = section["gear"][name]
        assert got["von_mises_Pa"] == pytest.approx(
            back.cell_data["von_mises_Pa"][0][region == reg].max()
        )
        i = np.nonzero((region == reg) & (hoop_cells == got["hoop_Pa"]))[0]
        assert i.size >= 1
    # the rim's largest hoop stress (at its inner radius) against plane stress at the element's
    # corner-mean radius, within 3 % of the disc's largest hoop stress (measured 1.9 %: the
    # coarse corner recovery's element mean against a point value)
    pts = back.points[back.cells[0].data].mean(axis=1)
    r = np.hypot(pts[:, 0], pts[:, 1])
    rim = section["gear"]["rim"]["hoop_Pa"]
    k = np.nonzero((region == 2) & (hoop_cells == rim))[0][0]
    hoop_ref = _timoshenko(np.array([r[k]]))[0][0]
    largest = np.abs(_timoshenko(np.linspace(1e-3 * A_MM, 1e-3 * B_MM, 401))[0]).max()
    assert rim == pytest.approx(hoop_ref, abs=0.03 * largest)


@pytest.mark.slow
def test_a_flexible_train_reports_its_body_stresses(fem_prep_cache, tmp_path):
    """``jaxgear run`` on the small flexible idler train (tests/data/hybrid-test-train.toml)
    reports the idler body's rim and web stresses as a pair's hybrid scene does (the same
    ``body_stress_outputs``): ``body_stress.idler.<region>`` equal to the maxima of the written
    ``body_idler_stress.vtu``, recovered at the position of ``body_idler.vtu`` (the two files'
    displacements have the same magnitude at every node: one solution, the stress file in the
    body frame, the deformed body turned to its angle)."""
    out = tmp_path / "out"
    case = Path(__file__).parent / "data" / "hybrid-test-train.toml"
    assert cli.main(["run", str(case), "--out", str(out), "--quiet"]) == 0
    s = json.loads((out / "summary.json").read_text())
    assert s["body_stress_vtu"] == ["body_idler_stress.vtu"]
    stress = meshio.read(out / "body_idler_stress.vtu")
    region = stress.cell_data["region"][0]
    got = s["body_stress"]["idler"]
    assert {"rim", "web", "hub"} <= set(got)
    for name in got:
        cells = region == fem_prep.REGIONS[name]
        vm = stress.cell_data["von_mises_Pa"][0][cells]
        assert got[name]["von_mises_Pa"] == pytest.approx(vm.max(), rel=1e-12)
        hoop = stress.cell_data["hoop_Pa"][0][cells]
        assert got[name]["hoop_Pa"] == pytest.approx(hoop[np.argmax(np.abs(hoop))], rel=1e-12)
    assert got["rim"]["von_mises_Pa"] > 1e6  # the tooth loads reach the rim
    deformed = meshio.read(out / "body_idler.vtu")
    np.testing.assert_allclose(
        np.linalg.norm(stress.point_data["displacement"], axis=1),
        np.linalg.norm(deformed.point_data["displacement_m"], axis=1),
        rtol=1e-9,
        atol=1e-9 * np.abs(deformed.point_data["displacement_m"]).max(),
    )
