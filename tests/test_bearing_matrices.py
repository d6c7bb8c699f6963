"""6×6 bearing stiffness and damping matrices: case-file keys, checks, assembly into
the lumped and hybrid scenes' K, and the bearing damping in the dynamic model's C.

References: the diagonal radial/axial/tilt keys (the same K bit for bit, the same quasi-static
solution); the statics of a rigid shaft on two coupled 6×6 springs written out by hand in NumPy;
the 1-DOF damping ratio ξ = c/(2√(k m)) of the axial mode of a spur pinion shaft (the axial
motion is decoupled from the spur mesh) from the quadratic eigenvalues of the model's (M, C, K̄);
the bearing damping blocks assembled by hand.
"""

from __future__ import annotations

import copy
import dataclasses
import math
import pathlib

import jax.numpy as jnp
import numpy as np
import pytest
import scipy.linalg
from _scene_solve import grounded_solve
from _toml import ACCESSORY_PAIR

import fem_prep
import jaxgear as jg
import jaxgear.io as jio
from jaxgear.dynamics import damping_matrix, dynamic_model
from jaxgear.io import Damping, SchemaError, parse_scene, static_scene
from jaxgear.scenes import Bearing, ShaftSpec, bearing_matrix, lumped_pair, shaft_matrices

DATA = pathlib.Path(__file__).parent / "data"


@pytest.fixture(scope="module")
def case():
    return jio.load_case("accessory-spur").replace(slices=6)


def _as_matrix_keys(bearing: dict) -> dict:
    """A bearing table with its diagonal keys written as the equivalent stiffness_matrix_SI."""
    b = dict(bearing)
    radial = b.pop("radial_N_per_um", 200.0) * 1e6
    axial = b.pop("axial_N_per_um", 0.0) * 1e6
    tilt = b.pop("tilt_Nm_per_rad", 0.0)
    b["stiffness_matrix_SI"] = np.diag([radial, radial, axial, tilt, tilt, 0.0]).tolist()
    return b


def test_diagonal_matrix_gives_the_same_K_and_quasi_static_solution(case):
    raw = copy.deepcopy(case.raw["scene"])
    for shaft in ("pinion_shaft", "gear_shaft"):
        raw[shaft]["bearings"] = [_as_matrix_keys(b) for b in raw[shaft]["bearings"]]
    spec_m = parse_scene(raw)
    assert all(b.stiffness is not None and b.radial is None for b in spec_m.pinion_shaft.bearings)
    model_d, r_d = grounded_solve(case, case.scene)
    model_m, r_m = grounded_solve(case, spec_m)
    sd, sm = model_d.scene, model_m.scene
    np.testing.assert_array_equal(
        np.asarray(sm.structure.K), np.asarray(sd.structure.K)
    )  # bit for bit
    np.testing.assert_array_equal(
        np.asarray(sm.structure.reaction), np.asarray(sd.structure.reaction)
    )
    assert sm.reaction_names == sd.reaction_names
    np.testing.assert_array_equal(np.asarray(sm.bearing_damping()), 0.0)
    np.testing.assert_allclose(r_m.transmission_error, r_d.transmission_error, rtol=1e-12)
    np.testing.assert_allclose(r_m.x, r_d.x, rtol=1e-12, atol=1e-12 * float(jnp.max(abs(r_d.x))))
    np.testing.assert_allclose(model_m.damping, model_d.damping, rtol=1e-12, atol=1e-12)


def _rot(deg):
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    return np.array([[c, -s], [s, c]])


def _coupled_bearings():
    """Two PSD bearing matrices with rotated radial axes, radial-tilt and radial-axial couplings."""
    KA = np.zeros((6, 6))
    KA[:2, :2] = _rot(30) @ np.diag([3e8, 1e8]) @ _rot(30).T
    KA[2, 2] = 1.5e8
    KA[3, 3], KA[4, 4] = 2e5, 3e5
    KA[0, 4] = KA[4, 0] = 2e6
    KA[1, 3] = KA[3, 1] = -1e6
    KA[0, 2] = KA[2, 0] = 2e7
    KB = np.zeros((6, 6))
    KB[:2, :2] = _rot(-20) @ np.diag([2e8, 0.5e8]) @ _rot(-20).T
    KB[3, 3], KB[4, 4] = 1e5, 1e5
    KB[1, 3] = KB[3, 1] = 1.5e6
    KB[0, 3] = KB[3, 0] = 0.5e6
    return KA, KB  # PSD: checked by Bearing (bearing_matrix)


