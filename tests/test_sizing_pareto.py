"""The sizing's objectives and Pareto front (jaxgear.sizing.pareto_front, objective_columns,
jaxgear size's figures and rank column): the non-dominated sorting against a brute-force
peeling of fronts written here (hypothesis: ties, duplicates, either sense, infeasible rows);
the chosen design on small fronts worked by hand; the mesh loss column against the tribology
model (Schlenk's μ, Ohlendorf's H_V) called on each candidate's jaxgear.GearPair, and through
the written case file's own [lubricant]; the envelope volume from the pair's radii; the spec's
[pareto] and [lubricant] refused in one line naming the key. The sizing program is the one of
tests/test_sizing.py's spec (the same angles, rack, grade and tip limit: one compilation)."""

from __future__ import annotations

import copy
import csv
import json
import math
import tomllib

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings, strategies as st
from test_sizing import _pair, _spec as _small_spec

import jaxgear.io as jio
import jaxgear.sizing as js
import jaxgear.tribology as tr
from jaxgear.cli import main

# the small helical reducer of tests/test_sizing.py with pinions to 24 and no outer-diameter
# limit, and an oil: the mesh loss columns
SPEC = _small_spec(z1_max=24)
del SPEC["sizing"]["outer_diameter_max_mm"]
SPEC |= {
    "name": "small-lubricated",
    "lubricant": {"viscosity_40C_mm2_s": 220.0, "viscosity_100C_mm2_s": 19.0,
                  "density_kg_m3": 895.0, "pressure_viscosity_per_GPa": 20.0,
                  "oil_temperature_C": 70.0, "roughness_Ra_um": [0.5, 0.7],
                  "lubricant_factor": 0.85},
    "pareto": {"minimise": ["mass_kg", "mesh_loss_W"], "maximise": ["least_margin"]},
}


def _spec(**tables):
    data = copy.deepcopy(SPEC)
    for name, change in tables.items():
        if change is None:
            data.pop(name, None)
        else:
            data[name] = data.get(name, {}) | change
    return data


# -- the non-dominated sorting ----------------------------------------------------------------

def _dominates(a, b) -> bool:
    """a dominates b: no worse in every objective, better in one (all minimised)."""
    return bool(np.all(a <= b) and np.any(a < b))


def _brute_force_ranks(points) -> np.ndarray:
    """Fronts by peeling: front 1 the points no other dominates, front 2 those no remaining
    point dominates, … (1-based)."""
    n = len(points)
    rank = np.zeros(n, dtype=int)
    left = set(range(n))
    r = 0
    while left:
        r += 1
        layer = [i for i in left if not any(_dominates(points[j], points[i]) for j in left)]
        for i in layer:
            rank[i] = r
        left -= set(layer)
    return rank


def _table(values, names, feasible):
    """A SizingTable of the given objective columns; the rows not ``feasible`` fail a check."""
    failed = np.zeros((len(feasible), len(js.CHECKS)), bool)
    failed[:, list(js.CHECKS).index("pitting")] = ~np.asarray(feasible)
    return js.SizingTable({n: np.asarray(values[:, j], float) for j, n in enumerate(names)},
                          failed)


