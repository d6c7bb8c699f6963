"""Every condensed gear first-class, whichever member it is: a pair's flexible
pinion, both members flexible, and a train's flexible gears (docs/hybrid.md, docs/trains.md).

References: the mirror symmetry of a pair (the test wheel as the wheel of the test pair and as
the pinion of the pair with the pinion and gear data, shafts and torque swapped: the same
physical structure under the same loads, so the same quasi-static TE at the same contact
configurations, the same modes, and nodal-diameter resonance speeds scaled by the speed ratio);
the seed's (3.9) written by hand; each condensed body's own matrices from fem_prep (SciPy
eigen-solutions at the body's own speed); meshio reading the VTU series back.
"""

from __future__ import annotations

import json
import pathlib
import xml.etree.ElementTree as ET

import jax
import jax.numpy as jnp
import meshio
import numpy as np
import pytest
import scipy.linalg
from _hybrid_util import drive_rotations, rigidified_pair, rigidified_runs

import fem_prep
import jaxgear as jg
from jaxgear import io as jio
from jaxgear.cli import main
from jaxgear.dynamics import gear_nodal_diameter_resonances, modal_analysis, rim_stations
from jaxgear.io import Damping, load_bodies, static_scene
from jaxgear.scenes import FlexibleMember

DATA = pathlib.Path(__file__).parent / "data"
CASE = DATA / "hybrid-test-case.toml"
TRAIN = DATA / "hybrid-test-train.toml"
PINION_SHAFT = """length_mm = 80.0
diameter_mm = 25.0
gear_position_mm = 40.0
torque_position_mm = 0.0
bearings = [{ position_mm = 0.0, radial_N_per_um = 200.0, axial_N_per_um = 100.0 },
            { position_mm = 80.0, radial_N_per_um = 200.0 }]
"""
GEAR_SHAFT = """length_mm = 80.0
diameter_mm = 25.0
gear_position_mm = 40.0
torque_position_mm = 80.0
bearings = [{ position_mm = 0.0, radial_N_per_um = 300.0, axial_N_per_um = 100.0 },
            { position_mm = 80.0, radial_N_per_um = 300.0 }]
"""
# the test pair (tests/data/hybrid-test-case.toml) mirrored: its 30-tooth wheel drives (the same
# body, now the pinion), its 20-tooth pinion is driven, each on its own shaft as before; the
# same normal load (60 N·m × 30/20 on the 30-tooth gear)
MIRROR = f"""name = "hybrid-test-mirror"
[pair]
normal_module_mm = 2.0
normal_pressure_angle_deg = 20.0
helix_angle_deg = 0.0
[pinion]
teeth = 30
face_width_mm = 10.0
[gear]
teeth = 20
face_width_mm = 12.0
[operating]
torque_Nm = 90.0
speed_rad_s = 0.0
[mesh]
stiffness = "weber"
slices = 4
positions_per_pitch = 16
[modifications]
tip_relief = {{ depth_um = 8.0, extent = 0.3, shape = "linear" }}
[scene]
model = "lumped3d"
[scene.pinion_body]
body = "{DATA / "hybrid-test-wheel.toml"}"
[scene.pinion_shaft]
{GEAR_SHAFT}
[scene.gear_shaft]
{PINION_SHAFT}
"""


@pytest.fixture(scope="module")
def pairs(fem_prep_cache, tmp_path_factory):
    """(case, scene) of the test pair with its flexible wheel and of its mirror, whose
    flexible member is the pinion. On the theoretical path: the mirror holds the other gear
    and loads the one the original holds, which is the same load case only while every cell
    shares the torque ratio of the line of action; a corner cell beyond the path (the case
    file's default) acts with the tip owner's shorter lever arm and breaks that ratio, so the
    two load cases differ there (measured 2.5 % of the TE at two of 16 positions)."""
    path = tmp_path_factory.mktemp("mirror") / "hybrid-test-mirror.toml"
    path.write_text(MIRROR)
    body = fem_prep.condensed(DATA / "hybrid-test-wheel.toml")
    out = []
    for case, bodies in ((jio.load_case(CASE), (None, body)), (jio.load_case(path), (body, None))):
        case = case.replace(contact_geometry=jg.TheoreticalPath())
        out.append((case, static_scene(case, bodies=bodies)[0]))
    return out


