"""A rolling bearing's clearance as a design variable (docs/bearings.md, "As a design variable"):
the scene's stiffness as a JAX function of the designed bearings' stiffness, the derivative of
the ERP of a housed case with respect to a clearance, the refusals, an optimisation.

References, each apart from the code under test: the scene assembled again in NumPy on the
changed bearing (``lumped_pair`` on a bearing of that stiffness, the housing's coupling
included); central finite differences of the objective re-evaluated at c ± h with the loads
held; a central difference of whole re-runs (the case file at c ± h, its operating point, model
and acoustic path built again); the optimum's objective evaluated on a scene assembled in
NumPy on the bearing's stiffness at the optimum."""

from __future__ import annotations

import dataclasses
import json
import tomllib
from pathlib import Path

import equinox as eqx
import jax.numpy as jnp
import numpy as np
import pytest
from _convergence import gradient_and_differences
from _housing import HOUSING_TABLE, WHINE_TABLE, two_seat_housing

import jaxgear as jg
import jaxgear.bearings as jb
import jaxgear.io as jio
import optimise as op
from jaxgear.cli import main
from jaxgear.dynamics import OperatingPoint, with_bearing_stiffness
from jaxgear.io._case_model import _lumped3d_pair
from jaxgear.scenes import Bearing

ROOT = Path(__file__).resolve().parents[1]
ROLLING = ROOT / "examples" / "accessory-lumped3d-rolling.toml"
LINEAR = ROOT / "examples" / "accessory-lumped3d.toml"
VAR = "pinion_shaft.bearings[0].clearance"


def _with_bearing(spec, shaft: str, k: int, bearing):
    """The scene spec with bearing ``k`` of ``shaft`` replaced."""
    s = getattr(spec, shaft)
    bearings = tuple(bearing if i == k else b for i, b in enumerate(s.bearings))
    return dataclasses.replace(spec, **{shaft: dataclasses.replace(s, bearings=bearings)})


def _change(kb):
    """A symmetric change of a bearing's 6x6 stiffness that keeps it positive semi-definite and
    its stiff DOFs (the force rows the assembly makes): 30 % of its own and 2 N/µm more on each
    DOF it resists."""
    return 0.3 * kb + np.diag(np.where(np.diag(kb) > 0, 2e6, 0.0))


@pytest.mark.parametrize("housed", [False, True])
def test_bearing_stiffness_change_equals_the_scene_assembled_again(housed):
    """K, its bearings part and the bearing force rows with ΔK_b added
    (with_bearing_stiffness) equal the scene assembled again in NumPy on a bearing of stiffness
    K_b + ΔK_b, on the ground and on the seats of a (synthetic) housing, to round-off."""
    case = jio.load_case(str(LINEAR))
    spec, mesh = case.scene, case.mesh_model(slices=2)
    housing = two_seat_housing()[0] if housed else None
    scene = _lumped3d_pair(case, spec, mesh, housing=housing)
    shafts = (spec.pinion_shaft, spec.gear_shaft)
    changes = {}
    for i, j, name in ((0, 1, "pinion_shaft"), (1, 0, "gear_shaft")):
        b = shafts[i].bearings[j]
        d = _change(b.stiffness_matrix())
        changes[(i, j)] = jnp.asarray(d)
        spec = _with_bearing(spec, name, j, Bearing(b.z, stiffness=b.stiffness_matrix() + d))
    got = with_bearing_stiffness(scene, shafts, changes).structure
    ref = _lumped3d_pair(case, spec, mesh, housing=housing).structure
    scale = float(np.abs(np.asarray(ref.K)).max())
    for a, b in ((got.K, ref.K), (got.parts_K, ref.parts_K), (got.reaction, ref.reaction)):
        np.testing.assert_allclose(np.asarray(a), np.asarray(b), rtol=0, atol=1e-13 * scale)
    assert got.reaction_names == ref.reaction_names
    base = np.asarray(scene.structure.K)
    assert np.abs(np.asarray(got.K) - base).max() > 1e6  # the change is there