NAMES = ("mass_kg", "least_margin", "mesh_loss_W", "volume_m3")


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.data())
def test_fronts_equal_a_brute_force_peeling(data):
    """pareto_rank over the feasible rows with a value in every objective equals the fronts
    peeled by the dominance relation (small integers: many ties and duplicates), each
    objective minimised or maximised; the rest rank 0."""
    k = data.draw(st.integers(2, 4))
    n = data.draw(st.integers(1, 40))
    values = np.array(data.draw(st.lists(st.lists(st.integers(0, 5), min_size=k, max_size=k),
                                         min_size=n, max_size=n)), float)
    feasible = np.array(data.draw(st.lists(st.booleans(), min_size=n, max_size=n)))
    if data.draw(st.booleans()):  # a feasible row without a value (no mesh loss, say)
        values[data.draw(st.integers(0, n - 1)), data.draw(st.integers(0, k - 1))] = np.nan
    senses = data.draw(st.lists(st.sampled_from(["min", "max"]), min_size=k, max_size=k))
    objectives = tuple(zip(NAMES[:k], senses, strict=True))
    front = js.pareto_front(_table(values, NAMES[:k], feasible), objectives)
    ranked = feasible & np.all(np.isfinite(values), axis=1)
    want = np.zeros(n, dtype=int)
    rows = np.flatnonzero(ranked)
    signed = values * np.array([1.0 if s == "min" else -1.0 for s in senses])
    want[rows] = _brute_force_ranks(signed[rows])
    assert np.array_equal(front.rank, want)
    if rows.size:
        assert front.chosen in set(np.flatnonzero(want == 1))
        best = js.pareto_front(_table(values, NAMES[:k], feasible), objectives, chosen=NAMES[0])
        first = signed[rows, 0].min()
        assert signed[best.chosen, 0] == first  # the best of the first objective
        # among equals in it, no other row of front 1 is better in the others in order
        ties = [i for i in rows if want[i] == 1 and signed[i, 0] == first]
        assert tuple(signed[best.chosen, 1:]) == min(tuple(signed[i, 1:]) for i in ties)
    else:
        assert front.chosen is None


def test_knee_is_the_compromise_of_a_hand_worked_front():
    """Front 1 of (mass min, margin max): (10, 1.0), (11, 1.8), (20, 2.0) and a dominated
    (12, 1.5). Scaled over the front (mass 10…20 → 0…1, margin 2.0…1.0 → 0…1): distances to
    the ideal (0, 0): 1, √(0.1² + 0.2²) = 0.224, 1: the knee is the second; scaling an
    objective's unit keeps it; "least_margin" chooses the third, "mass_kg" the first."""
    values = np.array([[10.0, 1.0], [12.0, 1.5], [11.0, 1.8], [20.0, 2.0]])
    obj = (("mass_kg", "min"), ("least_margin", "max"))
    table = _table(values, ("mass_kg", "least_margin"), np.ones(4, bool))
    front = js.pareto_front(table, obj)
    assert list(front.rank) == [1, 2, 1, 1] and front.chosen == 2 and front.rule == "knee"
    assert list(front.front) == [0, 2, 3]
    scaled = _table(values * [1e3, 1.0], ("mass_kg", "least_margin"), np.ones(4, bool))
    assert js.pareto_front(scaled, obj).chosen == 2
    assert js.pareto_front(table, obj, chosen="least_margin").chosen == 3
    assert js.pareto_front(table, obj, chosen="mass_kg").chosen == 0
    none = js.pareto_front(_table(values, ("mass_kg", "least_margin"), np.zeros(4, bool)), obj)
    assert none.chosen is None and not none.rank.any()


@pytest.mark.parametrize("objectives,chosen,message", [
    ((("mass_kg", "min"),), "knee", "objectives = ('mass_kg',) is out of range: allowed 2 to 6"),
    ((("mass_kg", "min"), ("mass_kg", "max")), "knee", "none twice"),
    ((("mass_kg", "least"), ("least_margin", "max")), "knee",
     "objectives entry ('mass_kg', 'least') is out of range"),
    ((("mass", "min"), ("least_margin", "max")), "knee", "objectives entry ('mass', 'min')"),
    ((("mass_kg", "min"), ("least_margin", "max")), "volume_m3",
     "chosen = 'volume_m3' is out of range: allowed 'knee', 'mass_kg', 'least_margin'"),
])
def test_pareto_front_refuses_bad_objectives_in_one_line(objectives, chosen, message):
    table = _table(np.ones((2, 2)), ("mass_kg", "least_margin"), np.ones(2, bool))
    with pytest.raises(ValueError) as err:
        js.pareto_front(table, objectives, chosen)
    assert str(err.value).startswith("pareto_front: ") and message in str(err.value)
    assert "\n" not in str(err.value)