def _mean_mesh_stiffness(scene, qs) -> np.ndarray:
    """K̄_m (n, n): Σ_c k_c l_c V_c V_cᵀ over the cells loaded in the quasi-static result
    ``qs`` (line load > 0), averaged over its positions (the one mesh of a pair)."""
    n = scene.structure.K.shape[0]
    P = qs.theta.shape[0]
    loaded = np.asarray(qs.meshes[0].line_load).reshape(P, -1) > 0

    @jax.jit
    def rows(theta):
        def one(th):
            cells = scene.mesh_cells(th)
            r = scene.window_row(cells, tuple(jnp.zeros_like(c.s) for c in cells))
            return r.idx, r.V, jnp.where(r.mask, r.k * r.length, 0.0)

        return jax.vmap(one)(theta)

    idx, V, kl = (np.asarray(a) for a in rows(qs.theta))
    Km = np.zeros((n, n))
    for p in range(P):
        w = np.where(loaded[p], kl[p], 0.0)
        np.add.at(Km, (idx[p][:, None], idx[p][None, :]), V[p].T @ (w[:, None] * V[p]))
    return Km / P


def test_a_flexible_pinion_mirrors_the_flexible_wheel(pairs):
    """The test wheel as the mirror's pinion: the quasi-static TE at the same contact
    configurations (the positions mirrored on the line of action) equals the flexible-wheel
    pair's at every position to 1e-10 of its mean, the modes with the mesh stiffness averaged
    over those configurations agree to 1e-7, and
    the (3.9) nodal-diameter resonances of the body are found on the pinion (member 0) at the
    same frequencies and orders, at pinion speeds 20/30 of the flexible-wheel pair's (the body's
    speed is the same)."""
    (case, scene), (mirror, mscene) = pairs
    assert isinstance(mscene.members[0], FlexibleMember)
    assert not isinstance(mscene.members[1], FlexibleMember)
    pair, mpair = case.pair, mirror.pair
    assert mpair.path_of_contact == pytest.approx(pair.path_of_contact, rel=1e-12)
    theta = np.asarray(jg.mesh_positions(scene.base_planes[0], 16))
    # s' = g_α − s on every line: r_b1' θ' = g_α − r_b1 θ (modulo a base pitch)
    mtheta = (pair.path_of_contact - pair.base_radii[0] * theta) / mpair.base_radii[0]
    qs = jg.quasi_static(scene, case.modifications, case.torque, jnp.asarray(theta))
    mqs = jg.quasi_static(mscene, mirror.modifications, mirror.torque, jnp.asarray(mtheta))
    te, mte = np.asarray(qs.transmission_error), np.asarray(mqs.transmission_error)
    assert np.all(np.asarray(qs.result) == 0) and np.all(np.asarray(mqs.result) == 0)
    np.testing.assert_allclose(mte, te, rtol=0, atol=1e-10 * np.mean(te))
    assert np.ptp(te) > 0.02 * np.mean(te)  # the positions differ: a real curve is compared
    # the modes with the mesh stiffness averaged over the same (mirrored) configurations
    modes = [
        modal_analysis(s, jnp.asarray(_mean_mesh_stiffness(s, r)))
        for (_, s), r in zip(pairs, (qs, mqs), strict=True)
    ]
    f = [np.sort(np.asarray(m.omega))[:30] / (2 * np.pi) for m in modes]
    np.testing.assert_allclose(f[1][1:], f[0][1:], rtol=1e-7)
    # (3.9) on the body, wherever it is
    speeds = np.array([1e3, 1e5])
    rows = []
    for (_, s), m in zip(pairs, modes, strict=True):
        ((member, _),) = rim_stations(s)
        rows.append(gear_nodal_diameter_resonances(s, m, member, max_speed=1.05 * speeds.max()))
    assert [r["member"] for r in rows[0]] == [1] * len(rows[0]) and len(rows[0]) >= 4
    assert {r["member"] for r in rows[1]} == {0} and len(rows[1]) == len(rows[0])
    for a, b in zip(rows[0], rows[1], strict=True):
        for key in ("nodal_diameter", "order", "direction", "harmonic"):
            assert a[key] == b[key]
        assert b["frequency_hz"] == pytest.approx(a["frequency_hz"], rel=1e-6)
        assert a["speed_ratio"] == pytest.approx(20 / 30) and b["speed_ratio"] == 1.0
        assert b["wheel_speed_rad_s"] == pytest.approx(a["wheel_speed_rad_s"], rel=1e-6)
        assert b["pinion_speed_rad_s"] == pytest.approx(a["pinion_speed_rad_s"] * 20 / 30, 1e-6)


