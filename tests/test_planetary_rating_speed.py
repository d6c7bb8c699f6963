"""The planetary stages' tooth-root stress at speed (docs/rating.md, "Root stress at speed"):
the cells' forces recorded by the planetary dynamics (jaxgear.planetary.PlanetaryRun
``cell_loads=True``, PlanetaryDynamics.cell_forces) and the rating's map at speed
(jaxgear.cli.planetary_speed: run_at_speed, stage_at_speed, rating_at_speed).

References, independent of the code under test:
- the mesh forces the run records (each planet's mesh force, summed by the run's own mesh
  force code) against the recorded cell forces summed here by hand per planet and mesh, times
  cos(beta_b);
- the quasi-static limit: at a carrier speed of 1e-7 rad/s the Newmark run's inertia falls as
  (S Omega)^2 (tests/test_planetary_dynamics.py), so its cell forces are the quasi-static solve's
  (jaxgear.planetary.planetary_quasi_static's line loads times the cells' lengths, and on the rated
  NREL stage the rating's own stage_loads);
- a flat FE table (the same stress per unit load at every roll distance): the map is then the
  line load times a constant, so the ratio of the largest root stresses at speed and at rest is
  the ratio of the largest line loads, counted here from the loads; and the real FE fillet
  influence tables (fem_prep, the rating's) applied to the dynamic cell loads by hand with
  np.interp.
"""

import json
import math
import warnings

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from _planetary_stage import K0, SEQ, WIDTH, geometry, seq_ring_case, stage
from _rating_cases import Table, stub_table

import jaxgear as jg
import jaxgear.dynamics as jd
import jaxgear.io as jio
import jaxgear.planetary as jp
from jaxgear.io import CaseWarning

# the contact model a stub measured row states (jaxgear.rating.contact_model's words)
CONTACT = "stub contact model"

jax.config.update("jax_enable_x64", True)

TORQUE = 1000.0


def test_cell_forces_sum_to_the_mesh_forces_and_reach_the_quasi_static_limit():
    """A 3-planet torsional stage (19/17/-53, 2 slices, a 10 µm pin error, damped): the recorded
    cell forces (N) of each planet's sun and ring mesh, summed here, times cos(beta_b), are the
    recorded mesh forces (1e-10 of the largest) at a real speed and at 1e-7 rad/s; at 1e-7 rad/s
    they are the quasi-static solve's cell loads (line load times the cell length (b/N)/cos
    beta_b) at the same travels (1e-6 of the largest), at 30 rad/s not (1e-3); never negative;
    ``cell_loads`` off by default."""
    geo = geometry(**SEQ)
    st = stage(geo, 3)
    meshes = jp.ContactMeshes.from_geometry(geo, st.planet_angles, jg.Uniform(K0), n_slices=2)
    errors = np.array([10e-6, 0.0, 0.0])
    run = jp.PlanetaryRun(TORQUE, steps_per_period=12, periods=3, keep_periods=1,
                          tangential_pin_errors=errors, cell_loads=True)
    model = jp.TorsionalPlanetary()
    n, lines, slices = 3, meshes.sun_mesh.n_lines, meshes.sun_mesh.n_slices
    per = lines * slices
    assert meshes.ring_mesh.n_lines * meshes.ring_mesh.n_slices == per
    cos_b = math.cos(float(meshes.sun_mesh.base_helix_angle))
    for speed in (1e-7, 30.0):
        got = jp.planetary_dynamics(model, st, meshes, run, jnp.asarray(speed))
        assert int(got.result) == 0
        p = np.asarray(got.cell_forces)
        assert p.shape == (12, 2 * n * per) and p.min() >= 0.0
        f_s, f_r = np.asarray(got.sun_mesh_forces), np.asarray(got.ring_mesh_forces)
        for j in range(n):
            sun = cos_b * p[:, j * per:(j + 1) * per].sum(axis=1)
            ring = cos_b * p[:, (n + j) * per:(n + j + 1) * per].sum(axis=1)
            np.testing.assert_allclose(sun, f_s[:, j], rtol=0, atol=1e-10 * f_s.max())
            np.testing.assert_allclose(ring, f_r[:, j], rtol=0, atol=1e-10 * f_r.max())
        if speed == 1e-7:
            static = jp.planetary_quasi_static(model, st, meshes, np.asarray(TORQUE), got.travel,
                                               errors)
            # every cell's length: (b/N)/cos(beta_b)
            want = np.asarray(static.cell_line_load) * WIDTH / slices / cos_b
            np.testing.assert_allclose(p, want, rtol=0, atol=1e-6 * want.max())
            slow = p
        else:  # at speed the loads are not the static ones
            assert np.max(np.abs(p - slow)) > 1e-3 * slow.max()
    plain = jp.PlanetaryRun(TORQUE, steps_per_period=12, periods=3, keep_periods=1)
    assert plain.cell_loads is False