def _T(z):
    """Node DOFs (u, φ) at axial position z of a rigid shaft moving with (u0, φ) at z = 0:
    u = u0 + φ × z e_z, i.e. u_x += φ_y z, u_y −= φ_x z."""
    T = np.eye(6)
    T[0, 4] = z
    T[1, 3] = -z
    return T


def _shaft_on_coupled_bearings(case, stiffening):
    """FE displacements (pinion shaft block of the lumped scene's K, rz of node 0 pinned) of a
    shaft ``stiffening`` × stiffer than steel on the two coupled bearings under F at the gear."""
    KA, KB = _coupled_bearings()
    shaft = ShaftSpec(
        length=0.1,
        diameter=0.06,
        gear_z=0.05,
        bearings=(Bearing(0.0, stiffness=KA), Bearing(0.1, stiffness=KB)),
        elements=4,
    )
    other = ShaftSpec(length=0.1, diameter=0.03, gear_z=0.05, bearings=(Bearing(0.0), Bearing(0.1)))
    E = 210e9 * stiffening
    scene = lumped_pair(
        case.pair,
        case.mesh_model(slices=2),
        shaft,
        other,
        masses=(1.0, 1.0),
        inertias=((1e-3, 2e-3), (1e-3, 2e-3)),
        youngs_modulus=E,
    )
    nodes = shaft_matrices(shaft, E, E / 2.6, 7800.0).nodes
    n1 = 6 * nodes.size
    K = np.asarray(scene.structure.K)[:n1, :n1]
    f = np.zeros(n1)
    g = scene.members[0].dofs[0]  # the pinion's gear node
    f[g : g + 6] = LOAD
    keep = np.setdiff1d(np.arange(n1), [5])  # rz of node 0 pinned (the free drive rotation)
    x = np.zeros(n1)
    x[keep] = np.linalg.solve(K[np.ix_(keep, keep)], f[keep])
    return scene, nodes, x


LOAD = np.array([1000.0, -500.0, 300.0, 20.0, -10.0, 0.0])  # F (N), M (N·m) at the gear node


def test_coupled_matrices_give_the_statics_of_a_rigid_shaft_on_two_springs(case):
    """A shaft on two coupled 6×6 bearings (rotated radial axes, radial-tilt and radial-axial
    couplings) under a known force and moment at the gear node, against the hand-written statics
    of a rigid shaft: K_rb q = T_gᵀ F, K_rb = Σ T_bᵀ K_b T_b. The FE shaft is 1e3 and 1e4 × stiffer
    than steel: the difference falls as 1/E (the shaft's own compliance), to ~1e-5 at 1e4; the
    bearing forces (translational rows of each 6×6) balance the load."""
    KA, KB = _coupled_bearings()
    L, zg = 0.1, 0.05
    Krb = _T(0.0).T @ KA @ _T(0.0) + _T(L).T @ KB @ _T(L)
    Q = _T(zg).T @ LOAD
    assert np.linalg.eigvalsh(Krb[:5, :5]).min() > 0  # the bearings hold the rigid shaft
    q = np.zeros(6)  # (u0, φ) at z = 0; φ_z left out (no torque, free)
    q[:5] = np.linalg.solve(Krb[:5, :5], Q[:5])
    errors = []
    for stiffening in (1e3, 1e4):
        scene, nodes, x = _shaft_on_coupled_bearings(case, stiffening)
        err = 0.0
        for z in (0.0, zg, L):
            i = int(np.argmin(np.abs(nodes - z)))
            ref = (_T(z) @ q)[:5]
            err = max(err, np.abs(x[6 * i : 6 * i + 5] - ref).max() / np.abs(ref).max())
        errors.append(err)
    assert errors[1] < 3e-5
    assert errors[0] / errors[1] == pytest.approx(10.0, rel=0.05)
    # the couplings matter: the diagonal part of the bearings alone is far off
    Kd = _T(0.0).T @ np.diag(np.diag(KA)) @ _T(0.0) + _T(L).T @ np.diag(np.diag(KB)) @ _T(L)
    qd = np.linalg.solve(Kd[:5, :5], Q[:5])
    assert np.linalg.norm(qd - q[:5]) > 0.1 * np.linalg.norm(q[:5])
    # bearing forces (translational rows of each 6×6, couplings included) balance the load
    n1 = x.size
    names = [nm for nm in scene.reaction_names if nm.startswith("pinion")]
    assert len(names) == 5  # Fx, Fy, Fz at z = 0; Fx, Fy at z = L (no axial row: K_B[2] = 0)
    forces = np.asarray(scene.reaction_matrix())[: len(names), :n1] @ x
    for c, axis in enumerate("xyz"):
        total = sum(fv for fv, nm in zip(forces, names, strict=True) if nm.endswith(f"F{axis}"))
        assert total == pytest.approx(LOAD[c], rel=1e-8, abs=1e-8 * np.abs(LOAD).max())
    np.testing.assert_allclose(forces[:3], (KA @ _T(0.0) @ q)[:3], rtol=1e-4, atol=1e-4 * 1000)


