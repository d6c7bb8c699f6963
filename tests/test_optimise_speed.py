"""tooth-modification optimisation on the hybrid scene at speed — the load-centroid
and L_p objectives, one-sided end relief, the design variables' gradients in exact contact, the
CLI, and the seed's end relief finding on the power pair (IV-33/34, slow).

References: hand-written ramps and sums (NumPy), central finite differences, grid scans in exact
contact."""

from __future__ import annotations

import dataclasses
import json
import math
import pathlib

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest
from _examples import load_example

import jaxgear as jg
import optimise as op
from jaxgear import io as jio
from jaxgear.io import static_scene

ROOT = pathlib.Path(__file__).resolve().parents[1]
DATA = ROOT / "tests" / "data"
CASE_TEXT = (DATA / "hybrid-test-case.toml").read_text()
TIP = 'tip_relief = { depth_um = 8.0, extent = 0.3, shape = "linear" }\n'


def _case_text(extra: str = "") -> str:
    """The small flexible-wheel case (wheel path made absolute), ``extra`` lines appended to its
    ``[modifications]`` table."""
    assert TIP in CASE_TEXT
    text = CASE_TEXT.replace("hybrid-test-wheel.toml", str(DATA / "hybrid-test-wheel.toml"))
    return text.replace(TIP, TIP + extra)


# -- one-sided end relief --------------------------------------------------------------------------


def _linear_end_relief(zeta, depth, extent, edge):
    """The seed's linear lead relief written out: depth·(extent − ζ)/extent on ζ < extent (z = 0
    edge), depth·(ζ − 1 + extent)/extent on ζ > 1 − extent (z = b edge)."""
    z0 = np.where(zeta < extent, depth * (extent - zeta) / extent, 0.0)
    z1 = np.where(zeta > 1 - extent, depth * (zeta - 1 + extent) / extent, 0.0)
    return {"z0": z0, "z1": z1, "both": z0 + z1}[edge]


@pytest.mark.parametrize("edge", ["both", "z0", "z1"])
def test_end_relief_on_one_or_both_edges_is_the_linear_ramp(edge):
    zeta = np.linspace(0.0, 1.0, 201)
    kw = dict(end_relief_depth=7e-6, end_relief_extent=0.4)
    edges = {"both": jg.BothEdges(), "z0": jg.EdgeZ0(), "z1": jg.EdgeZ1()}
    m = jg.MemberModification(**kw, end_relief_edge=edges[edge])
    got = -np.asarray(m.deviation(jnp.full_like(jnp.asarray(zeta), 0.5), jnp.asarray(zeta)))
    np.testing.assert_allclose(got, _linear_end_relief(zeta, 7e-6, 0.4, edge), atol=1e-20)
    if edge == "both":  # the default is the symmetric relief
        default = jg.MemberModification(**kw)
        np.testing.assert_array_equal(np.asarray(default.deviation(0.5, jnp.asarray(zeta))), -got)


def test_end_relief_blend_rounds_only_the_start():
    """A blend s (lead fraction) leaves the ramp unchanged farther than s/2 from the start, stays
    within depth·s/(8·extent) of it at the start, and makes the deviation of a point at the start
    C¹ in the extent (the one-sided derivatives agree)."""
    depth, extent, s = 5e-6, 0.3, 0.05
    zeta = np.linspace(0.0, 1.0, 401)
    m = jg.MemberModification(
        end_relief_depth=depth,
        end_relief_extent=extent,
        end_relief_blend=s,
        end_relief_edge=jg.EdgeZ0(),
    )
    got = -np.asarray(m.deviation(0.5, jnp.asarray(zeta)))
    ref = _linear_end_relief(zeta, depth, extent, "z0")
    far = np.abs(zeta - extent) > s / 2 + 1e-12
    np.testing.assert_allclose(got[far], ref[far], atol=1e-20)
    assert np.max(np.abs(got - ref)) == pytest.approx(depth * s / (8 * extent), rel=1e-2)

    def e(le, blend):
        mm = jg.MemberModification(
            end_relief_depth=depth,
            end_relief_extent=le,
            end_relief_blend=blend,
            end_relief_edge=jg.EdgeZ0(),
        )
        return float(mm.deviation(0.5, 0.3))

    h = 1e-7
    left = (e(0.3, s) - e(0.3 - h, s)) / h
    right = (e(0.3 + h, s) - e(0.3, s)) / h
    assert left == pytest.approx(right, rel=1e-4)
    sharp_left = (e(0.3, 0.0) - e(0.3 - h, 0.0)) / h
    sharp_right = (e(0.3 + h, 0.0) - e(0.3, 0.0)) / h
    assert abs(sharp_left - sharp_right) > 1e-6  # the sharp start is a kink


