"""The transmission-error stage of a sizing (jaxgear.sizing.te_stage, jaxgear size --te): a
candidate's TE columns against the library's quasi-static solve of its written case files (the
plain one and the one with the optimised flanks) as jaxgear run makes it, its mesh-order
amplitudes against a DFT written here; the optimised flanks' TE below the plain flanks'; the
batched curves against one candidate at a time; the stage's keys refused in one line."""

from __future__ import annotations

import copy
import csv
import math
import tomllib

import numpy as np
import pytest
from test_sizing import _refused, _spec as _small_spec

import jaxgear as jg
import jaxgear.io as jio
import jaxgear.sizing as js
from jaxgear.cli import main

# the small helical reducer of tests/test_sizing.py narrowed to one module and three pinions
# (a few feasible candidates), the stage at two torques and a short optimisation: cheap
SPEC = _small_spec(normal_module_min_mm=2.5, normal_module_max_mm=2.5, z1_min=18, z1_max=20,
                  te_candidates=1, te_torque_min_percent=50.0, te_torques=2,
                  te_max_iterations=20)
SPEC["name"] = "small-te"


def _spec(**sizing):
    data = copy.deepcopy(SPEC)
    data["sizing"].update(sizing)
    return data


@pytest.fixture(scope="module")
def staged():
    spec, tables = jio.parse_sizing_spec(_spec())
    table = js.size(spec)
    settings = jio.sizing_te_settings(tables)
    return spec, tables, js.te_stage(spec, table, settings), settings


def _mesh_order_amplitude(te, order):
    """|2/P Σ te_k exp(−2πi order k/P)|: the amplitude of mesh order ``order`` of one mesh
    period sampled at P equal steps (a sine of amplitude A reads A)."""
    p = te.size
    k = np.arange(p)
    return 2.0 / p * abs(np.sum(te * np.exp(-2j * math.pi * order * k / p)))


def _case(text):
    return jio.parse_case(tomllib.loads(text))


def test_te_columns_equal_the_quasi_static_solve_of_the_written_cases(staged):
    """The plain case file (``jaxgear size --write``) and the modified one
    (``candidate_K_modified.toml``) solved as jaxgear run solves them (its mesh model, its
    positions, two mesh periods, exact contact) at each torque of the range give the row's
    peak-to-peaks and mesh-order amplitudes to 1e-9."""
    spec, tables, table, settings = staged
    c = table.columns
    evaluated = np.flatnonzero(c["stage"] == "te")
    assert evaluated.tolist() == table.ranked()[:1].tolist()
    k = int(evaluated[0])
    row = {n: v[k] for n, v in c.items()}
    close = lambda a, b: np.testing.assert_allclose(a, b, rtol=1e-9, atol=0)
    torques = float(spec.operating.torque) * np.asarray(settings.torque_fractions)
    for suffix, modified in (("", False), ("_modified", True)):
        case = _case(jio.candidate_case_text(tables, spec, row, k, modified=modified))
        mesh, ppp = case.mesh_model(), case.positions_per_pitch
        mods = case.modifications if modified else None
        ppk = []
        for t in torques:
            te = np.asarray(jg.quasi_static(mesh, mods, t, positions_per_pitch=ppp,
                                            periods=2).transmission_error)
            ppk.append(te.max() - te.min())
        close(ppk[-1], row[f"te_ppk{suffix}_m"])
        close(max(ppk), row[f"te_ppk_max{suffix}_m"])
        period = te[:ppp]  # the rated torque's, the last; the second period repeats the first
        np.testing.assert_allclose(te[ppp:], period, rtol=0, atol=1e-12 * np.abs(te).max())
        close(_mesh_order_amplitude(period, 1), row[f"te_h1{suffix}_m"])
        close(_mesh_order_amplitude(period, 2), row[f"te_h2{suffix}_m"])
    # the modified case carries the row's amounts, both members alike
    m = case.modifications
    for member in (m.pinion, m.gear):
        close(float(member.tip_relief_depth), row["tip_relief_depth_m"])
        close(float(member.tip_relief_extent), row["tip_relief_extent"])
        close(float(member.crowning_depth), row["crowning_depth_m"])
    # the others: not evaluated, NaN
    rest = c["stage"] != "te"
    assert rest.any() and np.all(np.isnan(c["te_ppk_m"][rest]))
    assert np.all(np.isnan(c["tip_relief_depth_m"][rest]))


def test_optimised_flanks_lower_the_rated_te(staged):
    """The optimiser's tip relief and crowning (TE peak-to-peak at the rated torque) give a
    lower TE there than the plain flanks, with a relief that acts (depth above 1 µm)."""
    _, _, table, _ = staged
    c = table.columns
    k = int(np.flatnonzero(c["stage"] == "te")[0])
    assert c["te_ppk_modified_m"][k] <= c["te_ppk_m"][k]
    assert c["te_ppk_modified_m"][k] < 0.5 * c["te_ppk_m"][k]
    assert c["tip_relief_depth_m"][k] > 1e-6 and 0 < c["tip_relief_extent"][k] < 1
    assert 1 <= c["te_iterations"][k] <= 20