def _pinion_mass(case):
    p = case.pair
    return case.density * math.pi * p.tip_radii[0] ** 2 * p.pinion.face_width


def _axial_scene(case, k_axial, c_axial, extra_damping=None):
    p = case.pair
    rho = case.density
    r1 = p.tip_radii[0]
    m1 = _pinion_mass(case)
    r2, b2 = p.tip_radii[1], p.gear.face_width
    m2 = rho * math.pi * r2 * r2 * b2
    C = np.zeros((6, 6))
    C[2, 2] = c_axial
    if extra_damping is not None:
        C = C + extra_damping
    Kp = np.diag([2e8, 2e8, k_axial, 0.0, 0.0, 0.0])
    pinion = ShaftSpec(
        length=0.1,
        diameter=0.03,
        gear_z=0.05,
        bearings=(Bearing(0.0, stiffness=Kp, damping=C), Bearing(0.1, 2e8, 0.0, 0.0)),
    )
    gear = ShaftSpec(
        length=0.1,
        diameter=0.035,
        gear_z=0.05,
        torque_z=0.1,
        bearings=(Bearing(0.0, 3e8, 1e8, 0.0), Bearing(0.1, 3e8, 0.0, 0.0)),
    )
    inertias = ((m1 * r1 * r1 / 4, m1 * r1 * r1 / 2), (m2 * r2 * r2 / 4, m2 * r2 * r2 / 2))
    scene = lumped_pair(
        p, case.mesh_model(slices=4), pinion, gear, masses=(m1, m2), inertias=inertias
    )
    m_axial = m1 + rho * math.pi * 0.03**2 / 4 * 0.1  # gear body + the whole shaft
    return scene, pinion, gear, m_axial