def test_end_relief_edge_in_the_case_file(tmp_path):
    text = _case_text(
        'end_relief = { depth_um = 10.0, extent = 0.4, edge = "z1" }\n'
        "[modifications.gear]\nend_relief = { depth_um = 2.0, extent = 0.2 }\n"
    )
    p = tmp_path / "c.toml"
    p.write_text(text)
    case = jio.load_case(p)
    assert case.modifications.pinion.end_relief_edge == "z1"
    assert float(case.modifications.pinion.end_relief_depth) == pytest.approx(10e-6)
    assert case.modifications.gear.end_relief_edge == "both"
    bad = p.with_name("bad.toml")
    bad.write_text(text.replace('edge = "z1"', 'edge = "left"'))
    with pytest.raises(ValueError) as err:
        jio.load_case(bad)
    msg = str(err.value)
    assert "\n" not in msg.strip()
    for needle in ("end_relief", "edge", "'left'", "'both'", "'z0'", "'z1'"):
        assert needle in msg, msg
    with pytest.raises(ValueError, match="end_relief_edge"):
        jg.MemberModification(end_relief_edge="left")


# -- the objectives on a hand-made load map ----------------------------------------------------------


def _result(line_load, z, mask):
    P, L, N = line_load.shape
    zeros = jnp.zeros(P)
    mesh = jg.MeshResult(
        transmission_error=zeros,
        mesh_stiffness=zeros,
        contact_length=zeros,
        line_load=jnp.asarray(line_load),
        cell_s=jnp.zeros((P, L, N)),
        cell_z=jnp.broadcast_to(jnp.asarray(z), (P, L, N)),
        cell_mask=jnp.asarray(mask),
    )
    return jg.QuasiStaticResult(
        theta=zeros,
        x=jnp.zeros((P, 1)),
        iterations=jnp.zeros(P, int),
        result=jnp.zeros(P, int),
        meshes=(mesh,),
    )


def test_load_centroid_and_lp_norm_against_sums_written_out():
    rng = np.random.default_rng(3)
    P, L, N, b = 5, 3, 8, 0.04
    z = (np.arange(N) + 0.5) * b / N
    q = rng.uniform(0, 4e5, (P, L, N))
    mask = rng.uniform(size=(P, L, N)) > 0.2
    q = np.where(mask, q, 0.0)
    r = _result(q, z, mask)
    zz = np.broadcast_to(z, q.shape)
    want = (np.sum(q * zz) / np.sum(q) - b / 2) / b
    assert float(op.load_centroid(r, b)) == pytest.approx(want, rel=1e-12)
    # load on the z = b half only: the centroid is positive (towards z = b)
    right = np.where(zz > b / 2, q, 0.0)
    assert float(op.load_centroid(_result(right, z, mask), b)) > 0.2
    for p in (1.0, 2.0, 8.0):
        lp = (np.sum(q[mask] ** p) / mask.sum()) ** (1 / p)
        assert float(op.line_load_lp(r, p)) == pytest.approx(lp, rel=1e-12)
    assert float(op.line_load_lp(r, 8.0)) < q.max()
    assert float(op.line_load_lp(r, 64.0)) == pytest.approx(q.max(), rel=0.1)
    # the gradient of the L_p norm, through the stopped reference, is the analytic one
    g = jax.grad(lambda v: op.line_load_lp(_result(v, z, mask), 8.0))(jnp.asarray(q))
    lp8 = (np.sum(q[mask] ** 8) / mask.sum()) ** (1 / 8)
    ref = np.where(mask, (q / lp8) ** 7 / mask.sum(), 0.0)
    np.testing.assert_allclose(np.asarray(g), ref, rtol=1e-10, atol=1e-18)