def test_pareto_front_names_a_missing_column():
    table = _table(np.ones((2, 2)), ("mass_kg", "least_margin"), np.ones(2, bool))
    with pytest.raises(ValueError, match=r"^pareto_front: objective 'mesh_loss_W' is not a "
                       r"column of the table \(the mesh loss's columns need the spec's "):
        js.pareto_front(table, (("mass_kg", "min"), ("mesh_loss_W", "min")))


# -- the objective columns of a sized spec ----------------------------------------------------

@pytest.fixture(scope="module")
def sized():
    spec, tables = jio.parse_sizing_spec(_spec())
    return spec, tables, js.size(spec)


def test_mesh_loss_equals_the_tribology_model_on_each_candidates_pair(sized):
    """Every candidate with a valid geometry: μ_mZ, H_V, P_VZP = μ H_V T ω and η_Z of the
    table equal jaxgear.tribology's Schlenk (X_L 0.85) and Ohlendorf called on the candidate's
    own GearPair to 1e-9; the envelope volume equals the box of the pair's tip circles; NaN
    where the geometry is invalid."""
    spec, _, table = sized
    c = table.columns
    lub = tr.Lubricant(220e-6, 19e-6, 895.0, 20e-9, 70.0)
    torque, speed = 120.0, 1500.0 * math.pi / 30
    valid = np.isfinite(c["S_H1"])
    assert 10 < valid.sum() < len(table)
    for k in np.flatnonzero(valid):
        row = {n: v[k] for n, v in c.items()}
        pair = _pair(row, spec)
        mu = float(tr.Schlenk(0.85).coefficient(pair, lub, torque, speed, (0.5e-6, 0.7e-6)))
        h_v = tr.ohlendorf_loss_factor(pair)
        close = lambda a, b: np.testing.assert_allclose(a, b, rtol=1e-9, atol=0)
        close(row["friction_coefficient"], mu)
        close(row["loss_factor"], h_v)
        close(row["mesh_loss_W"], mu * h_v * torque * speed)
        close(1 - row["efficiency"], mu * h_v)
        ra1, ra2 = pair.tip_radii
        close(row["volume_m3"], (pair.center_distance + ra1 + ra2) * 2 * max(ra1, ra2)
              * pair.face_width)
    for name in js.MESH_LOSS_COLUMNS:
        assert np.all(np.isnan(c[name][~valid]))


def test_a_given_friction_coefficient_gives_the_loss_of_that_mu(sized):
    """[lubricant] friction_coefficient: μ is that value for every candidate and the loss
    μ H_V T ω (H_V unchanged); the objectives default to mass and margin without [pareto]."""
    table = sized[2]
    lub = dict(SPEC["lubricant"])
    del lub["lubricant_factor"]
    given_spec, _ = jio.parse_sizing_spec(
        _spec(pareto=None, lubricant=None) | {"lubricant": lub | {"friction_coefficient": 0.04}})
    assert given_spec.objectives == (("mass_kg", "min"), ("least_margin", "max"))
    assert given_spec.chosen == "knee"
    cols = js.objective_columns(given_spec, table.columns, np.isnan(table.columns["S_H1"]))
    ok = np.isfinite(table.columns["S_H1"])
    np.testing.assert_array_equal(cols["friction_coefficient"][ok], 0.04)
    np.testing.assert_allclose(cols["loss_factor"][ok], table.columns["loss_factor"][ok],
                               rtol=1e-15)
    np.testing.assert_allclose(cols["mesh_loss_W"][ok],
                               0.04 * cols["loss_factor"][ok] * 120.0 * 50 * math.pi,
                               rtol=1e-12)


def test_a_written_candidate_carries_the_oil_of_its_loss(sized):
    """The case file of a candidate holds the spec's [lubricant]: the case reader's tribology
    inputs (what jaxgear run's film and loss use) and the case's own pair give the table's
    μ, H_V and loss to 1e-9 (the case's rating: tests/test_sizing.py)."""
    spec, tables, table = sized
    front = js.pareto_front(table, spec.objectives, spec.chosen)
    k = front.chosen
    row = {n: v[k] for n, v in table.columns.items()}
    text = jio.candidate_case_text(tables, spec, row, k)
    assert tomllib.loads(text)["lubricant"] == SPEC["lubricant"]
    case = jio.parse_case(tomllib.loads(text))
    inputs = jio.tribology_of(case)
    torque = float(tomllib.loads(text)["operating"]["torque_Nm"])
    mu = float(inputs.friction.coefficient(case.pair, inputs.lubricant, torque, inputs.speed,
                                           inputs.roughness))
    h_v = tr.ohlendorf_loss_factor(case.pair)
    np.testing.assert_allclose([mu, h_v, mu * h_v * torque * inputs.speed],
                               [row["friction_coefficient"], row["loss_factor"],
                                row["mesh_loss_W"]], rtol=1e-9)