def _two_body_train(tmp_path, extra: str = "") -> pathlib.Path:
    """The test idler train with its input flexible too (the test pinion body: 20 teeth, rim
    10 mm wide = the mesh face width) beside its idler; ``extra``: more TOML."""
    text = TRAIN.read_text().replace(
        'body = "hybrid-test-wheel.toml"', f'body = "{DATA / "hybrid-test-wheel.toml"}"'
    )
    text += f'[scene.bodies.input]\nbody = "{DATA / "hybrid-test-pinion.toml"}"\n' + extra
    path = tmp_path / "hybrid-test-train-2.toml"
    path.write_text(text)
    return path


@pytest.fixture(scope="module")
def train(fem_prep_cache, tmp_path_factory):
    case = jio.load_case(_two_body_train(tmp_path_factory.mktemp("train")))
    return case, load_bodies(case.scene)


def _body_free_dofs(body) -> np.ndarray:
    """The condensed DOFs of ``body`` that are not bearing masters (those merge with shaft
    nodes): its rim masters and modal coordinates."""
    kind = np.asarray(body.master_kind)
    return np.array(
        [i for i, (m, _) in enumerate(np.asarray(body.dof_map)) if m < 0 or kind[m] != 1]
    )


def _gyroscopic_frequencies(M, G, K, count):
    """The ``count`` lowest natural frequencies (rad/s) of M q̈ + G q̇ + K q = 0 (SciPy, the
    first-order form)."""
    n = M.shape[0]
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-np.linalg.solve(M, K), -np.linalg.solve(M, G)]])
    w = np.abs(np.imag(scipy.linalg.eigvals(A)))
    return np.sort(w[w > 1.0])[: 2 * count : 2]  # each frequency once (a conjugate pair)


def test_train_spin_terms_are_each_bodys_at_its_own_speed(train):
    """``rotating_frame`` on a train: restricted to each condensed gear's body (its shaft held),
    the assembled structure at input speed Ω has the modes of the body's own fem_prep matrices
    spinning at the gear's speed, Ω for the input and (20/30) Ω for the idler (teeth not lumped
    on the rim): (M, K + Ω_g² (S + Kσ)) to 1e-9, and with the Coriolis term 2 Ω_g Gy to 1e-7;
    taken at the input's speed instead, the idler's modes would be off by more than 1e-4."""
    case, bodies = train
    scene = case.hybrid_train(bodies, tooth_mass=False)
    st = scene.structure
    K, M = np.asarray(st.K), np.asarray(st.M)
    S, G = np.asarray(st.spin_stiffness), np.asarray(st.gyroscopic)
    omega = 12000.0
    own = {"input": 1.0, "idler": 20 / 30}  # each gear's turns per input turn, by its teeth
    checked = 0
    for g, body in enumerate(bodies):
        if body is None:
            continue
        name = case.gear_names[g]
        member = scene.members[g]
        free = _body_free_dofs(body)
        idx = np.asarray(member.body_dofs)[free]
        sub = np.ix_(idx, idx)
        Mb = np.asarray(body.M)[np.ix_(free, free)]
        Kb = np.asarray(body.K)[np.ix_(free, free)]
        Sb = (np.asarray(body.spin_softening) + np.asarray(body.stress_stiffening))[
            np.ix_(free, free)
        ]
        Gb = np.asarray(body.gyroscopic)[np.ix_(free, free)]
        wg = own[name] * omega
        got = scipy.linalg.eigh(K[sub] + omega**2 * S[sub], M[sub], eigvals_only=True)[:20]
        ref = scipy.linalg.eigh(Kb + wg**2 * Sb, Mb, eigvals_only=True)[:20]
        np.testing.assert_allclose(got, ref, rtol=1e-9)
        rest = scipy.linalg.eigh(Kb, Mb, eigvals_only=True)[:20]
        assert np.max(np.abs(ref / rest - 1)) > 1e-3  # the terms move the modes
        if name == "idler":
            wrong = scipy.linalg.eigh(Kb + omega**2 * Sb, Mb, eigvals_only=True)[:20]
            assert np.max(np.abs(wrong / ref - 1)) > 1e-4
        got = _gyroscopic_frequencies(M[sub], omega * G[sub], K[sub] + omega**2 * S[sub], 12)
        ref = _gyroscopic_frequencies(Mb, 2 * wg * Gb, Kb + wg**2 * Sb, 12)
        np.testing.assert_allclose(got, ref, rtol=1e-7)
        checked += 1
    assert checked == 2