def test_bearing_variable_parses_and_acts_on_the_structure():
    """A bearing's clearance parses by its case-file name (a train's dotted shaft name too),
    its kind declares that it acts on the structure and writes µm; the flank variables act on
    the modifications as before."""
    var = op.Variable.parse("gear_shaft.bearings[1].clearance")
    assert (var.shaft, var.bearing, var.field, var.members) == ("gear_shaft", 1, "clearance", ())
    assert isinstance(var.kind, op.Clearance) and var.kind.acts_on == "structure"
    assert var.kind.to_model(7.0, 1.0) == pytest.approx(7e-6)
    assert var.kind.file_value(7e-6) == pytest.approx(7.0)
    assert op.Variable.parse("shafts.idler.bearings[0].clearance").shaft == "shafts.idler"
    for name in ("tip_relief.depth", "pinion.crowning.depth", "end_relief.extent"):
        assert op.Variable.parse(name).kind.acts_on == "modifications"
    with pytest.raises(ValueError, match=r"'pinion_shaft\.bearings\[0\]\.stiffness' is an "
                       r"unknown design variable") as e:
        op.Variable.parse("pinion_shaft.bearings[0].stiffness")
    assert "\n" not in str(e.value)


@pytest.fixture(scope="module")
def small_point():
    """The linear example's shafts with the pinion's first bearing a 6206 from its geometry at
    the ring displacement that carries 1300 N radially (an operating point written by hand, no
    fixed point), and the grounded quasi-static scene on them."""
    case = jio.load_case(str(LINEAR))
    spec = case.scene
    kind = jb.DeepGrooveBall(bore=0.03, outer_diameter=0.062, width=0.016, elements=9,
                             element_diameter=9.525e-3, pitch_diameter=0.046, clearance=10e-6)
    load = np.array([1300.0, 0.0, 0.0, 0.0, 0.0])
    d = np.asarray(jb.solve_displacement(kind, load).displacement)
    b0 = spec.pinion_shaft.bearings[0]
    spec = _with_bearing(spec, "pinion_shaft", 0, Bearing(b0.z, rolling=kind).at(d))
    shafts = (spec.pinion_shaft, spec.gear_shaft)
    loads = ((load, None), (None, None))
    point = OperatingPoint(shafts, loads, loads, 1, 0.0)
    return case, point


@pytest.mark.parametrize(
    ("variables", "settings", "match"),
    [
        (VAR, {"bearings": None}, r"variables: 'pinion_shaft\.bearings\[0\]\.clearance' acts "
         r"on the structure: allowed with bearings = optimise\.bearing_design"),
        ("pinion_shaft.bearings[1].clearance", {}, r"'pinion_shaft\.bearings\[1\]\.clearance' "
         r"is a linear bearing \(a stiffness\): allowed on a rolling bearing"),
        ("idler.bearings[0].clearance", {}, r"unknown shaft 'idler', allowed pinion_shaft, "
         "gear_shaft"),
        ("gear_shaft.bearings[2].clearance", {}, r"gear_shaft has 2 bearings, allowed "
         r"bearings\[0\] to bearings\[1\]"),
        (VAR, {"bounds": {VAR: (-200.0, 5.0)}}, r"bounds of 'pinion_shaft\.bearings\[0\]\."
         r"clearance' = \(-200\.0, 5\.0\) µm: .*clearance"),
        (VAR, {"objective": op.DynamicFactor([100.0])}, r"objective = 'dynamic_factor' does "
         "not take a designed structure"),
    ],
)
def test_bearing_variable_refusals_one_line(small_point, variables, settings, match):
    """A bearing variable without the bearings' design, on a linear bearing, an unknown shaft
    or bearing, bounds outside the bearing's range of clearances (a preload beyond D_w/100), an
    objective that does not take a designed structure: one line, before any solve."""
    case, point = small_point
    design = op.bearing_design(point, ("pinion_shaft", "gear_shaft"))
    settings = {"bearings": design} | settings
    objective = settings.pop("objective", op.TeRms())
    with pytest.raises(ValueError, match=match) as e:
        op.make_problem(case.mesh_model(slices=2), None, case.torque, variables, objective,
                        **settings)
    assert "\n" not in str(e.value)