def _synthetic_loads(pair, positions, seed, scale=None):
    """A quasi-static-like load record over one base pitch for one mesh: two contact lines a
    base pitch apart, 2 slices, loads of a few 1e5 N/m, the cells off the path masked; with
    ``scale`` (per position) the loads multiplied by it, tiled over len(scale)/positions
    periods."""
    from jaxgear.cli.planetary_speed import MeshLoads

    rng = np.random.default_rng(seed)
    p_b, g = float(pair.base_pitch), float(pair.path_of_contact)
    s0 = (np.arange(positions) + 0.5) / positions * p_b
    s = s0[:, None, None] + np.array([0.0, p_b])[None, :, None] + np.zeros((1, 1, 2))
    mask = s <= g
    w = np.where(mask, rng.uniform(1e5, 4e5, s.shape), 0.0)
    z = np.broadcast_to(np.array([0.25, 0.75]) * float(pair.face_width), s.shape)
    length = np.full(s.shape, 0.5 * float(pair.face_width))
    if scale is not None:
        reps = len(scale) // positions
        tile = (lambda a: np.concatenate([a] * reps))
        return MeshLoads(np.asarray(scale)[:, None, None] * tile(w), tile(s), tile(z),
                         tile(mask), tile(length))
    return MeshLoads(w, s, np.array(z), mask, length)


def _flat_table(tooth, radii):
    """The shape of an FE fillet influence table (the roll distances of the radii) with the
    same stress per unit load everywhere: 2.0 Pa per N/m."""
    stub = stub_table(tooth, radii)
    return Table(stub.roll, np.full_like(stub.roll, 2.0))


def _stage1(slices=2, positions=16):
    case = jio.load_case("nrel-5mw-planetary")
    return case.replace(slices=slices, positions_per_pitch=positions)


#: steps per mesh period of the given records; the factors f_k of the loads at speed over two
#: kept periods
P = 6
F = [1.0, 1.3, 0.8, 1.45, 1.1, 0.9, 1.05, 1.2, 0.95, 1.1, 1.0, 0.85]


@pytest.fixture(scope="module")
def given(tmp_path_factory):
    """nrel-5mw-planetary (coarse) rated with given loads: per planet and mesh a static record
    (planet 3 the most loaded: mean and peak forces 1, 1, 1.1), and at speed each planet's
    static loads scaled by F step by step (planet 2 the most loaded at speed: peak forces 1, 1.2, 1.1); the
    quasi-static maps with the flat table. (case, static, fast, loads, at, rating)."""
    from jaxgear.cli.planetary import rating_section
    from jaxgear.cli.planetary_speed import StageAtSpeed, StageLoads

    case = _stage1()
    static, fast = [], []
    for k, pair in enumerate(case.pairs):
        static.append(tuple(_synthetic_loads(pair, P, 10 * k + j) for j in range(3)))
        fast.append(tuple(_synthetic_loads(pair, P, 10 * k + j, F) for j in range(3)))
    loads = StageLoads(tuple(static), (np.array([1.0, 1.0, 1.1]),) * 2, "stub loads",
                       CONTACT, peak_forces=(np.array([1.0, 1.0, 1.1]),) * 2)
    at = StageAtSpeed(tuple(fast), (np.array([1.0, 1.2, 1.1]),) * 2, 1.0, loads, 1.5, 0, 2, P,
                      "stub run")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", CaseWarning)
        rating = rating_section(case, str(tmp_path_factory.mktemp("rated")), 1.0, loads=loads,
                                table=_flat_table)
    return case, static, fast, loads, at, rating