# -- the command -------------------------------------------------------------------------------

def _toml(data) -> str:
    lines = [f'name = "{data["name"]}"']
    for table, values in data.items():
        if isinstance(values, dict):
            lines.append(f"[{table}]")
            lines += [f"{k} = " + json.dumps(v) for k, v in values.items()]
    return "\n".join(lines) + "\n"


def test_jaxgear_size_writes_the_rank_column_the_front_and_its_figures(sized, tmp_path):
    """sizing.csv's pareto_rank: 1 exactly on the feasible rows no feasible row dominates in
    (mass, mesh loss, −margin) (brute force here), 0 on the infeasible; sizing.json's front,
    chosen design (on the front) and figures, each written as a PNG; none of them without a
    feasible candidate (``sized``: the program the command reuses, compiled once)."""
    path = tmp_path / "small.toml"
    path.write_text(_toml(SPEC), encoding="utf-8")
    out = tmp_path / "out"
    # without the TE stage (its columns are not objectives here: tests/test_sizing_te.py)
    assert main(["size", str(path), "--out", str(out), "--quiet", "--te", "0"]) == 0
    with open(out / "sizing.csv", encoding="utf-8") as f:
        rows = list(csv.DictReader(f))
    rank = np.array([int(r["pareto_rank"]) for r in rows])
    feasible = np.array([r["feasible"] == "1" for r in rows])
    pts = np.array([[float(r["mass_kg"] or "nan"), float(r["mesh_loss_W"] or "nan"),
                     -float(r["least_margin"] or "nan")] for r in rows])
    on_front = [i for i in np.flatnonzero(feasible)
                if not any(_dominates(pts[j], pts[i]) for j in np.flatnonzero(feasible))]
    assert 1 < len(on_front) < feasible.sum()
    assert set(np.flatnonzero(rank == 1)) == set(on_front)
    assert np.all(rank[~feasible] == 0) and np.all(rank[feasible] >= 1)
    summary = json.loads((out / "sizing.json").read_text(encoding="utf-8"))
    assert summary["pareto_front"] == sorted(on_front)
    assert summary["chosen"]["row"] in on_front and summary["chosen"]["rule"] == "knee"
    assert [o["column"] for o in summary["objectives"]] == ["mass_kg", "mesh_loss_W",
                                                           "least_margin"]
    assert summary["plots"] == ["pareto_mass_kg__mesh_loss_W.png",
                                "pareto_mass_kg__least_margin.png",
                                "pareto_mesh_loss_W__least_margin.png", "contact_ratios.png"]
    for name in summary["plots"]:
        assert (out / name).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n", name
    # no feasible candidate: no front, no chosen design, no figure
    heavy = copy.deepcopy(SPEC)
    heavy["operating"]["torque_Nm"] = 5000.0
    path.write_text(_toml(heavy), encoding="utf-8")
    assert main(["size", str(path), "--out", str(tmp_path / "none"), "--quiet",
                 "--te", "0"]) == 0
    summary = json.loads((tmp_path / "none" / "sizing.json").read_text(encoding="utf-8"))
    assert summary["feasible"] == 0 and summary["chosen"] is None and summary["plots"] == []
    assert not list((tmp_path / "none").glob("*.png"))