def test_a_tapered_pairs_clearance_variable_is_its_end_play(small_point):
    """A tapered roller pair declares its end play as its clearance field (``clearance_field``
    on the contract): its variable's value is the end play (µm), and bounds past the pair's
    preload range (−D_w/(100 tan α)) are refused in one line naming the end play."""
    case, point = small_point
    pair = jb.TaperedRollerPair.of(jb.catalogue("30205"), "O", end_play=30e-6)
    assert pair.clearance_field == "end_play" and jb.catalogue("30205").clearance_field == (
        "clearance")
    assert jb.LinearSpring().clearance_field is None
    shafts = list(point.shafts)
    b0 = shafts[0].bearings[0]
    d = np.asarray(jb.solve_displacement(pair, np.array([1300.0, 0, 0, 0, 0])).displacement)
    shafts[0] = dataclasses.replace(
        shafts[0], bearings=(Bearing(b0.z, rolling=pair).at(d), *shafts[0].bearings[1:]))
    point = point._replace(shafts=tuple(shafts))
    design = op.bearing_design(point, ("pinion_shaft", "gear_shaft"))
    var = op.Variable.parse(VAR)
    assert design.case_value(var) == pytest.approx(30.0)
    with pytest.raises(ValueError, match=r"bounds of 'pinion_shaft\.bearings\[0\]\.clearance' "
                       r"= \(-300\.0, 5\.0\) µm: .*end_play") as e:
        design.check_bounds(var, -300.0, 5.0)
    assert "\n" not in str(e.value)


@pytest.mark.slow  # the lumped 3D scene assembled, the held solve compiled (about 20 s)
def test_the_designed_scene_at_the_operating_clearance_is_the_scene(small_point):
    """At the operating point's clearance c₀ the designed scene (``apply``, K_b(c₀) held once
    in the design) is the scene it was given: exactly, evaluated eagerly; to round-off
    (1e-15 of its largest stiffness) compiled; and 1 µm away it is not."""
    import jax

    case, point = small_point
    spec = dataclasses.replace(case.scene, pinion_shaft=point.shafts[0])
    scene = _lumped3d_pair(case, spec, case.mesh_model(slices=2))
    design = op.bearing_design(point, ("pinion_shaft", "gear_shaft"))
    var = op.Variable.parse(VAR)
    c0 = design.clearance(var)
    assert c0 == pytest.approx(10e-6)

    def structure(s, c):
        return design.apply(s, [var], [c]).structure

    base = scene.structure
    scale = float(np.abs(np.asarray(base.K)).max())
    eager = structure(scene, jnp.asarray(c0))
    for a, b in ((eager.K, base.K), (eager.parts_K, base.parts_K),
                 (eager.reaction, base.reaction)):
        np.testing.assert_array_equal(np.asarray(a), np.asarray(b))
    compiled = jax.jit(structure)(scene, jnp.asarray(c0))
    for a, b in ((compiled.K, base.K), (compiled.parts_K, base.parts_K),
                 (compiled.reaction, base.reaction)):
        np.testing.assert_allclose(np.asarray(a), np.asarray(b), rtol=0, atol=1e-15 * scale)
    moved = structure(scene, jnp.asarray(c0 + 1e-6))
    assert np.abs(np.asarray(moved.K) - np.asarray(base.K)).max() > 1e3


def _rolling_text(**changes) -> str:
    text = ROLLING.read_text()
    for old, new in changes.items():
        text = text.replace(old, new)
    return text