# -- the small hybrid case at speed -------------------------------------------------------------------


@pytest.fixture(scope="module")
def hybrid(fem_prep_cache):
    """The small flexible-wheel case (δ_m = 11 µm), made asymmetric across the face: a 30 µm
    helix slope on the pinion (the z = 0 edge partly out of contact, so that symmetric
    modifications move the centroid too) and its end relief, extent 0.4, on the z = b edge only;
    its hybrid scene at 3000 rad/s."""
    case = jio.load_case(DATA / "hybrid-test-case.toml")
    m = case.modifications
    pinion = dataclasses.replace(
        m.pinion, helix_slope_deviation=30e-6, end_relief_edge=jg.EdgeZ1(), end_relief_extent=0.4
    )
    case = case.replace(modifications=jg.Modifications(pinion=pinion, gear=m.gear))
    return case, static_scene(case)[0]


VARS = (
    "end_relief.depth,end_relief.extent,pinion.crowning.depth,gear.crowning.depth,"
    "tip_relief.depth,tip_relief.extent"
)
DESIGN_UM = {
    "end_relief.depth": 2.0,
    "end_relief.extent": 0.3,
    "pinion.crowning.depth": 1.0,
    "gear.crowning.depth": 0.5,
    "tip_relief.depth": 8.0,
    "tip_relief.extent": 0.3,
}


def _exact_metrics(hybrid):
    """The load_centroid problem of the six design variables on the hybrid scene at 3000 rad/s
    (8 positions per pitch), its start ``x0`` (normalised) and the compiled ``x -> (J, f)`` of
    f: the objective (``Problem.value``), the L8 norm of the line load, the signed centroid, the
    maximum line load and TE RMS (``Problem.metrics``), in exact contact, each of order one."""
    case, scene = hybrid
    pc = jio.case_problem(
        case, VARS, "load_centroid", scene=scene, speed=3000.0, positions_per_pitch=8
    )
    x0 = jnp.asarray(pc.from_physical(DESIGN_UM))

    def f(x):
        m = pc.metrics(x, jg.ExactContact())
        return jnp.stack(
            [
                pc.value(x, jg.ExactContact()),
                m["line_load_lp_N_per_m"] / 1e5,
                m["load_centroid"] * 10.0,
                m["max_line_load_N_per_m"] / 1e5,
                m["te_rms_m"] * 1e6,
            ]
        )

    def with_values(x):
        y = f(x)
        return y, y

    # the Jacobian and the values from one compiled program (jacfwd with the values as its
    # auxiliary output): the differences' values come from the Jacobian's own program
    return pc, x0, jax.jit(jax.jacfwd(with_values, has_aux=True))


def test_design_variable_gradients_match_central_differences_in_exact_contact(hybrid):
    """The load_centroid objective (``Problem.value``), the L8 norm of the line load, the maximum
    line load, TE RMS and the signed centroid (``Problem.metrics``), differentiated in exact contact
    w.r.t. end relief depth and extent, crowning per member, tip relief depth and extent, on the
    hybrid scene at 3000 rad/s: the Jacobian's projections on two fixed random directions
    (seeded) against central differences along them (h = 1e-6 in normalised units); every
    variable moves the centroid and the L_p norm (each column of the Jacobian). Each variable
    against its own central difference: the slow test below."""
    pc, x0, jacobian = _exact_metrics(hybrid)
    J, y0 = (np.asarray(a) for a in jacobian(x0))

    def fj(x):
        return np.asarray(jacobian(x)[1])

    h = 1e-6
    rng = np.random.default_rng(54)
    for d in rng.standard_normal((2, x0.size)):
        d /= np.linalg.norm(d)
        fd = (fj(x0 + h * d) - fj(x0 - h * d)) / (2 * h)
        np.testing.assert_allclose(J @ d, fd, rtol=1e-5, atol=1e-7, err_msg=str(d))
    # none trivially zero: every variable moves the centroid and the L_p norm
    assert np.all(np.abs(J[1]) > 1e-4), J[1]
    assert np.all(np.abs(J[2]) > 1e-4), J[2]
    # the design's centroid is off centre (the first entry: Problem.value in exact contact, from
    # the program compiled above instead of a quasi-static program of its own)
    assert float(y0[0]) > 1.0