def test_bearing_damping_gives_the_one_dof_damping_ratio_of_the_axial_mode(case):
    """Spur pinion: its axial motion (shaft bar + gear mass on the axial bearing k) is decoupled
    from the mesh, a 1-DOF oscillator up to the bar's compliance (k/(EA/L) ≈ 7e-4). With the
    bearing damping c the model's C (damping model "none": the bearing damping alone) gives the
    quadratic eigenvalue λ of that mode with −Re λ/|λ| = c/(2√(k m))."""
    k = 1e6
    m = _pinion_mass(case) + case.density * math.pi * 0.03**2 / 4 * 0.1
    c = 2 * 0.05 * math.sqrt(k * m)  # ξ = 0.05
    scene, pinion, _, m_axial = _axial_scene(case, k, c)
    assert m_axial == m
    model = dynamic_model(scene, None, case.torque, Damping("none"), positions_per_pitch=16)
    M = np.asarray(scene.structure.M)
    C = np.asarray(model.damping)
    np.testing.assert_array_equal(C, np.asarray(scene.bearing_damping()))
    K = np.asarray(scene.structure.K) + np.asarray(model.modes.mesh_stiffness)
    n = M.shape[0]
    Minv = np.linalg.inv(M)
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-Minv @ K, -Minv @ C]])
    lam, vec = scipy.linalg.eig(A)
    n1 = 6 * shaft_matrices(pinion, 210e9, 210e9 / 2.6, 7800.0).nodes.size
    uz = np.zeros(n, dtype=bool)
    uz[2:n1:6] = True
    amplitude = np.linalg.norm(vec[:n], axis=0)
    share = np.linalg.norm(vec[:n][uz], axis=0) / np.maximum(amplitude, 1e-300)
    # the lowest pinion-axial mode (the others are the shaft's own bar modes, far above)
    axial = np.flatnonzero((share > 0.999) & (np.abs(lam) > 1.0))
    j = int(axial[np.argmin(np.abs(lam[axial]))])
    xi = -lam[j].real / abs(lam[j])
    assert xi == pytest.approx(c / (2 * math.sqrt(k * m)), rel=2e-3)
    assert abs(lam[j]) == pytest.approx(math.sqrt(k / m), rel=2e-3)
    # the other models add the bearing damping to their own C
    d = Damping("rayleigh", alpha=30.0, beta=2e-6)
    Cr = np.asarray(damping_matrix(scene, model.modes, d))
    np.testing.assert_allclose(Cr - (30.0 * M + 2e-6 * K), C, atol=1e-9 * np.abs(Cr).max())


def test_bearing_damping_is_assembled_at_the_bearing_nodes(case):
    Cd = np.diag([1e3, 2e3, 3e3, 4.0, 5.0, 0.0])
    Cd[0, 4] = Cd[4, 0] = 30.0
    scene, pinion, gear, _ = _axial_scene(case, 1e8, 0.0, extra_damping=Cd)
    E, G = 210e9, 210e9 / 2.6
    nodes1 = shaft_matrices(pinion, E, G, 7800.0).nodes
    nodes2 = shaft_matrices(gear, E, G, 7800.0).nodes
    n1 = 6 * nodes1.size
    n = n1 + 6 * nodes2.size
    ref = np.zeros((n, n))
    i = 6 * int(np.argmin(np.abs(nodes1 - 0.0)))
    ref[i : i + 6, i : i + 6] = Cd
    np.testing.assert_array_equal(np.asarray(scene.bearing_damping()), ref)


# ---- case-file keys and checks ------------------------------------------------------------


def _raw_with(case, **bearing0):
    raw = copy.deepcopy(case.raw["scene"])
    b = raw["pinion_shaft"]["bearings"][0]
    for key, value in bearing0.items():
        if value is None:
            b.pop(key, None)
        else:
            b[key] = value
    return raw


_K_OK = np.diag([2e8, 2e8, 1e8, 1e5, 1e5, 0.0]).tolist()


def _with(entries, base=_K_OK):
    K = [list(r) for r in base]
    for (i, j), v in entries.items():
        K[i][j] = v
    return K