def test_train_lists_the_nodal_diameter_resonances_of_each_flexible_gear(train):
    """A train with a flexible input (20 teeth) and a flexible idler (30 teeth): each gear's
    (3.9) resonances, from its own modes, at the orders h Z ± n of its own teeth, at input
    speeds 2π f / ((h Z ± n) Ω_g/Ω) with its speed ratio from the teeth (1 and 20/30)."""
    case, bodies = train
    scene = case.hybrid_train(bodies)
    modes = modal_analysis(scene, jnp.zeros_like(scene.structure.K))  # the structure's own
    members = [m for m, _ in rim_stations(scene)]
    assert [case.gear_names[m] for m in members] == ["input", "idler"]
    teeth = {"input": (20, 1.0), "idler": (30, 20 / 30)}
    speeds = np.array([1e3, 1e5])
    seen = set()
    for m in members:
        name = case.gear_names[m]
        Z, ratio = teeth[name]
        rows = gear_nodal_diameter_resonances(
            scene, modes, m, max_speed=1.05 * speeds.max(), n_modes=200
        )
        assert len(rows) >= 2
        for r in rows:
            sign = 1 if r["direction"] == "backward" else -1
            order = r["harmonic"] * Z + sign * r["nodal_diameter"]
            assert r["member"] == m and r["teeth"] == Z and r["order"] == order
            assert r["speed_ratio"] == pytest.approx(ratio, rel=1e-12)
            w_in = 2 * np.pi * r["frequency_hz"] / (order * ratio)
            assert r["pinion_speed_rad_s"] == pytest.approx(w_in, rel=1e-12)
            assert r["pinion_speed_rad_s"] <= 1.05e5
            seen.add((name, round(r["frequency_hz"])))
    # the output gear is rigid: one line naming the condensed members
    match = r"^gear_nodal_diameter_resonances: member = 2 is not a condensed body: allowed 0, 1$"
    with pytest.raises(ValueError, match=match):
        gear_nodal_diameter_resonances(scene, modes, 2)
    # the two bodies' web modes are different modes
    assert {n for n, _ in seen} == {"input", "idler"}


def _frame_turn(path, centre, k: int) -> float:
    """The angle (rad) by which the body's first point turned about ``centre`` between frame 0
    and frame ``k`` of the VTU series ``path`` (.pvd) (the points are the undeformed body turned
    to each step's angle), and the time between them (s)."""
    pvd = ET.parse(path).getroot()
    sets = list(pvd.iter("DataSet"))
    a = meshio.read(path.parent / sets[0].get("file"))
    b = meshio.read(path.parent / sets[k].get("file"))
    assert np.abs(b.point_data["displacement_m"]).max() > 0
    np.testing.assert_allclose(a.points.mean(axis=0)[:2], centre[:2], atol=1e-6)
    pa, pb = a.points[0, :2] - centre[:2], b.points[0, :2] - centre[:2]
    turn = np.arctan2(pa[0] * pb[1] - pa[1] * pb[0], pa @ pb)
    return float(turn), float(sets[k].get("timestep")) - float(sets[0].get("timestep"))