@pytest.mark.slow  # the directional check above keeps the claim in the default suite
def test_design_variable_gradients_match_central_differences_per_variable(hybrid):
    """As above, each of the six variables against its own central difference (h = 1e-6 in
    normalised units)."""
    pc, x0, jacobian = _exact_metrics(hybrid)
    J = np.asarray(jacobian(x0)[0])
    h = 1e-6
    for i in range(x0.size):
        e = np.zeros(x0.size)
        e[i] = h
        fd = (np.asarray(jacobian(x0 + e)[1]) - np.asarray(jacobian(x0 - e)[1])) / (2 * h)
        np.testing.assert_allclose(J[:, i], fd, rtol=1e-5, atol=1e-7, err_msg=pc.names[i])


# default tier: tests/test_optimise.py::test_optimiser_reaches_the_grid_optimum_from_three_starts
# (the optimiser reaches the grid optimum) and
# ::test_design_variable_gradients_match_central_differences_in_exact_contact (load_centroid
# on the hybrid scene at speed, its value and derivatives)
@pytest.mark.slow
def test_load_centroid_optimum_matches_a_grid_scan_at_speed(hybrid):
    """On the small hybrid case at 3000 rad/s, the 30 µm helix slope loads the z = b edge; the
    gradient optimum of load_centroid over the depth of the z = b end relief (smooth contact,
    then exact) centres the load, at the zero crossing of c(E) from a grid scan in exact contact
    (E* = E/δ_m in [0, 8], steps of 1, then of 0.25 across the first crossing)."""
    case, scene = hybrid
    p = jio.case_problem(
        case,
        "pinion.end_relief.depth",
        "load_centroid",
        scene=scene,
        speed=3000.0,
        positions_per_pitch=8,
    )
    p = eqx.tree_at(lambda q: q.upper, p, jnp.asarray([8.0]))
    res = op.minimise(p, np.array([0.5]), progress=False)
    sharp = p.sharp()
    c = jax.jit(lambda x: sharp.metrics(x)["load_centroid"])

    def values(grid):
        return np.array([float(c(jnp.asarray([g]))) for g in grid])

    def first_crossing(cs):
        return int(np.flatnonzero(np.sign(cs[:-1]) != np.sign(cs[1:]))[0])

    # the first crossing on a unit grid of E* = E/δ_m in [0, 8], then the steps of 0.25 across
    # it: the points of the 0.25 grid that bracket the root (12 solves instead of 33)
    coarse = values(np.arange(0.0, 8.01, 1.0))
    k = first_crossing(coarse)
    grid = k + np.linspace(0.0, 1.0, 5)
    cs = np.concatenate([coarse[k : k + 1], values(grid[1:-1]), coarse[k + 1 : k + 2]])
    j = first_crossing(cs)
    root = grid[j] - cs[j] * (grid[j + 1] - grid[j]) / (cs[j + 1] - cs[j])
    assert coarse[0] > 0.1  # without relief the load sits towards z = b
    assert float(res.x[0]) == pytest.approx(root, abs=0.05)
    assert abs(float(c(jnp.asarray(res.x)))) < 0.02 * coarse[0]


# -- CLI ---------------------------------------------------------------------------------------------


def _one_line_error(capsys, *needles):
    err = capsys.readouterr().err
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert len(lines) == 1 and lines[0].startswith("jaxgear: error: "), err
    for n in needles:
        assert n in lines[0], err
    return lines[0]


@pytest.mark.parametrize(
    ("opts", "needles"),
    [
        (["--vars", "crowning.dpth"], ["--vars", "'crowning.dpth'", "end_relief.depth"]),
        (["--vars", "crowning.depth,,end_relief.depth"], ["--vars", "empty"]),
        (["--vars", "gear.end_relief.depth,gear.end_relief.depth"], ["--vars", "twice"]),
        (["--objective", "line_load_lp", "--lp-order", "0.5"], ["--lp-order", "0.5", "[1, 64]"]),
        (["--objective", "line_load_lp", "--lp-order", "nan"], ["--lp-order", "nan", "[1, 64]"]),
        (["--objective", "max_line_load", "--lp-order", "8"], ["--lp-order", "line_load_lp"]),
        (["--speed", "-3000"], ["--speed", "-3000", "[0, 1e+05]"]),
        (["--speed", "inf"], ["--speed", "inf", "[0, 1e+05]"]),
    ],
)
def test_bad_optimise_input_is_a_one_line_error(opts, needles, tmp_path, capsys):
    from jaxgear.cli import main

    case = tmp_path / "c.toml"
    case.write_text(_case_text())
    assert main(["optimise", str(case), *opts, "--out", str(tmp_path / "o"), "--quiet"]) == 2
    _one_line_error(capsys, *needles)
    assert not (tmp_path / "o").exists()


