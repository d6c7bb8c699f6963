"""The ring's model in a planetary case file ([planetary.ring] model, body): the names mapped to
jaxgear.planetary.RigidRing / CondensedRing by jaxgear.io, and the refusals in one line before any work
(an unknown model, a missing or unknown body, a body with a rigid ring, a ring body whose tooth
count or root radius disagree with the ring gear)."""

import copy
import json
import tomllib

import numpy as np
import pytest

import fem_prep as fp
import jaxgear as jg
import jaxgear.io as jio
import jaxgear.planetary as jp
from _planetary_stage import seq_ring_case
from _toml import case_toml
from jaxgear.cli import main, planetary as pr

NREL2 = "nrel-5mw-stage2"
NREL2_RING = "nrel-5mw-stage2-ring"


def _with_ring(tmp_path, **ring):
    data = copy.deepcopy(tomllib.loads(jio.embedded_case_text(NREL2)))
    data["planetary"]["ring"].update(ring)
    path = tmp_path / "case.toml"
    path.write_text(case_toml(data))
    return path


def test_names_map_to_ring_objects(tmp_path):
    """No model: the rigid ring; model = "condensed" with the embedded NREL stage-2 ring: its
    body (93 stations, the ring gear's root radius within 2 %), not built until asked."""
    rigid = jio.load_case(NREL2).form.spec.ring_model
    assert not rigid.flexible and isinstance(rigid.ring(), jp.RigidRing)
    case = jio.load_case(_with_ring(tmp_path, model="condensed", body=NREL2_RING))
    spec = case.form.spec.ring_model
    assert spec.flexible and spec.body == fp.load_ring_body(NREL2_RING)
    assert spec.body.condensation.teeth == 93
    assert spec.body.root_radius == pytest.approx(float(case.pairs[1].root_radii[1]), rel=1e-4)
    explicit = jio.load_case(_with_ring(tmp_path, model="rigid")).form.spec.ring_model
    assert isinstance(explicit.ring(), jp.RigidRing)


def test_a_ring_body_file_by_path(tmp_path):
    text = fp.embedded_ring_text(NREL2_RING)
    body = tmp_path / "my-ring.toml"
    body.write_text(text.replace('name = "nrel-5mw-stage2-ring"', 'name = "mine"'))
    spec = jio.load_case(_with_ring(tmp_path, model="condensed", body=str(body))).form.spec
    assert spec.ring_model.body.name == "mine"


@pytest.mark.parametrize(
    "ring, words",
    [
        (dict(model="elastic"), "[planetary.ring] model = 'elastic'"),
        (dict(model="condensed"), "[planetary.ring] body: missing required key"),
        (dict(model="rigid", body=NREL2_RING),
         "[planetary.ring] body = 'nrel-5mw-stage2-ring': allowed only with model = \"condensed\""),
        (dict(model="condensed", body="no-such-ring"),
         "[planetary.ring] body = 'no-such-ring': ring body 'no-such-ring' not found"),
        (dict(model="condensed", body="seq-test-ring"),
         "has 53 tooth stations ([condensation] teeth); the ring gear has 93 teeth"),
        (dict(model="condensed", body="BODY_900"),
         "root_radius_mm = 900 differs from the ring gear's root radius 1000.3 mm by 10"),
    ],
)
def test_bad_ring_keys_are_one_line_before_any_work(tmp_path, capsys, ring, words):
    if ring.get("body") == "BODY_900":
        text = fp.embedded_ring_text(NREL2_RING)
        body = tmp_path / "small.toml"
        body.write_text(text.replace("root_radius_mm = 1000.30", "root_radius_mm = 900.0"))
        ring = {**ring, "body": str(body)}
    path = _with_ring(tmp_path, **ring)
    out = tmp_path / "out"
    assert main(["run", str(path), "--out", str(out), "--quiet"]) == 2
    err = capsys.readouterr().err.strip()
    assert words in err and "\n" not in err, err
    assert not out.exists()