@pytest.mark.parametrize(
    ("keys", "pattern"),
    [
        (
            {"stiffness_matrix_SI": _K_OK[:5]},
            (
                r"^\[scene\.pinion_shaft\.bearings\[0\]\] stiffness_matrix_SI = \[\[.*\]: must be "
                r"6 rows of 6 finite numbers \(SI; DOF order ux, uy, uz, rx, ry, rz\), got 5 rows"
            ),
        ),
        (
            {"stiffness_matrix_SI": _with({(2, 2): True})},
            r"stiffness_matrix_SI = .*: must be 6 rows of 6 finite numbers.*non-number",
        ),
        (
            {"stiffness_matrix_SI": _with({(0, 4): 1e6})},
            (
                r"^\[scene\.pinion_shaft\.bearings\[0\]\] stiffness_matrix_SI: not symmetric: "
                r"\[0\]\[4\] = 1e\+06 but \[4\]\[0\] = 0 \(allowed \|K_ij - K_ji\| <= 1e-06"
            ),
        ),
        (
            {"stiffness_matrix_SI": _with({(0, 4): 1e7, (4, 0): 1e7})},
            (
                r"stiffness_matrix_SI: not positive semi-definite: smallest eigenvalue of "
                r"K_ij/sqrt\(K_ii K_jj\) is -1\.23607 \(allowed >= -1e-06\)"
            ),
        ),
        (
            {"stiffness_matrix_SI": _with({(1, 1): -1.0})},
            r"stiffness_matrix_SI: not positive semi-definite: \[1\]\[1\] = -1 \(allowed",
        ),
        (
            {"stiffness_matrix_SI": _with({(5, 5): 1e3})},
            r"stiffness_matrix_SI: row and column 5 \(rz\) must be 0, got \[5\]\[5\] = 1000",
        ),
        (
            {
                "stiffness_matrix_SI": _K_OK,
                "damping_matrix_SI": _with({(3, 3): 0.0, (0, 3): 5.0, (3, 0): 5.0}),
            },
            r"damping_matrix_SI: not positive semi-definite: \[3\]\[3\] = 0 but \[3\]\[0\] = 5",
        ),
        (
            {"stiffness_matrix_SI": _K_OK},  # the case's radial/axial keys stay
            (
                r"^\[scene\.pinion_shaft\.bearings\[0\]\] stiffness_matrix_SI: give either "
                r"radial_N_per_um/axial_N_per_um/tilt_Nm_per_rad or stiffness_matrix_SI, not both "
                r"\(the matrix is the whole stiffness; remove radial_N_per_um, axial_N_per_um\)"
            ),
        ),
        (
            {
                "radial_N_per_um": None,
                "axial_N_per_um": None,
                "stiffness_matrix_SI": np.diag([2e8, 2e8, 0.0, 0, 0, 0]).tolist(),
            },
            (
                r"needs an axial stiffness on at least one bearing \(axial_N_per_um > 0 or "
                r"stiffness_matrix_SI\[2\]\[2\] > 0\)"
            ),
        ),
    ],
)
def test_bad_matrices_give_a_one_line_error(case, keys, pattern):
    raw = _raw_with(case, **keys)
    with pytest.raises(SchemaError, match=pattern) as err:
        parse_scene(raw)
    assert "\n" not in str(err.value)


MATRIX_CASE = (
    """
name = "bearing-matrices"
"""
    + ACCESSORY_PAIR
    + """[mesh]
stiffness = "uniform"
stiffness_per_length_N_per_mm_per_um = 14.0
slices = 2
[scene]
model = "lumped3d"
[scene.pinion_shaft]
length_mm = 100.0
diameter_mm = 30.0
gear_position_mm = 50.0
[[scene.pinion_shaft.bearings]]      # array-of-tables form: a matrix spans several lines
position_mm = 0.0
stiffness_matrix_SI = [              # SI per DOF pair; ux, uy, uz, rx, ry, rz
  [2e8,   0,    0,   0,    2e6, 0],
  [0,     2e8,  0,   -2e6, 0,   0],
  [0,     0,    1e8, 0,    0,   0],
  [0,     -2e6, 0,   1e5,  0,   0],
  [2e6,   0,    0,   0,    1e5, 0],
  [0,     0,    0,   0,    0,   0],
]
damping_matrix_SI = [
  [500, 0,   0,   0, 0, 0],
  [0,   500, 0,   0, 0, 0],
  [0,   0,   200, 0, 0, 0],
  [0,   0,   0,   0, 0, 0],
  [0,   0,   0,   0, 0, 0],
  [0,   0,   0,   0, 0, 0],
]
[[scene.pinion_shaft.bearings]]
position_mm = 100.0
radial_N_per_um = 200.0
damping_matrix_SI = [[300, 0, 0, 0, 0, 0], [0, 300, 0, 0, 0, 0], [0, 0, 0, 0, 0, 0],
                     [0, 0, 0, 0, 0, 0], [0, 0, 0, 0, 0, 0], [0, 0, 0, 0, 0, 0]]
[scene.gear_shaft]
length_mm = 100.0
diameter_mm = 35.0
gear_position_mm = 50.0
torque_position_mm = 100.0
bearings = [{ position_mm = 0.0, radial_N_per_um = 300.0, axial_N_per_um = 100.0 },
            { position_mm = 100.0, radial_N_per_um = 300.0 }]
"""
)