BAD = [
    ({"pareto": {"minimise": ["mass"]}},
     "[pareto] minimise = ['mass']: 'mass' is not an objective: allowed mass_kg, volume_m3"),
    ({"pareto": {"minimise": ["mass_kg"], "maximise": ["mass_kg"]}},
     "[pareto] maximise = ['mass_kg']: 'mass_kg' is named twice"),
    ({"pareto": {"minimise": ["mass_kg"], "maximise": []}},
     "[pareto] minimise = ['mass_kg']: 1 objectives with maximise: allowed 2 to 6"),
    ({"pareto": {"choose": "lightest"}}, "[pareto] choose = 'lightest': allowed 'knee', 'mass_kg'"),
    ({"pareto": {"minimize": ["mass_kg"]}}, "[pareto] unknown key 'minimize'"),
    ({"pareto": {"minimise": "mass_kg"}}, "[pareto] minimise = 'mass_kg': allowed a list"),
    ({"lubricant": None},
     "[pareto] minimise = ['mass_kg', 'mesh_loss_W']: 'mesh_loss_W' needs a [lubricant] table"),
    ({"lubricant": {"film": "grubin"}}, "[lubricant] film: not read by a sizing"),
    ({"lubricant": {"oil_temperature_C": 300.0}}, "[lubricant] oil_temperature_C = 300: out"),
]


@pytest.mark.parametrize("change,message", BAD, ids=[m.split(":")[0] for _, m in BAD])
def test_bad_pareto_and_lubricant_tables_are_refused_in_one_line(change, message):
    data = copy.deepcopy(SPEC)
    for table, value in change.items():
        if value is None:
            del data[table]
        elif table == "pareto":
            data[table] = value
        else:
            data[table] = data[table] | value
    with pytest.raises(ValueError) as err:
        jio.parse_sizing_spec(data)
    text = str(err.value)
    assert text.startswith(message) and "\n" not in text, text


# default tier: the notebook's pieces (the fronts, the case file's rating in tests/test_sizing.py)
# and its stored outputs (tests/test_notebook_outputs.py)
@pytest.mark.slow
def test_explore_notebook_executes(tmp_path):
    """examples/sizing/explore.ipynb runs in a fresh kernel (the example spec copied beside
    it): its front 1 is the brute-force one over (mass, loss, −margin), its pick the lightest
    of front 1 with a margin of 1.2 or more, and the case file it writes rates to the table's
    S_H and S_F to 1e-9; two figures inline, numbers for people."""
    import pathlib
    import re
    import shutil

    import nbformat
    from _notebooks import execute_with_probe

    folder = pathlib.Path(__file__).resolve().parents[1] / "examples" / "sizing"
    shutil.copy(folder / "helical.toml", tmp_path / "helical.toml")
    nb = nbformat.read(folder / "explore.ipynb", as_version=4)
    probe = """import json
print("PROBE" + json.dumps({
    "points": np.stack([cols["mass_kg"], cols["mesh_loss_W"], -cols["least_margin"]], 1).tolist(),
    "feasible": table.feasible.tolist(), "rank": front.rank.tolist(), "knee": front.chosen,
    "lightest": lightest, "S_H": np.asarray(rating.pitting.S_H).tolist(),
    "S_F": np.asarray(rating.bending.S_F).tolist(),
    "row": [row["S_H1"], row["S_H2"], row["S_F1"], row["S_F2"]], "path": str(path)}))"""
    code, text, got = execute_with_probe(nb, probe, tmp_path)
    pngs = [o for c in code for o in c.outputs if "image/png" in o.get("data", {})]
    assert len(pngs) == 2
    assert not re.search(r"\d\.\d{7,}", text) and "array(" not in text, text
    pts = np.array(got["points"], float)
    feasible = np.flatnonzero(got["feasible"])
    front = [i for i in feasible if not any(_dominates(pts[j], pts[i]) for j in feasible)]
    assert sorted(front) == [i for i, r in enumerate(got["rank"]) if r == 1]
    assert got["knee"] in front
    reserve = [i for i in front if -pts[i, 2] >= 1.2]
    assert got["lightest"] == min(reserve, key=lambda i: (pts[i, 0], i))
    np.testing.assert_allclose([*got["S_H"], *got["S_F"]], got["row"], rtol=1e-9)
    assert (tmp_path / got["path"]).is_file()