def test_batched_curves_equal_one_candidate_at_a_time(staged):
    """te_curves' batched program (meshes grouped by their static layout, padded to a power of
    two) gives each candidate's curves as the single-candidate solve does; a failed solve
    gives NaN curves."""
    spec, _, table, settings = staged
    idx = table.ranked()[:3]
    meshes = [js.candidate_mesh(spec, js.candidate_pair(spec, {n: v[i] for n, v in
                                                              table.columns.items()}))
              for i in idx]
    torques = float(spec.operating.torque) * np.asarray(settings.torque_fractions)
    batched = js.te_curves(meshes, None, torques)
    loop = js.te_curves(meshes, None, torques, batched=False)
    assert batched.shape == (3, 2, 16)
    np.testing.assert_allclose(batched, loop, rtol=1e-12, atol=1e-20)
    # a load that closes the tip corners' gap at the far end of the cells: the solve fails
    # (jaxgear.ContactResult), the curves are NaN, batched or not
    for b in (True, False):
        assert np.all(np.isnan(js.te_curves(meshes[:1], None, [1e8, 2e8], batched=b)))


def test_batched_optimiser_equals_one_candidate_at_a_time(staged):
    """optimise.minimise_batch of three candidates' modification problems (one mesh layout: one
    vmapped solve, padded to four) gives each candidate the optimum optimise.minimise finds
    from the same start: the same accepted iterations and history length, the design within
    1e-6 (normalised units; the solver's Cauchy tolerance is 1e-7) and the objective within
    1e-8 relative, at every iterate too; a start outside the bounds is refused before any
    solve, naming it."""
    import warnings

    import optimise
    from jaxgear.sizing._te import _start

    spec, _, table, settings = staged
    meshes = [js.candidate_mesh(spec, js.candidate_pair(spec, {n: v[i] for n, v in
                                                              table.columns.items()}))
              for i in table.ranked()[:3]]
    problems = [optimise.make_problem(m, None, float(spec.operating.torque),
                                      ",".join(js.TE_VARIABLES), optimise.TePeakToPeak(),
                                      positions_per_pitch=16) for m in meshes]
    starts = [_start(p) for p in problems]
    cap = settings.max_iterations
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        one = [optimise.minimise(p, x, max_iterations=cap, progress=False)
               for p, x in zip(problems, starts, strict=True)]
        batch = optimise.minimise_batch(problems, starts, max_iterations=cap)
    for a, b in zip(one, batch, strict=True):
        assert b.iterations == a.iterations and b.converged == a.converged
        assert b.history_x.shape == a.history_x.shape
        np.testing.assert_allclose(b.x, a.x, rtol=0, atol=1e-6)
        np.testing.assert_allclose(b.history_x, a.history_x, rtol=0, atol=1e-6)
        np.testing.assert_allclose(b.history_value, a.history_value, rtol=1e-8)
        np.testing.assert_array_equal(b.x0, a.x0)
    with pytest.raises(ValueError, match="is outside the bounds"):
        optimise.minimise_batch(problems[:1], [np.asarray(starts[0]) + 1e3])


def test_the_stage_settings_of_a_spec():
    _, tables = jio.parse_sizing_spec(_spec(te_torques=4, te_torque_min_percent=25.0))
    s = jio.sizing_te_settings(tables)
    assert s.torque_fractions == (0.25, 0.5, 0.75, 1.0) and s.candidates == 1
    assert jio.sizing_te_settings(tables, 0).candidates == 0
    _, tables = jio.parse_sizing_spec(_spec(te_torques=1))
    assert jio.sizing_te_settings(tables).torque_fractions == (1.0,)
    data = _spec()
    for key in ("te_candidates", "te_torque_min_percent", "te_torques", "te_max_iterations"):
        del data["sizing"][key]
    s = jio.sizing_te_settings(jio.parse_sizing_spec(data)[1])
    assert s == js.TeSettings()


BAD = [
    ({"te_candidates": -1}, "[sizing] te_candidates = -1: out of range"),
    ({"te_candidates": 2.5}, "[sizing] te_candidates = 2.5:"),
    ({"te_torque_min_percent": 0.0}, "[sizing] te_torque_min_percent = 0: out of range"),
    ({"te_torque_min_percent": 120.0}, "[sizing] te_torque_min_percent = 120: out of range"),
    ({"te_torques": 0}, "[sizing] te_torques = 0: out of range"),
    ({"te_torques": 17}, "[sizing] te_torques = 17: out of range"),
    ({"te_max_iterations": 0}, "[sizing] te_max_iterations = 0: out of range"),
]