@pytest.mark.parametrize(
    ("case_file", "optimise", "match"),
    [
        (LINEAR, f'vars = ["{VAR}"]', r"\[optimise\] vars = .*'pinion_shaft\.bearings\[0\]\."
         r"clearance' is a linear bearing: a clearance is allowed on a rolling bearing from "
         "its geometry"),
        (ROLLING, 'vars = ["gear_shaft.bearings[3].clearance"]', r"\[optimise\] vars = .*"
         r"\[scene\.gear_shaft\] has 2 bearings, allowed bearings\[0\] to bearings\[1\]"),
        (ROLLING, 'vars = ["idler.bearings[0].clearance"]', r"\[optimise\] vars = .*no "
         r"\[scene\.idler\] of a lumped3d scene, allowed the shafts pinion_shaft, gear_shaft"),
        (ROLLING, f'vars = ["{VAR}"]\n[optimise.bounds]\n"{VAR}" = [5.0, -5.0]',
         r"\[optimise\.bounds\] 'pinion_shaft\.bearings\[0\]\.clearance' = \[5, -5\]: out of "
         r"range, allowed \[lo, hi\] with lo < hi \(µm"),
    ],
)
def test_case_file_bearing_variable_refused_one_line(tmp_path, case_file, optimise, match):
    """``[optimise] vars`` naming a linear bearing's clearance, a bearing or a shaft the scene
    does not have, crossed bounds: one line naming the key when the case loads."""
    path = tmp_path / "c.toml"
    text = Path(case_file).read_text()
    path.write_text(text + "\n[optimise]\n" + optimise + "\n")
    with pytest.raises(jio.SchemaError, match=match) as e:
        jio.load_case(str(path))
    assert "\n" not in str(e.value)