def test_rating_at_speed_ratio_is_the_largest_line_loads_ratio_with_a_flat_table(tmp_path,
                                                                                 given):
    """With a flat FE table the largest root stress of each member at speed over the static one
    is the largest line load of the planet most loaded at speed (2) over the static one of the
    planet most loaded at rest (3), counted here (1e-12); the mesh's dynamic factor is planet
    2's peak force over the nominal (1.2), its tooth factor the largest tooth force (line load
    times length, summed across the face) over the static one (1e-12). summary keys as a pair's
    at_speed (per-mesh lists) plus the planets, rating.md's two rows per mesh beside the K_γ
    row, the maps at speed written."""
    from jaxgear.cli.planetary_speed import rating_at_speed

    case, static, fast, _, at, rating = given
    out = rating_at_speed(case, str(tmp_path), rating, at, table=_flat_table)
    rs = out["root_stress"]["at_speed"]
    for k in (0, 1):
        dyn, rest = fast[k][1], static[k][2]
        assert rs["planet"][k] == 2 and rs["static_planet"][k] == 3
        assert rs["dynamic_factor"][k] == pytest.approx(1.2, rel=1e-12)
        tooth = [np.max((w * c).sum(axis=-1)) for w, c in
                 ((dyn.line_load, dyn.cell_length), (rest.line_load, rest.cell_length))]
        assert rs["dynamic_factor_tooth"][k] == pytest.approx(tooth[0] / tooth[1], rel=1e-12)
        want = dyn.line_load[dyn.cell_mask].max() / rest.line_load[rest.cell_mask].max()
        for i in (0, 1):
            assert rs["ratio"][k][i] == pytest.approx(want, rel=1e-12)
            assert rs["ratio"][k][i] == pytest.approx(
                rs["max_Pa"][k][i] / rs["static_max_Pa"][k][i], rel=1e-12)
    assert rs["file"] == [f"root_stress_map_{m}_speed.png" for m in out["meshes"]]
    for key in ("speed_rad_s", "max_Pa", "static_max_Pa", "ratio", "dynamic_factor",
                "dynamic_factor_tooth", "slices", "result", "source"):  # the pair's keys
        assert len(rs[key]) == 2, key
    assert rs["speed_rad_s"] == [1.5, 1.5] and rs["steps_per_period"] == [P, P]
    md = (tmp_path / "rating.md").read_text()
    assert md.count("| σ_F,FE max at speed |") == 2
    assert md.count("| σ_F,FE at speed / static |") == 2
    assert "planet 2: the largest mesh force at speed" in md and md.count("| K_γ | ") == 2
    for name in rs["file"]:
        assert (tmp_path / name).stat().st_size > 10_000


def test_rating_at_speed_of_loads_scaled_step_by_step(tmp_path, given):
    """With a table linear in the roll distance (stub, g = 1e3 rho) and the loads at speed the
    static ones scaled step by step by f_k, each member's ratio at speed / static is
    max_k f_k sigma_k of planet 2 over planet 3's static maximum (the map linear in the loads,
    sigma_k the static map's largest at step k's position: tests/test_root_stress_speed.py's
    rule), 1e-12."""
    from jaxgear.cli.planetary_speed import rating_at_speed

    case, static, _, _, at, rating = given
    rs = rating_at_speed(case, str(tmp_path), rating, at, table=stub_table)["root_stress"][
        "at_speed"]
    for k, pair in enumerate(case.pairs):
        for i in (0, 1):
            sigma = [(np.where(m.cell_mask, m.line_load, 0) * 1e3
                      * np.asarray(pair.roll_distance(m.cell_s, i))).reshape(P, -1).max(axis=1)
                     for m in (static[k][1], static[k][2])]
            want = np.max(np.asarray(F) * np.tile(sigma[0], 2)) / sigma[1].max()
            assert rs["ratio"][k][i] == pytest.approx(want, rel=1e-12)