def test_matrix_keys_parse_from_a_case_file_in_si(tmp_path):
    path = tmp_path / "matrix.toml"
    path.write_text(MATRIX_CASE)
    b0, b1 = jio.load_case(path).scene.pinion_shaft.bearings
    assert b0.radial is None and b0.stiffness_matrix()[0, 4] == 2e6
    assert b0.stiffness_matrix()[3, 1] == -2e6 and b0.damping_matrix()[2, 2] == 200.0
    # diagonal keys and a damping matrix together (the case file's axial default: 0)
    np.testing.assert_array_equal(np.diag(b1.stiffness_matrix()), [2e8, 2e8, 0, 0, 0, 0])
    assert b1.damping_matrix()[1, 1] == 300.0
    path.write_text(MATRIX_CASE.replace("[0,     0,    1e8, 0,    0,   0]", "[0, 0, 1e8, 0, 0, 9]"))
    with pytest.raises(
        SchemaError,
        match=r"^\[scene\.pinion_shaft\.bearings\[0\]\] stiffness_matrix_SI: not symmetric: "
        r"\[2\]\[5\] = 9 but \[5\]\[2\] = 0",
    ):
        jio.load_case(path)


def test_python_bearing_refuses_both_forms_and_checks_matrices():
    K = np.diag([1.0, 1.0, 1.0, 1.0, 1.0, 0.0])
    with pytest.raises(ValueError, match="give either radial/axial/tilt or a stiffness matrix"):
        Bearing(0.0, radial=1e8, stiffness=K)
    with pytest.raises(ValueError, match=r"Bearing at z = 10 mm: damping not symmetric"):
        Bearing(0.01, damping=K + np.triu(np.ones((6, 6)), 1))
    b = Bearing(0.0, stiffness=K)
    assert b.radial is None and b.axial is None and b.tilt is None
    assert dataclasses.replace(b, damping=K).stiffness == b.stiffness  # replace keeps the form
    assert hash(b) == hash(Bearing(0.0, stiffness=K.tolist()))  # stored as nested tuples
    # an asymmetry within the tolerance (1e-6 of sqrt(K_ii K_jj)) is accepted and symmetrised
    K2 = K.copy()
    K2[0, 1] = 1e-8
    a = bearing_matrix(K2)
    assert a[0, 1] == a[1, 0] == 0.5e-8


# ---- hybrid scene ---------------------------------------------------------------------------


@pytest.fixture(scope="module")
def hybrid(fem_prep_cache):
    case = jio.load_case(DATA / "hybrid-test-case.toml")
    body = fem_prep.condensed(DATA / "hybrid-test-wheel.toml")
    return case, body


def _hybrid_spec(case, gear_bearings):
    raw = copy.deepcopy(case.raw["scene"])
    raw["gear_shaft"]["bearings"] = gear_bearings
    raw["pinion_shaft"]["bearings"] = [_as_matrix_keys(b) for b in raw["pinion_shaft"]["bearings"]]
    return parse_scene(raw, base_dir=str(DATA))