def test_speed_on_a_rigid_case_is_a_one_line_error(tmp_path, capsys):
    from jaxgear.cli import main

    argv = ["optimise", "accessory-spur", "--speed", "3000", "--objective", "load_centroid"]
    assert main([*argv, "--out", str(tmp_path / "o"), "--quiet"]) == 2
    _one_line_error(capsys, "--speed 3000", "condensed bodies")


# default tier: tests/test_optimise_speed.py::test_load_centroid_optimum_matches_a_grid_scan_at_speed
# (the same problem and optimum at 3000 rad/s, 8 positions) and
# ::test_speed_on_a_rigid_case_is_a_one_line_error (the command's --speed)
@pytest.mark.slow
def test_jaxgear_optimise_load_centroid_at_speed_on_the_small_case(tmp_path, capsys, monkeypatch):
    """`jaxgear optimise CASE --objective load_centroid --speed 3000 --vars
    pinion.end_relief.depth` on the small flexible-wheel case with a 20 µm helix slope and a
    z = b end relief (default bounds: up to 3 δ_m = 33 µm; the centring depth is near 23 µm),
    at 8 positions per pitch: optimum.json holds the exact-contact centroid before and after,
    near 0 after."""
    from jaxgear.cli import main

    text = _case_text(
        "[modifications.pinion]\nhelix_slope = { deviation_um = 20.0 }\n"
        'end_relief = { depth_um = 5.0, extent = 0.4, edge = "z1" }\n'
    )
    # 8 positions per pitch, as the grid-scan test above: the same programs (the problem's
    # shapes and structure), compiled once in a run
    assert "positions_per_pitch = 16\n" in text
    text = text.replace("positions_per_pitch = 16\n", "positions_per_pitch = 8\n")
    case = tmp_path / "c.toml"
    case.write_text(text)
    out = tmp_path / "o"
    argv = ["optimise", str(case), "--objective", "load_centroid", "--speed", "3000"]
    argv += ["--vars", "pinion.end_relief.depth", "--max-iterations", "40"]
    assert main([*argv, "--out", str(out), "--quiet"]) == 0
    printed = capsys.readouterr().out
    assert "load_centroid (hybrid scene at 3000 rad/s): centroid" in printed
    rep = json.loads((out / "optimum.json").read_text())
    assert rep["model"] == "hybrid scene" and rep["speed_rad_s"] == 3000.0
    assert rep["case_start"] == {"pinion.end_relief.depth": pytest.approx(5.0)}
    c0 = rep["initial"]["exact"]["load_centroid"]
    c1 = rep["final"]["exact"]["load_centroid"]
    assert c0 > 0.05 and abs(c1) < 0.05 * abs(c0)
    assert rep["final"]["objective_exact_face_fraction_squared"] == pytest.approx(c1**2, rel=1e-9)
    assert rep["final"]["exact"]["load_centroid_mm"] == pytest.approx(c1 * 10.0, rel=1e-12)
    names = sorted(p.name for p in out.iterdir())
    assert names == [".jaxgear-outputs", "convergence.png", "harris.png", "optimum.json"]


# -- the seed's end relief on the power pair (slow) ---------------------------------------------------


def _example():
    mod = load_example("end_relief_at_speed")
    return mod