@pytest.mark.slow
def test_nrel_stage1_quasi_static_limit_and_the_fe_map_at_speed(tmp_path):
    """nrel-5mw-planetary at 2 slices and 16 steps per period (the real FE tables):
    run_at_speed at 1e-6 of the operating speed gives every planet's cell line loads equal to
    the rating's quasi-static stage_loads at the same slices and positions (1e-6 of the
    largest), and a ratio at speed / static of 1 (1e-6); at the operating speed (6 periods, 2
    kept) each member's largest root stress equals the FE tables applied by hand to the
    recorded cell forces over their lengths (np.interp of the fillet influence, 1e-12), the
    mesh's dynamic factor is the planet's largest recorded force over T_s/(N r_bs) (1e-12).
    The ring's map on its cutter's tooth (z0 = 36), as the quasi-static map."""
    from jaxgear.cli import fillet_table
    from jaxgear.cli.planetary import rating_section, sharing_models, stage_loads
    from jaxgear.cli.planetary_speed import rating_at_speed, run_at_speed

    case = _stage1()
    spec = case.form.spec
    full = spec.stage(case)
    opts = {"steps_per_period": 16, "periods": 3, "keep_periods": 1, "slices": 2}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", CaseWarning)
        slow = run_at_speed(case.form, case, 1e-6 * case.speed, **opts)
        loads = stage_loads(case, spec, full, sharing_models(spec, full))
    assert slow.result == 0
    for k in (0, 1):
        for j in range(spec.n_planets):
            # the run's kept steps start at the period's second position (step i at the
            # travel (i + 1/2) p_b / S, i from 1): the quasi-static positions rolled by one,
            # the same cells there
            a = slow.meshes[k][j]
            b = [np.roll(v, -1, axis=0) for v in loads.meshes[k][j][:4]]
            np.testing.assert_allclose(a.cell_s, b[1], rtol=0, atol=1e-12)
            np.testing.assert_array_equal(a.cell_mask, b[3])
            np.testing.assert_allclose(a.line_load, b[0], rtol=0, atol=1e-6 * b[0].max())
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", CaseWarning)
        rating = rating_section(case, str(tmp_path), 1.0, loads=loads)
    out = rating_at_speed(case, str(tmp_path), rating, slow)
    np.testing.assert_allclose(np.asarray(out["root_stress"]["at_speed"]["ratio"], float), 1.0,
                               rtol=1e-6)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", CaseWarning)
        fast = run_at_speed(case.form, case, case.speed, steps_per_period=16, periods=6,
                            keep_periods=2, slices=2)
    seen = []  # the FE tables the rating maps with: sun, planet, planet, ring

    def table(tooth, radii):
        seen.append(fillet_table(tooth, radii))
        return seen[-1]

    out = rating_at_speed(case, str(tmp_path), rating, fast, table=table)
    rs = out["root_stress"]["at_speed"]
    nominal = abs(spec.torques(case.torque)["sun"]) / (3 * float(case.pairs[0].base_radii[0]))
    for k, pair in enumerate(case.pairs):
        planet = rs["planet"][k] - 1
        assert rs["dynamic_factor"][k] == pytest.approx(
            float(fast.peak_forces[k].max()) / nominal, rel=1e-12)
        m = fast.meshes[k][planet]
        for i in (0, 1):
            t = seen[2 * k + i]
            rho = np.asarray(pair.roll_distance(m.cell_s, i))
            by_hand = np.where(m.cell_mask, m.line_load, 0) * np.interp(rho, t.roll, t.peak)
            assert rs["max_Pa"][k][i] == pytest.approx(by_hand.max(), rel=1e-12)
        assert 0.5 < min(r for r in rs["ratio"][k] if r is not None)