def _check_sweep(out, names, teeth, ratios, spins, centres, speed):
    """sweep.json and the VTU series of a hybrid sweep whose condensed gears are ``names``:
    each gear's (3.9) resonances at its own teeth and speed (by hand), its rim waves per speed,
    its VTU series (one file set per gear, read back by meshio), each body turning at its own
    speed and sense (the angle between two frames)."""
    w = json.loads((out / "sweep.json").read_text())
    assert w["model"] == "hybrid" and w["result"] == [0, 0]
    assert w["flexible_gears"] == names and w["flexible_gear_teeth"] == teeth
    np.testing.assert_allclose(w["flexible_gear_speed_ratio"], ratios, rtol=1e-12)
    rows = w["nodal_diameter_resonances"]
    assert {r["gear"] for r in rows} <= set(names)
    for r in rows:
        Z, ratio = teeth[names.index(r["gear"])], ratios[names.index(r["gear"])]
        sign = 1 if r["direction"] == "backward" else -1
        order = r["harmonic"] * Z + sign * r["nodal_diameter"]
        assert r["order"] == order
        if not w["campbell_at_speed"]:  # at rest: f/order is the gear's speed
            w_in = 2 * np.pi * r["frequency_hz"] / (order * ratio)
            assert r["pinion_speed_rad_s"] == pytest.approx(w_in, rel=1e-9)
    assert sorted(w["rim_waves"]) == sorted(names)
    for name in names:
        assert len(w["rim_waves"][name]) == 2
        assert all(v["axial"]["nodal_diameter"] >= 1 for v in w["rim_waves"][name])
    assert (out / "campbell.png").stat().st_size > 0
    files = w["vtu_series"]["files"]
    assert len(files) == len(names) * (2 * 16 + 1)
    for name, ratio, spin, centre in zip(names, ratios, spins, centres, strict=True):
        turn, dt = _frame_turn(out / "vtu" / f"body_{name}.pvd", np.asarray(centre), 5)
        assert turn == pytest.approx(spin * ratio * speed * dt, rel=1e-6)
    return w


@pytest.mark.slow
def test_jaxgear_sweep_with_both_members_flexible(fem_prep_cache, tmp_path):
    """`jaxgear sweep` on the test pair with both members condensed (H2): the (3.9)
    resonances and rim waves of the pinion (20 teeth, the pinion's speed) and of the wheel
    (30 teeth, 20/30 of it), and a VTU series of each body, turning +Ω and −(20/30) Ω."""
    text = CASE.read_text().replace(
        'body = "hybrid-test-wheel.toml"', f'body = "{DATA / "hybrid-test-wheel.toml"}"'
    )
    text += f'[scene.pinion_body]\nbody = "{DATA / "hybrid-test-pinion.toml"}"\n'
    path = tmp_path / "h2.toml"
    path.write_text(text)
    out = tmp_path / "sweep"
    argv = ["sweep", str(path), "--speeds", "400:800:2", "--periods", "4", "--keep-periods"]
    argv += ["2", "--steps-per-period", "16", "--out", str(out), "--quiet", "--vtu-speed", "600"]
    assert main(argv) == 0
    case = jio.load_case(path)
    scene = static_scene(case, bodies=load_bodies(case.scene))[0]
    centres = [np.asarray(m.centre) for m in scene.members]
    _check_sweep(out, ["pinion", "gear"], [20, 30], [1.0, 20 / 30], [1.0, -1.0], centres, 600.0)


@pytest.mark.slow
def test_jaxgear_sweep_on_a_train_with_two_flexible_gears(train, tmp_path):
    """`jaxgear sweep` on the train with a flexible input and a flexible idler and
    ``rotating_frame = true``: the run has each body's spin terms (the Campbell diagram and
    the (3.9) resonances follow the modes at speed), every flexible gear's resonances at its
    teeth and speed, its rim waves, and a VTU series per body named by its gear, each turning
    at its own speed (+Ω, −(20/30) Ω)."""
    path = _two_body_train(tmp_path, "[scene.integration]\nrotating_frame = true\n")
    out = tmp_path / "sweep"
    argv = ["sweep", str(path), "--speeds", "400:800:2", "--periods", "4", "--keep-periods"]
    argv += ["2", "--steps-per-period", "16", "--out", str(out), "--quiet", "--vtu-speed", "600"]
    assert main(argv) == 0
    case, bodies = train
    scene = case.hybrid_train(bodies)
    centres = [np.asarray(scene.members[g].centre) for g in (0, 1)]
    w = _check_sweep(out, ["input", "idler"], [20, 30], [1.0, 20 / 30], [1.0, -1.0], centres, 600.0)
    assert w["rotating_frame"] is True and w["campbell_at_speed"] is True
    assert w["flexible_gear_meshes"] == [["input-idler"], ["input-idler", "idler-output"]]