@pytest.mark.parametrize("change,message", BAD, ids=[m.split(":")[0] for _, m in BAD])
def test_bad_stage_keys_are_refused_in_one_line(change, message):
    _refused(_spec(**change), message)


@pytest.mark.parametrize("kwargs,message", [
    ({"candidates": -2}, "TeSettings: candidates = -2 is out of range"),
    ({"torque_fractions": (0.5, 0.9)}, "TeSettings: torque_fractions = (0.5, 0.9) is out of"),
    ({"torque_fractions": (1.0, 0.5, 1.0)}, "TeSettings: torque_fractions = (1.0, 0.5, 1.0)"),
    ({"max_iterations": 0}, "TeSettings: max_iterations = 0 is out of range"),
])
def test_bad_settings_are_refused_in_one_line(kwargs, message):
    with pytest.raises(ValueError) as err:
        js.TeSettings(**kwargs)
    assert str(err.value).startswith(message) and "\n" not in str(err.value)


def _toml(data) -> str:
    lines = [f'name = "{data["name"]}"']
    for table, values in data.items():
        if isinstance(values, dict):
            lines.append(f"[{table}]")
            for k, v in values.items():
                lines.append(f"{k} = " + (f'"{v}"' if isinstance(v, str) else repr(v)))
    return "\n".join(lines) + "\n"


@pytest.mark.usefixtures("no_figures")
def test_jaxgear_size_runs_the_stage_and_writes_both_cases(staged, tmp_path, capsys):
    """``jaxgear size`` (the spec's stage: one candidate, the fixture's settings: the same
    compiled programs) writes the stage's columns and, for an evaluated candidate, the plain
    and the modified case files; ``--te -1`` is refused in one line before any work."""
    spec, tables, table, _ = staged
    path = tmp_path / "small.toml"
    path.write_text(_toml(SPEC))
    out = tmp_path / "out"
    k = int(np.flatnonzero(table.columns["stage"] == "te")[0])
    assert main(["size", str(path), "--out", str(out), "--write", str(k), "--quiet"]) == 0
    with open(out / "sizing.csv", encoding="utf-8") as f:
        rows = list(csv.DictReader(f))
    assert [r["stage"] for r in rows] == list(table.columns["stage"])
    assert float(rows[k]["te_ppk_modified_m"]) == table.columns["te_ppk_modified_m"][k]
    assert rows[k - 1 if k else k + 1]["te_ppk_m"] == ""
    row = {n: v[k] for n, v in table.columns.items()}
    assert (out / f"candidate_{k}.toml").read_text(encoding="utf-8") == \
        jio.candidate_case_text(tables, spec, row, k)
    assert (out / f"candidate_{k}_modified.toml").read_text(encoding="utf-8") == \
        jio.candidate_case_text(tables, spec, row, k, modified=True)
    assert main(["size", str(path), "--out", str(tmp_path / "o2"), "--te", "-1"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--te -1: out of range, allowed an integer >= 0" in err[0]
    assert not (tmp_path / "o2").exists()
    with pytest.raises(ValueError, match=r"^candidate_case_text: modified = True for candidate"):
        other = int(np.flatnonzero(table.columns["stage"] != "te")[0])
        jio.candidate_case_text(tables, spec, {n: v[other] for n, v in
                                               table.columns.items()}, other, modified=True)


# default tier: test_te_columns_equal_the_quasi_static_solve_of_the_written_cases (the solve
# jaxgear run makes, without the rest of the run)
@pytest.mark.slow
def test_jaxgear_run_on_the_written_cases_gives_the_te_columns(staged, tmp_path):
    """The whole ``jaxgear run`` on the plain and the modified case files of an evaluated
    candidate: summary.json's exact-contact TE peak-to-peak at the rated torque, unmodified
    and modified, equal the row's to 1e-9."""
    import json

    spec, tables, table, _ = staged
    k = int(np.flatnonzero(table.columns["stage"] == "te")[0])
    row = {n: v[k] for n, v in table.columns.items()}
    for modified, key, column in ((False, "quasi_static_unmodified", "te_ppk_m"),
                                  (True, "quasi_static", "te_ppk_modified_m")):
        path = tmp_path / f"candidate_{modified}.toml"
        path.write_text(jio.candidate_case_text(tables, spec, row, k, modified=modified),
                        encoding="utf-8")
        out = tmp_path / f"run_{modified}"
        assert main(["run", str(path), "--out", str(out), "--quiet"]) == 0
        summary = json.loads((out / "summary.json").read_text(encoding="utf-8"))
        np.testing.assert_allclose(summary[key]["exact"]["te_ptp_m"], row[column], rtol=1e-9)