# default tier: tests/test_bearing_matrices.py::test_diagonal_matrix_gives_the_same_K_and_quasi_static_solution and test_bearing_damping_is_assembled_at_the_bearing_nodes (same claims on the lumped 3D scene: matrix keys give the diagonal keys' K, the damping block at the bearing node); a hybrid scene's bearings run in tests/test_every_kind.py's pair-hybrid run and test_hybrid_refuses_a_non_axisymmetric_bearing_on_a_flexible_shaft
@pytest.mark.slow
def test_hybrid_scene_assembles_matrices_and_exposes_bearing_damping(hybrid):
    """Diagonal keys as matrices: the hybrid K bit for bit. An axisymmetric coupled matrix with
    damping on the flexible wheel's shaft: K changes by exactly its block, bearing_damping()
    holds the damping block at the bearing node and zeros elsewhere, shape (n, n)."""
    case, body = hybrid
    base = static_scene(case, bodies=(None, body))[0]
    gear_b = case.raw["scene"]["gear_shaft"]["bearings"]
    same = static_scene(
        case.replace(scene=_hybrid_spec(case, [_as_matrix_keys(b) for b in gear_b])),
        bodies=(None, body),
    )[0]
    np.testing.assert_array_equal(np.asarray(same.structure.K), np.asarray(base.structure.K))
    np.testing.assert_array_equal(np.asarray(same.bearing_damping()), 0.0)
    k, c = 3e8, 1e8
    K0 = np.diag([k, k, c, 0.0, 0.0, 0.0])
    Kc = K0 + np.diag([0.0, 0.0, 0.0, 2e5, 2e5, 0.0])
    Kc[0, 4] = Kc[4, 0] = 3e6  # radial-tilt coupling, axisymmetric: K[1][3] = −K[0][4]
    Kc[1, 3] = Kc[3, 1] = -3e6
    Cc = np.diag([800.0, 800.0, 300.0, 2.0, 2.0, 0.0])
    bearings = [
        {"position_mm": 0.0, "stiffness_matrix_SI": Kc.tolist(), "damping_matrix_SI": Cc.tolist()},
        gear_b[1],
    ]
    spec = _hybrid_spec(case, bearings)
    sc = static_scene(case.replace(scene=spec), bodies=(None, body))[0]
    n = base.structure.K.shape[0]
    # the bearing at 0 mm is node 0 of the gear shaft, whose DOFs follow the pinion shaft's
    i = 6 * shaft_matrices(spec.pinion_shaft, 210e9, 80e9, 7800.0).nodes.size
    dK = np.asarray(sc.structure.K) - np.asarray(base.structure.K)
    np.testing.assert_allclose(dK[i : i + 6, i : i + 6], Kc - K0, rtol=1e-12, atol=1e-3)
    dK[i : i + 6, i : i + 6] = 0.0
    assert np.abs(dK).max() <= 1e-6 * np.abs(np.asarray(base.structure.K)).max()
    Cb = np.asarray(sc.bearing_damping())
    assert Cb.shape == (n, n)
    ref = np.zeros((n, n))
    ref[i : i + 6, i : i + 6] = Cc
    np.testing.assert_array_equal(Cb, ref)
    # the quasi-static solve still runs (drive rotation free, structure definite)
    r = jg.quasi_static(sc, case.modifications, case.torque, jg.mesh_positions(sc.mesh, 2))
    assert np.all(np.asarray(r.result) == 0)


def test_hybrid_refuses_a_non_axisymmetric_bearing_on_a_flexible_shaft(hybrid):
    case, body = hybrid
    K = np.diag([3e8, 1e8, 1e8, 0.0, 0.0, 0.0])  # orthotropic radial stiffness
    gear_b = case.raw["scene"]["gear_shaft"]["bearings"]
    spec = _hybrid_spec(case, [{"position_mm": 0.0, "stiffness_matrix_SI": K.tolist()}, gear_b[1]])
    with pytest.raises(
        ValueError,
        match=r"scene\.gear_shaft\.bearings\[0\]: its stiffness matrix is not axisymmetric "
        r"about the shaft axis",
    ):
        static_scene(case.replace(scene=spec), bodies=(None, body))
    # the same matrix on the rigid pinion's shaft (fixed frame) is fine
    raw = copy.deepcopy(case.raw["scene"])
    raw["pinion_shaft"]["bearings"][0] = {"position_mm": 0.0, "stiffness_matrix_SI": K.tolist()}
    spec = parse_scene(raw, base_dir=str(DATA))
    sc = static_scene(case.replace(scene=spec), bodies=(None, body))[0]
    assert sc.bearing_damping().shape == sc.structure.K.shape