def test_both_members_flexible_spin_terms_leave_the_drive_rotations_neutral(fem_prep_cache):
    """Both members condensed (H2): a rigid turn of either member about its own axis costs
    nothing in its turning frame: the scene's spin stiffness (each body's at its own speed, its
    shaft's, its teeth's) maps the two drive rotations, the null space of K, to zero (1e-10 of
    its norm). On each body's modal coordinates it is the body's own fem_prep S + Kσ times its
    speed ratio squared, 1 for the pinion and (20/30)² for the wheel (to 1e-12)."""
    case = jio.load_case(CASE)
    bodies = (
        fem_prep.condensed(DATA / "hybrid-test-pinion.toml"),
        fem_prep.condensed(DATA / "hybrid-test-wheel.toml"),
    )
    scene = static_scene(case, bodies=bodies)[0]
    S = np.asarray(scene.structure.spin_stiffness)
    null = drive_rotations(scene)
    assert np.linalg.norm(S @ null) <= 1e-10 * np.linalg.norm(S, 2)
    for body, member, ratio in zip(bodies, scene.members, (1.0, 20 / 30), strict=True):
        modal = np.flatnonzero(np.asarray(body.dof_map)[:, 0] < 0)
        own = np.asarray(body.spin_softening) + np.asarray(body.stress_stiffening)
        g = np.asarray(member.body_dofs)[modal]
        np.testing.assert_allclose(
            S[np.ix_(g, g)],
            ratio**2 * own[np.ix_(modal, modal)],
            rtol=0,
            atol=1e-12 * np.abs(own).max(),
        )


@pytest.mark.slow
def test_rigidified_pinion_body_in_its_turning_frame_is_the_lumped_pinion(fem_prep_cache):
    """The dynamics with a condensed pinion: the test pinion body 100× stiffer (1000×:
    fem_prep's eigen-solver misses its residual check) as the pair's pinion (the wheel a rigid
    node), its frame turning at +Ω with its Coriolis, spin softening and stress stiffening
    (``rotating_frame``), against the rigid-node lumped pair given the body's mass and
    inertias; Rayleigh D1, uniform mesh stiffness, 32 steps per period, 60 periods: dynamic
    factor within 0.5 % at 800, 1500 and 2100 rad/s (measured −0.18, +0.31, −0.10 %; without
    the rotating-frame terms −0.16, −0.26, −0.21 %: this stiff pinion's spin terms are small,
    and the rest is the body's remaining flexibility)."""
    pair = rigidified_pair(jio.load_case(CASE), 0, DATA / "hybrid-test-pinion.toml", 100.0)
    d1 = Damping("rayleigh", alpha=25.0, beta=2.5e-6)
    speeds = [800.0, 1500.0, 2100.0]
    got, refs, _ = rigidified_runs(pair, speeds, d1, spp=32, periods=60, rotating_frame=True)
    ref = [float(r.dynamic_factor) for r in refs]
    np.testing.assert_allclose(np.asarray(got.dynamic_factor), ref, rtol=5e-3)


def test_rotating_frame_on_a_rigid_train_is_a_one_line_error(tmp_path):
    """``rotating_frame = true`` on a train without condensed bodies: one line naming the key
    and what it needs, when the file is read."""
    rigid = TRAIN.read_text().split("[scene.bodies.idler]")[0]
    path = tmp_path / "rigid.toml"
    path.write_text(rigid + "[scene.integration]\nrotating_frame = true\n")
    with pytest.raises(ValueError, match=r"rotating_frame.*condensed body") as err:
        jio.load_case(path)
    assert "\n" not in str(err.value)