@pytest.mark.slow
def test_power_pair_end_relief_at_speed(fem_prep_cache):
    """docs/bench/end_relief_at_speed.{png,json} (seed IV-33/34) on power-helical-flexible at 3000 rad/s,
    recomputed: (1) the committed scan values; (2) what the figure shows — the web-side relief
    moves the centroid towards the centre as it deepens, the seed's cantilevered-edge relief
    away from it; (3) the gradient optimum of load_centroid over the web-side depth is the zero
    crossing of c(E) from a 2 µm grid scan in exact contact (within 0.5 µm), and c there < 1e-3;
    (4) the max_line_load gradient optimum is within 1 % of the best of a 1 µm grid scan."""
    ex = _example()
    record = json.loads((ROOT / "docs" / "bench" / "end_relief_at_speed.json").read_text())
    stored = record["speeds"]["3000"]
    depths = np.arange(0.0, 20.01, 2.0)
    got = {}
    for edge in ("z0", "z1"):
        case = ex.design_case(edge)
        scene, _ = static_scene(case)
        p = ex.make(case, scene, 3000.0, "load_centroid", (0.0, 20.0))
        got[edge] = ex.scan(p, depths)
        want = stored[edge]["scan"]
        idx = [want["depth_um"].index(d) for d in depths]
        for key in ("load_centroid", "max_line_load_N_per_m"):
            np.testing.assert_allclose(got[edge][key], np.asarray(want[key])[idx], rtol=1e-6)
        if edge == "z0":
            c = np.asarray(got[edge]["load_centroid"])
            assert c[0] < -0.05 and np.all(np.diff(c) > 0)  # towards the centre
            wide = ex.make(case, scene, 3000.0, "load_centroid", (0.0, 160.0))
            grid = np.arange(0.0, 160.01, 2.0)
            cs = np.asarray(ex.scan(wide, grid)["load_centroid"])
            k = int(np.flatnonzero(np.sign(cs[:-1]) != np.sign(cs[1:]))[0])
            root = grid[k] - cs[k] * (grid[k + 1] - grid[k]) / (cs[k + 1] - cs[k])
            opt = ex.gradient_optimum(wide, 20.0)
            assert opt["depth_um"] == pytest.approx(root, abs=0.5)
            assert abs(opt["load_centroid"]) < 1e-3
            assert opt["depth_um"] == pytest.approx(
                stored["z0"]["optimum_load_centroid"]["depth_um"], abs=0.05
            )
            pm = ex.make(case, scene, 3000.0, "max_line_load", (0.0, 20.0))
            best = ex.gradient_optimum(pm, 5.0)["max_line_load_N_per_m"]
            fine = ex.scan(pm, np.arange(0.0, 20.01, 1.0))["max_line_load_N_per_m"]
            assert best <= 1.01 * min(fine)
        else:
            c = np.asarray(got[edge]["load_centroid"])
            assert np.all(np.diff(c) < 0)  # the seed's relief: away from the centre
            assert c[5] < c[0] < 0
    seed = record["seed_check"]
    assert seed["reproduced"] is False
    assert math.isclose(seed["centroid_seed_relief"], got["z1"]["load_centroid"][5], rel_tol=1e-6)


@pytest.mark.filterwarnings("always")
def test_an_extent_without_a_depth_warns(monkeypatch, tmp_path, capsys):
    """An end relief extent as the only variable of a relief the case does not have does
    nothing (zero gradient): the CLI says so, before the optimiser starts (stopped here where
    ``jaxgear optimise`` turns the case's values into the optimiser's start)."""
    from jaxgear.cli import main

    def stop(self, values):
        raise ValueError("stopped before the optimiser")

    monkeypatch.setattr(op.Problem, "from_physical", stop)
    case = jio.load_case("accessory-spur")
    assert float(case.modifications.pinion.end_relief_depth) == 0.0
    for names, warns in [
        (("end_relief.extent",), True),
        (("gear.end_relief.extent", "pinion.end_relief.depth"), True),
        (("end_relief.extent", "end_relief.depth"), False),
        (("pinion.end_relief.extent", "end_relief.depth"), False),
        (("end_relief.extent", "gear.end_relief.depth"), False),
    ]:
        argv = ["optimise", "accessory-spur", "--vars", ",".join(names), "--quiet"]
        assert main([*argv, "--out", str(tmp_path / "o")]) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert err[-1] == "jaxgear: error: stopped before the optimiser", err
        w = [line for line in err if line.startswith("jaxgear: warning: ")]
        assert bool(w) == warns, (names, w)
        if warns:
            assert "end_relief.depth is 0" in w[0]