def test_case_file_bearing_variable_loads_and_the_command_refuses_it(tmp_path, capsys):
    """The rolling example with a bearing's clearance in ``[optimise] vars`` (bounds in µm)
    loads; ``jaxgear optimise`` with a quasi-static objective refuses it in one line (exit
    status 2, nothing written): the command takes it with an acoustic objective, the Python API
    (``jaxgear.io.case_problem``) with any that takes a designed structure."""
    path = tmp_path / "c.toml"
    path.write_text(ROLLING.read_text() + f'\n[optimise]\nvars = ["{VAR}"]\n'
                    f'[optimise.bounds]\n"{VAR}" = [-5.0, 15.0]\n')
    case = jio.load_case(str(path))
    assert case.optimise["bounds"] == {VAR: (-5.0, 15.0)}
    out = tmp_path / "o"
    assert main(["optimise", str(path), "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert ("a bearing's clearance is optimised by jaxgear optimise with the objective erp or "
            "sound_power (a housed case), not te_rms") in err
    assert not out.exists()


# -- the derivative of a housed case's ERP and an optimisation (slow) --------------------------
H_HELD = (0.02, 0.01)  # µm: the central differences at held loads, Richardson-extrapolated
H_RUN = 0.5  # µm: the central difference of whole re-runs


def _housed_case(tmp_path, clearance_um: float = 10.0):
    """The rolling example (4 slices) in the soft box of the housing tests with their short
    [whine] (3 speeds, 2 harmonics), its pinion's first bearing at ``clearance_um``."""
    text = ROLLING.read_text()
    assert tomllib.loads(text)["mesh"]["slices"] == 4
    first = text.index("clearance_um = 10.0")
    text = text[:first] + f"clearance_um = {clearance_um!r}" + text[first + 19:]
    path = tmp_path / f"housed-{clearance_um}.toml"
    path.write_text(text + HOUSING_TABLE + WHINE_TABLE)
    return jio.load_case(str(path))


def _assembled_at(case, clearance_um: float):
    """The case's scene spec on linear bearings of each rolling bearing's stiffness at its
    operating point, the pinion's bearing 0 at K_b(c) = stiffness6 of its displacement under
    its held load with the clearance c (µm): what the scene is assembled on in NumPy."""
    point = jio.operating_point(case)
    b = point.shafts[0].bearings[0]
    kind = eqx.tree_at(lambda k: k.clearance, b.rolling, clearance_um * 1e-6)
    k6 = np.asarray(kind.stiffness6(jb.solve_displacement(
        kind, np.asarray(point.loads[0][0])).displacement))
    linear = [dataclasses.replace(s, bearings=tuple(
        Bearing(x.z, stiffness=x.stiffness_matrix(), damping=x.damping) for x in s.bearings))
        for s in point.shafts]
    spec = dataclasses.replace(case.scene, pinion_shaft=linear[0], gear_shaft=linear[1])
    spec = _with_bearing(spec, "pinion_shaft", 0, Bearing(b.z, stiffness=k6, damping=b.damping))
    assert not spec.rolling
    return spec


def _erp(case) -> tuple[op.Problem, float]:
    """The ERP problem of a housed case (mean over the speeds, A-weighted) with the pinion's
    first clearance the variable, and that case's own ERP (W, the smooth law)."""
    problem = jio.case_problem(case, VAR, "erp", reduce="mean")
    value = eqx.filter_jit(lambda p, x: p.value(x))(problem, jnp.asarray(
        problem.from_physical(problem.case_values(case.modifications))))
    return problem, float(value) * float(problem.scale)


@pytest.mark.slow  # a housed case's acoustic path three times, its gradient, three iterations
def test_clearance_derivative_of_the_erp_and_an_optimisation(tmp_path):
    """d(ERP)/dc of the housed example (pinion bearing 0's clearance, 10 µm) by jax.grad
    through the displacement solve, the assembly and the whine against (1) a central difference
    of the objective at c ± h with the loads held (Richardson over h = 0.02, 0.01 µm; 1e-5) and
    (2) a central difference (±0.5 µm) of whole re-runs, each case file's operating point,
    model, damping and acoustic path built again (the measured gap stated in docs/bearings.md);
    three L-BFGS steps move the clearance within its bounds and lower the ERP, and the optimum's
    value equals the objective evaluated on a scene assembled in NumPy on the bearing's
    stiffness at the optimum (held load) to 1e-9."""
    case = _housed_case(tmp_path)
    problem, w0 = _erp(case)
    x0 = jnp.asarray([10.0])
    value = eqx.filter_jit(lambda p, x: p.value(x))
    grad, held = gradient_and_differences(problem, x0, H_HELD)
    print(f"d(objective)/dc: grad {grad:.10g}, held-load differences {held:.10g} "
          f"(rel {abs(grad - held) / abs(held):.2g})")
    assert grad == pytest.approx(held, rel=1e-5)
    # whole re-runs: the fixed point, the model (its damping) and the path built again
    up, down = (_erp(_housed_case(tmp_path, 10.0 + s * H_RUN))[1] for s in (1, -1))
    rerun = (up - down) / (2 * H_RUN)
    slope = grad * float(problem.scale)  # W per µm
    gap = abs(slope - rerun) / abs(rerun)
    print(f"dERP/dc: held {slope:.6g} W/µm, whole re-runs {rerun:.6g} W/µm, gap {gap:.3g}; "
          f"ERP {w0:.6g} W")
    assert np.sign(slope) == np.sign(rerun)
    assert gap < 0.1
    # an optimisation moves the clearance within its bounds and lowers the ERP
    with pytest.warns(UserWarning, match="iteration cap"):
        res = op.minimise(problem, x0, max_iterations=3, progress=False)
    print(f"clearance 10 -> {float(res.x[0]):.4g} µm, objective {res.value0:.6g} -> "
          f"{res.value:.6g}")
    lo, hi = float(problem.lower[0]), float(problem.upper[0])
    assert lo < float(res.x[0]) < hi and abs(float(res.x[0]) - 10.0) > 0.1
    assert res.value < res.value0
    # the optimum's value on a scene assembled in NumPy on K_b(c*) at the held load
    scene = problem.objective.path.model.scene
    again = _lumped3d_pair(case, _assembled_at(case, float(res.x[0])), scene.base_planes[0])
    objective = eqx.tree_at(lambda o: o.path.model.scene.structure, problem.objective,
                            again.structure)
    independent = eqx.tree_at(lambda p: p.objective, problem, objective)
    mods = problem.modifications(jnp.asarray(res.x))
    ref = float(eqx.filter_jit(lambda p, m: p.design_value(m))(independent, mods))
    assert float(value(problem, jnp.asarray(res.x))) == pytest.approx(ref, rel=1e-9)
    assert res.value == pytest.approx(ref, rel=1e-9)


def test_bearing_choices_refused_one_line(tmp_path):
    """A bearing name that is not one of the case's, no candidate, a candidate the case file
    refuses: one line (the candidate named), before any solve."""
    case = jio.load_case(str(ROLLING))
    with pytest.raises(ValueError, match=r"bearing = 'idler\.bearings\[0\]': allowed "
                       r"<shaft>\.bearings\[<k>\]") as e:
        jio.bearing_choices(case, "idler.bearings[0]", {"6205": {"catalogue": "6205"}})
    assert "\n" not in str(e.value)
    with pytest.raises(ValueError, match="candidates is empty"):
        jio.bearing_choices(case, "pinion_shaft.bearings[0]", {})
    with pytest.raises(ValueError, match=r"candidate 'x': .*catalogue") as e:
        jio.bearing_choices(case, "pinion_shaft.bearings[0]", {"x": {"catalogue": "9999"}})
    assert "\n" not in str(e.value)


@pytest.mark.slow  # two housed cases' operating points, acoustic paths and optimisations
def test_bearing_choice_by_enumeration(tmp_path):
    """Bearing choice (a discrete candidate, not a gradient variable) by enumeration on the
    housed example: pinion bearing 0 as the example's 6206 (its geometry keys), as that 6206
    with 15 µm clearance, or as the catalogue's 6205, each clearance optimised (two L-BFGS
    steps), ranked by the mean ERP in W. The 6205 (ISO 15: 25 mm bore) does not fit the 30 mm
    shaft: listed last, not evaluated. The 6206 candidate's start is the example's own ERP (the
    case rewritten faithfully); each candidate's clearance stays within its bounds and its ERP
    does not rise, the 6206's moves and lowers it; the ranking is by the unscaled values."""
    case = _housed_case(tmp_path)
    own = {k: v for k, v in tomllib.loads(ROLLING.read_text())["scene"]["pinion_shaft"][
        "bearings"][0].items() if k != "position_mm"}
    with pytest.warns(UserWarning, match="iteration cap"):
        ranked = jio.bearing_choices(case, "pinion_shaft.bearings[0]",
                                     {"6206": own, "6206 C3": own | {"clearance_um": 15.0},
                                      "6205": {"catalogue": "6205"}}, "erp",
                                     max_iterations=2, reduce="mean")
    assert [c.name for c in ranked][2] == "6205"
    unfit = ranked[2]
    assert not unfit.fits and unfit.value is None and unfit.case is None
    assert unfit.bore_mm == pytest.approx(25.0, abs=0.01) and unfit.seat_mm == 30.0
    by = {c.name: c for c in ranked[:2]}
    assert set(by) == {"6206", "6206 C3"}
    assert [c.value for c in ranked[:2]] == sorted(c.value for c in ranked[:2])
    assert by["6206 C3"].start_um == pytest.approx(15.0)
    assert by["6206"].start_value == pytest.approx(_erp(case)[1], rel=1e-9)
    for c in ranked[:2]:
        print(f"{c.name}: clearance {c.start_um:.4g} -> {c.clearance_um:.4g} µm, ERP "
              f"{c.start_value:.6g} -> {c.value:.6g} W")
        assert -5.0 < c.clearance_um < 20.0 and c.value <= c.start_value
    assert abs(by["6206"].clearance_um - 10.0) > 0.1 and by["6206"].value < by[
        "6206"].start_value


@pytest.mark.slow  # the example's operating point and a quasi-static objective compiled
def test_case_problem_quasi_static_objective_runs_on_the_bearings_scene():
    """A quasi-static objective with a bearing variable runs on the case's grounded lumped 3D
    scene (not the rigid mesh), and its value at a clearance of 0 µm (the load held) equals the
    same objective on that scene assembled again in NumPy on the bearing's stiffness there."""
    from jaxgear.scenes import Grounded

    case = jio.load_case(str(ROLLING))
    problem = jio.case_problem(case, VAR, "max_line_load", positions_per_pitch=16)
    assert isinstance(problem.mesh, Grounded)
    scene = _lumped3d_pair(case, _assembled_at(case, 0.0), problem.mesh.base_planes[0])
    again = Grounded(scene, problem.mesh.stiffness_value, problem.mesh.dofs)
    x = jnp.asarray([0.0])
    res = jg.quasi_static(again, problem.modifications(x), problem.design_torque,
                          contact=problem.contact, positions_per_pitch=16)
    ref = float(problem.objective.of_result(res, problem)) / float(problem.scale)
    assert float(problem.value(x)) == pytest.approx(ref, rel=1e-9)
    assert float(problem.value(x)) != float(problem.value(jnp.asarray([10.0])))


@pytest.mark.slow  # the housed whine, its gradient, two L-BFGS steps, the written case's own
@pytest.mark.filterwarnings("ignore:optimiser stopped at the iteration cap")
def test_jaxgear_optimise_designs_a_clearance_and_writes_it(tmp_path, capsys):
    """``jaxgear optimise --objective erp --vars pinion_shaft.bearings[0].clearance`` on the
    housed example: the ERP ends below its start (exact contact), the report's per-speed powers
    at the optimum are the optimum's objective (their mean), and the case file ``--write``
    leaves carries the optimum's ``clearance_um`` in that bearing's table; that case, its
    operating point found again at the new clearance (not held), has an ERP within 1e-3 of the
    reported optimum (what holding the loads and the damping leaves out over the step; measured
    5e-5)."""
    case = _housed_case(tmp_path)
    path = tmp_path / "housed-10.0.toml"
    out, new = tmp_path / "o", tmp_path / "optimum.toml"
    assert main(["optimise", str(path), "--objective", "erp", "--reduce", "mean", "--vars", VAR,
                 "--max-iterations", "2", "--out", str(out), "--quiet",
                 "--write", str(new)]) == 0
    assert f"{VAR} = " in capsys.readouterr().out
    rep = json.loads((out / "optimum.json").read_text())
    a, b = rep["initial"]["objective_exact_W"], rep["final"]["objective_exact_W"]
    assert 0 < b < a
    np.testing.assert_allclose(np.mean(rep["acoustics"]["final"]["power_W"]), b, rtol=1e-12)
    c = rep["final"]["parameters"][VAR]
    assert -5.0 < c < 20.0 and abs(c - 10.0) > 0.1
    designed = jio.load_case(str(new))
    kind = designed.scene.pinion_shaft.bearings[0].rolling
    assert float(kind.clearance) * 1e6 == pytest.approx(c, rel=1e-12)
    assert float(designed.scene.pinion_shaft.bearings[1].rolling.clearance) == pytest.approx(1e-5)
    problem = jio.case_problem(designed, VAR, "erp", reduce="mean")
    # the written case's own path (its operating point, model and damping), its design as
    # written (sharp relief starts), exact contact: as the report evaluates the optimum
    own = float(problem.objective.at_torque(None, designed.modifications, designed.torque,
                                            jg.ExactContact()))
    print(f"clearance 10 -> {c:.4g} µm: ERP {a:.6g} -> {b:.6g} W (held loads), "
          f"{own:.6g} W from the written case")
    assert own == pytest.approx(b, rel=1e-3)