@pytest.mark.slow
def test_jaxgear_run_nrel_stage1_reports_the_root_stress_at_speed(tmp_path):
    """`jaxgear run nrel-5mw-planetary` (its first-look sweep, the run's resolution): each
    mesh's rating.root_stress.at_speed at the operating input speed with the sweep's steps per
    period there, the map at speed written, rating.md's rows; the dynamic factor of the mapped
    planet's mesh equals the sweep's at the operating speed within the settling rule's 1e-3 (the
    same step, its own span: the sweep's speeds share the longest one; measured 1.5e-4)."""
    from jaxgear.cli import main

    out = tmp_path / "out"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        main(["run", "nrel-5mw-planetary", "--out", str(out), "--quiet"])
    run_dir = out
    summary = json.loads((run_dir / "summary.json").read_text())
    rs = summary["rating"]["root_stress"]["at_speed"]
    case = jio.load_case("nrel-5mw-planetary")
    assert rs["speed_rad_s"] == [case.speed] * 2
    assert rs["result"] == [0, 0]
    sweep = json.loads((run_dir / "sweep" / "sweep.json").read_text())
    i = int(np.argmin(np.abs(np.asarray(sweep["speeds_rad_s"]) - case.speed)))
    assert rs["steps_per_period"] == [summary["dynamics"]["steps_per_period"][i]] * 2
    df = np.asarray(sweep["dynamic_factor_mesh"])[i]
    n = case.form.spec.n_planets
    for k in (0, 1):
        assert rs["dynamic_factor"][k] == pytest.approx(df[k * n:(k + 1) * n].max(), rel=1e-3)
        assert (run_dir / rs["file"][k]).stat().st_size > 10_000
    md = (run_dir / "rating.md").read_text()
    assert md.count("| σ_F,FE max at speed |") == 2


@pytest.mark.slow
def test_condensed_ring_stage_reaches_the_condensed_quasi_static_limit():
    """A small stage whose ring is the condensed coarse test ring (tests/_planetary_stage.py's
    seq_ring_case, massless in the dynamics): run_at_speed at 1e-6 of its operating speed
    gives every planet's cell line loads equal to the static solve beside it, which takes the
    same condensed ring (1e-6 of the largest; measured 2.2e-7 with the case's contact beyond
    the path, 1.3e-5 while its corners took the stage's rolling: docs/extended-contact.md,
    "The pair's rolling"), and not the rigid ring's (the
    flexible ring relieves the pin-error planet's ring mesh by more than 1e-3)."""
    from jaxgear.cli.planetary import sharing_models, stage_loads
    from jaxgear.cli.planetary_speed import run_at_speed

    case = jio.parse_train(seq_ring_case())
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", CaseWarning)
        slow = run_at_speed(case.form, case, 1e-6 * case.speed, steps_per_period=12, periods=3,
                            keep_periods=1)
    assert slow.result == 0
    worst = 0.0
    for k in (0, 1):
        for j in range(3):
            a, b = slow.meshes[k][j], slow.static.meshes[k][j]
            want = np.roll(b.line_load, -1, axis=0)  # the kept steps from position 1
            np.testing.assert_allclose(a.line_load, want, rtol=0, atol=1e-6 * want.max())
    spec = case.form.spec
    full = spec.stage(case)
    rigid = stage_loads(case.replace(slices=slow.slices, positions_per_pitch=12), spec, full,
                        sharing_models(spec, full))
    for j in range(3):
        a, b = slow.static.meshes[1][j].line_load, rigid.meshes[1][j].line_load
        worst = max(worst, np.max(np.abs(a - b)) / b.max())
    assert worst > 1e-3


def test_a_run_without_cell_forces_is_refused_in_one_line():
    """stage_at_speed of a run recorded without ``cell_loads``: one line naming cell_forces and
    what is allowed, before any work."""
    from jaxgear.cli.planetary_speed import stage_at_speed

    z = np.zeros((4, 3))
    dyn = jp.PlanetaryDynamics(np.zeros(4), np.zeros(4), np.zeros((4, 9)), z, z,
                               np.asarray(1.0), np.asarray(0), z)
    assert dyn.cell_forces is None
    with pytest.raises(ValueError, match=r"^stage_at_speed: dynamics.cell_forces is None: "
                       r"allowed a run of PlanetaryRun\(cell_loads=True\)$"):
        stage_at_speed(None, None, None, {}, dyn, None, {})