# a first-look step: the sweep warns that it under-resolves the top mode (tests/test_planetary_step_resolution.py)
@pytest.mark.filterwarnings("ignore:.*time step under-resolved")
@pytest.mark.slow
def test_a_condensed_ring_run_end_to_end(tmp_path, capsys):
    """jaxgear run on a small stage with the coarse test ring (72 s of CPU, float64, load 4 to
    5; about 535 s before its sweep ran one program per N_s and the station model in the cell
    space: the run's own sweep, 9 speeds at N_s 6144 to 24576, and mesh sections; the fast tests above check the parser and the objects, and
    tests/test_planetary_ring.py the flexible ring's quasi-static solve): the ring section of summary.json
    (K_gamma of the rigid ring is the load_sharing one, found by another solver, to 1e-6; the
    flexible ring relieves planet 1; the ring's deflection at the ring meshes is the station
    compliance's C P within 1e-9 at the first position), ring.vtu with its mode shapes."""
    path = tmp_path / "seq.toml"
    path.write_text(case_toml(seq_ring_case()))
    out = tmp_path / "out"
    assert main(["run", str(path), "--out", str(out), "--quiet"]) == 0
    summary = json.loads((out / "summary.json").read_text())
    ring = summary["ring"]
    assert ring["k_gamma_rigid"] == pytest.approx(
        summary["load_sharing"]["planar"]["k_gamma"], rel=1e-6)
    assert ring["k_gamma_condensed"] < ring["k_gamma_rigid"]
    case = jio.load_case(path)
    spec = case.form.spec
    C = np.asarray(spec.ring_model.ring().mesh_compliance(spec.stage(case), 0.0))
    P = np.asarray(ring["ring_mesh_forces_condensed_N"][0])
    assert ring["ring_deflection_max_m"] >= np.max(np.abs(C @ P)) * (1 - 1e-9)
    assert set(ring["nd_frequencies_Hz"]) >= {"2", "3"}
    for r in ring["resonances"]:
        assert r["frequency_hz"] == pytest.approx(r["order"] * r["carrier_speed_hz"], rel=1e-12)
    vtu = (out / "ring.vtu").read_text()
    assert vtu.count('Name="mode_') == 8
    assert vtu.count(f'Name="{pr.DEFLECTION}"') == 1  # the deflected shape beside the modes
    # the ring's Campbell diagram draws the one list of resonances: every crossing at
    # 2 pi f_n / (order Omega) of the input (ring fixed, carrier in: Omega is the input speed)
    camp = ring["campbell"]
    assert (out / camp["file"]).stat().st_size > 10_000
    top = camp["input_speeds_rad_s"][1]
    assert camp["shown"] == sum(1 for r in ring["resonances"] if r["input_speed_rad_s"] <= top)
    for c in ring["resonances"]:
        assert c["input_speed_rad_s"] == pytest.approx(
            2 * np.pi * ring["nd_frequencies_Hz"][str(c["nd"])] / c["order"], rel=1e-12)
    # docs/planetary.md's figure: the n = 1 mode (195 Hz) meets the first harmonic's order
    # z_r + 1 = 54 near the 20 rad/s operating speed
    assert ring["nd_frequencies_Hz"]["1"] == pytest.approx(194.6, abs=0.5)
    (near,) = [c for c in ring["resonances"]
               if (c["nd"], c["harmonic"], c["order"]) == (1, 1, 54)]
    assert 20.0 < near["input_speed_rad_s"] < 25.0


@pytest.mark.parametrize("fixed, per_input", [("ring", 28 / 120), ("carrier", 28 / 92)])
def test_ring_campbell_lines_follow_the_moving_load_rule(tmp_path, fixed, per_input):
    """ring_campbell.png's lines and crossings (ring_crossings, the one list it draws) on the
    lumped lin-parker-1999 (28/92 teeth, sun in, three planets; synthetic nodal-diameter frequencies, no condensation): the lines
    are the (n, h, order) for which N point loads moving round the ring with the h-th mesh
    harmonic have a circumferential harmonic ±n, found here by summing the planets' phasors
    exp(2 pi i (h z_r - s n) j / N) (not by the library's congruence); each crossing's input
    speed is 2 pi f_n / (order Omega per input), Omega = |omega_c - omega_r| from Willis by
    hand (ring fixed: z_s/(z_s + z_r); carrier fixed: the ring's z_s/z_r)."""
    data = tomllib.loads(jio.embedded_case_text("lin-parker-1999"))
    data["planetary"]["fixed"] = fixed
    data["planetary"][fixed].setdefault("torsional_stiffness_N_per_um", 1000.0)
    case = jio.parse_train(data)
    nd = {2: 400.0, 3: 1100.0, 4: 2000.0, 5: 3000.0}
    got = pr.ring_campbell(case, case.form.spec, nd, str(tmp_path / "ring_campbell.png"))
    assert got["planet_pass_speed_per_input"] == pytest.approx(per_input, rel=1e-12)
    n_p, z_r = 3, 92
    want = set()
    for h in range(pr.RING_HARMONICS + 1):
        for n in nd:
            for s in (1, -1):
                total = sum(np.exp(2j * np.pi * (h * z_r - s * n) * j / n_p) for j in range(n_p))
                if abs(total) > 1e-9 and h * z_r - s * n != 0:
                    want.add((n, h, abs(h * z_r - s * n)))
    # the one list the diagram draws (its lines, one crossing each) and the ring section reports
    lines = pr.ring_crossings(case.form.spec, nd)
    assert {(c["nd"], c["harmonic"], c["order"]) for c in lines} == want
    assert len(lines) == len(want)
    top = got["input_speeds_rad_s"][1]
    expect = {(n, h, k): 2 * np.pi * nd[n] / (k * per_input) for n, h, k in want}
    shown = {k: v for k, v in expect.items() if v <= top}
    assert shown and any(h > 0 for _, h, _ in shown)
    assert got["shown"] == len(shown)
    for c in lines:
        assert c["input_speed_rad_s"] == pytest.approx(expect[(c["nd"], c["harmonic"],
                                                                c["order"])], rel=1e-12)
    assert (tmp_path / "ring_campbell.png").stat().st_size > 10_000
