"""The hybrid scene on a flexible housing (jaxgear.scenes.Housing, docs/housing.md, "Hybrid
scenes"): the small flexible-wheel pair (H1) with its shafts' bearings in the seats of a box
housing, the wheel's shaft too (it turns with the condensed body's frame and meets its seats at
that frame's angle at θ = 0). References written here: the full, uncondensed housing FE joined
to the grounded hybrid structure by the bearings (modes), the grounded hybrid scene as the
housing grows stiff, and the static equilibrium of the shafts and of the housing."""

import json
import math
import pathlib

import numpy as np
import pytest
import scipy.linalg as sla
import scipy.sparse as sp
import scipy.sparse.linalg as spla

import fem_prep
import jaxgear as jg
from fem_prep.housing import Bore, Foot, HousingBox, Tet4, mesh_box, prepare_housing
from jaxgear import io as jio
from jaxgear.cli import main
from jaxgear.scenes import Housing, Material, hybrid_pair, shaft_matrices

DATA = pathlib.Path(__file__).parent / "data"
# housing frame -> scene frame: the shafts' axis (scene z) along the box's length (housing x),
# the shafts' plane (scene x) along its width (housing y), scene y along its height (housing z)
R = np.array([[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]])
SEATS = [0, 1, None, None]  # the pinion's bearings in the housing's two seats; the wheel's grounded


@pytest.fixture(scope="module")
def case(fem_prep_cache):
    return jio.load_case(DATA / "hybrid-test-case.toml")


@pytest.fixture(scope="module")
def body(fem_prep_cache):
    return fem_prep.condensed(DATA / "hybrid-test-wheel.toml")


def _box(a, t=0.008, width=0.16, height=0.12):
    """A box whose end walls' mid-planes hold the pinion's bearings (at ±40 mm of the gears),
    a bore round the pinion's axis in each end wall (seat 0 at z = −40 mm, 1 at +40 mm), four
    feet at the bottom corners; and its offset (m)."""
    L = 0.08 + t
    off = np.array([-(width / 2 - a / 2), -height / 2, -L / 2])
    bores = tuple(Bore(w, (-off[0], height / 2), 0.014) for w in ("x-", "x+"))
    f = 0.025
    feet = tuple(Foot((x0, x0 + f), (y0, y0 + f)) for x0 in (0.0, L - f) for y0 in (0.0, width - f))
    return HousingBox(L, width, height, t, bores=bores, feet=feet), off


def _prepared(case, youngs_modulus, density, cutoff_hz):
    box, off = _box(case.pair.center_distance)
    material = fem_prep.Material(youngs_modulus, 0.3, density)
    ph = prepare_housing(mesh_box(box, 0.03, element=Tet4()), material, cutoff_hz)
    return ph, Housing.of(ph.condensed_housing(), rotation=R, offset=off), off


def _scene(case, body, housing=None, seats=None):
    s = case.scene
    return hybrid_pair(
        case.pair,
        case.mesh_model(flexible=(False, True)),
        s.pinion_shaft,
        s.gear_shaft,
        bodies=(None, body),
        masses=(0.3, 1.0),
        inertias=((1e-4, 2e-4), (1e-3, 1e-3)),
        housing=housing,
        seats=seats,
    )


@pytest.fixture(scope="module")
def grounded(case, body):
    return _scene(case, body)


def _freqs(structure, below):
    lam = sla.eigvalsh(np.asarray(structure.K), np.asarray(structure.M))
    f = np.sqrt(np.abs(lam)) / (2 * math.pi)
    return f[(f > 1.0) & (f < below)]


def _skew(a):
    return np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])


def test_hybrid_modes_on_a_housing_match_the_full_housing_below_the_cutoff(case, body, grounded):
    """A soft housing (E = 7 GPa, ρ = 2700 kg/m³) condensed to f_c = 4 kHz under the hybrid
    pair: the coupled structure's natural frequencies below 0.6 f_c equal, within 0.6 %
    (measured 0.54 %, 7 modes up to 2.3 kHz), those of the grounded hybrid structure joined
    here by the pinion's two bearings (their stiffness K_b on the relative motion of shaft
    node and seat, rigid-link seat motion) to the full, uncondensed housing FE (sparse
    shift-invert); the grounded scene alone is far off. Between 0.6 f_c and f_c / 1.5 a
    coupled mode that leans on the dropped housing modes is 4 % high (2.63 kHz): on this small
    box f_c = 2 kHz would keep one housing mode and miss a free-seat mode at 1.29 kHz."""
    cutoff = 4000.0
    ph, housing, off = _prepared(case, 7e9, 2700.0, cutoff)
    st = _scene(case, body, housing, SEATS).structure
    got = _freqs(st, 0.6 * cutoff)
    # the reference: [grounded hybrid structure | full housing], the bearings added here
    Kg, Mg = np.asarray(grounded.structure.K), np.asarray(grounded.structure.M)
    ng, nh = Kg.shape[0], ph.K.shape[0]
    K = sp.lil_matrix((ng + nh, ng + nh))
    K[:ng, :ng] = Kg
    seats = off + np.array([s.centre for s in ph.mesh.seats]) @ R.T  # scene frame
    spec = case.scene.pinion_shaft
    E = case.youngs_modulus
    sm = shaft_matrices(spec, E, E / (2 * (1 + case.poisson_ratio)), case.density)
    for b, k in zip(spec.bearings, (0, 1), strict=True):
        p = np.array([0.0, 0.0, b.z - spec.gear_z])
        u = 6 * int(np.argmin(np.abs(sm.nodes - b.z))) + np.arange(6)  # pinion shaft first
        q = ng + ph.seat_dofs[k]
        G = np.zeros((6, 6))
        G[:3, :3] = G[3:, 3:] = R
        G[:3, 3:] = -_skew(p - seats[k]) @ R
        kb = b.stiffness_matrix()  # K_b on u is the grounded structure's already
        K[np.ix_(u, q)] = K[np.ix_(u, q)].toarray() - kb @ G
        K[np.ix_(q, u)] = K[np.ix_(q, u)].toarray() - G.T @ kb
        K[np.ix_(q, q)] = K[np.ix_(q, q)].toarray() + G.T @ kb @ G
    K = (K.tocsc() + sp.block_diag([sp.csr_matrix((ng, ng)), ph.K])).tocsc()
    M = sp.block_diag([sp.csr_matrix(Mg), ph.M]).tocsc()
    mu = spla.eigsh(K, k=len(got) + 6, M=M, sigma=-((2 * math.pi * 5.0) ** 2), which="LM")[0]
    ref = np.sort(np.sqrt(np.abs(mu)) / (2 * math.pi))
    ref = ref[ref > 1.0][: len(got)]
    assert len(got) >= 7
    np.testing.assert_allclose(got, ref, rtol=0.006)
    f0 = _freqs(grounded.structure, 0.6 * cutoff)
    assert abs(f0[0] / got[0] - 1) > 0.05


def test_stiff_housing_hybrid_structure_tends_to_the_grounded_one(case, body, grounded):
    """The housing's Young's modulus x 10 per step (steel's density): the coupled hybrid
    structure's natural frequencies below 5 kHz tend to the grounded hybrid structure's, the
    difference falling as the housing's compliance (x 0.1 per step; asserted <= x 0.125)."""
    f0 = _freqs(grounded.structure, 5000.0)
    errs = []
    for scale in (1e1, 1e2, 1e3):
        _, housing, _ = _prepared(case, 210e9 * scale, 7800.0, 5000.0)
        f = _freqs(_scene(case, body, housing, SEATS).structure, math.inf)[: f0.size]
        errs.append(np.abs(f / f0 - 1).max())
    errs = np.array(errs)
    assert np.all(errs[1:] < errs[:-1] / 8) and errs[-1] < 1e-4


@pytest.mark.slow
def test_stiff_housing_hybrid_quasi_static_tends_to_the_grounded_one(case, body, grounded):
    """Through the contact solve (20 s, a compile): the hybrid pair's quasi-static TE on a
    steel housing differs from the grounded pair's by 0.77 µm (the pinion shaft's seats give);
    x 10, 100 on the housing's Young's modulus divide the difference by 10 each (measured
    0.0768, 0.00768 µm; asserted within 2 %)."""
    theta = jg.mesh_positions(case.mesh_model(), 4, 1)
    mods, torque = case.modifications, case.torque

    def te(scene):
        return np.asarray(jg.quasi_static(scene, mods, torque, theta).meshes[0].transmission_error)

    te0 = te(grounded)
    diffs = []
    for scale in (1.0, 1e1, 1e2):
        _, housing, _ = _prepared(case, 210e9 * scale, 7800.0, 5000.0)
        diffs.append(np.abs(te(_scene(case, body, housing, SEATS)) - te0).max())
    assert diffs[0] > 1e-7  # the housing gives (m)
    np.testing.assert_allclose(np.array(diffs[1:]) / np.array(diffs[:-1]), 0.1, rtol=0.02)


def test_bearings_left_on_the_ground_leave_the_housing_free(case, body, grounded):
    """With every bearing on the ground (seats None each) the housing hangs free of the shafts,
    whose structure is the grounded one exactly; a seat index out of range is a one-line
    error."""
    _, housing, _ = _prepared(case, 210e9, 7800.0, 5000.0)
    with pytest.raises(ValueError, match=r"seats\[2\] = 5") as err:
        _scene(case, body, housing, [0, 1, 5, None])
    assert "\n" not in str(err.value)
    st = _scene(case, body, housing, [None] * 4).structure
    Kg, K = np.asarray(grounded.structure.K), np.asarray(st.K)
    n_sh, h = st.node("housing seat0"), housing.size
    body_dofs = np.r_[n_sh + h : K.shape[0]]
    keep = np.r_[np.arange(n_sh), body_dofs]
    np.testing.assert_array_equal(K[np.ix_(keep, keep)], Kg)
    assert not np.any(K[np.ix_(keep, np.arange(n_sh, n_sh + h))])


HOUSING = """
[housing]
width_mm = 160.0
height_mm = 120.0
wall_thickness_mm = 8.0
bore_diameter_mm = 26.0
mesh_size_mm = 20.0
element = "tet4"
youngs_modulus_GPa = {E}
density_kg_m3 = {rho}
cutoff_Hz = 5000.0
"""


def _case_file(tmp_path, extra=""):
    """The hybrid test case (its wheel body by absolute path) with ``extra`` tables appended."""
    text = (DATA / "hybrid-test-case.toml").read_text()
    text = text.replace('"hybrid-test-wheel.toml"', repr(str(DATA / "hybrid-test-wheel.toml")))
    path = tmp_path / f"c{abs(hash(extra))}.toml"
    path.write_text(text + extra)
    return path


def _table_box_housing(case):
    """The condensed box of ``HOUSING`` at E = 7 GPa placed in the scene (see
    :func:`_table_box_scene`)."""
    a, t, width, height = case.pair.center_distance, 0.008, 0.16, 0.12
    L = 0.08 + t
    off = np.array([a / 2 - width / 2, -height / 2, -L / 2])
    bores = tuple(Bore(w, (x - off[0], -off[1]), 0.013) for w in ("x-", "x+") for x in (0.0, a))
    f = 3 * t
    feet = tuple(Foot(xr, yr) for xr in ((0.0, f), (L - f, L))
                 for yr in ((0.0, f), (width - f, width)))
    box = HousingBox(L, width, height, t, bores=bores, feet=feet)
    ph = prepare_housing(mesh_box(box, 0.02, element=Tet4()),
                         fem_prep.Material(7e9, 0.3, 2700.0), 5000.0)
    return Housing.of(ph.condensed_housing(), rotation=R, offset=off)


def _table_box_scene(case, body, housing=None):
    """The hybrid pair of the case (jaxgear.io's default rigid pinion: a solid disc) on the box
    of ``HOUSING`` at E = 7 GPa, written out here (housing frame: x along the shafts, z up): its
    end walls' mid-planes at the bearings (±40 mm), centred across the two axes, a bore round
    each axis in both walls, feet of 3 walls; each shaft's bearings on its own bores' seats
    (x-, x+)."""
    return hybrid_pair(
        case.pair,
        case.mesh_model(flexible=(False, True)),
        case.scene.pinion_shaft,
        case.scene.gear_shaft,
        bodies=(None, body),
        masses=scene_masses(case),
        inertias=scene_inertias(case),
        material=Material(case.youngs_modulus, case.poisson_ratio, case.density),
        housing=_table_box_housing(case) if housing is None else housing,
        seats=[0, 2, 1, 3],
    )


@pytest.fixture(scope="module")
def soft_case(tmp_path_factory, fem_prep_cache):
    """The hybrid test case with ``HOUSING`` at E = 7 GPa (aluminium's density)."""
    return jio.load_case(_case_file(tmp_path_factory.mktemp("soft"),
                                    HOUSING.format(E=7.0, rho=2700.0)))


@pytest.fixture(scope="module")
def soft_box(soft_case):
    return _table_box_housing(soft_case)


@pytest.fixture(scope="module")
def soft_scene(soft_case, body, soft_box):
    return _table_box_scene(soft_case, body, soft_box)


@pytest.fixture(scope="module")
def grounded_case_scene(tmp_path_factory, body, fem_prep_cache):
    """The case's grounded hybrid pair (no [housing])."""
    case = jio.load_case(_case_file(tmp_path_factory.mktemp("grounded")))
    return jio.static_scene(case, bodies=(None, body))[0]


def test_a_hybrid_case_files_housing_is_the_box_round_its_shafts(
    tmp_path, body, soft_case, soft_scene, grounded_case_scene
):
    """``[housing]`` in a case with a condensed wheel: the case's scene (jaxgear.io's
    static_scene, the one ``jaxgear run``, ``sweep`` and ``modes`` build) equals the hybrid pair
    built here on the box the table describes, written out in the test (its end walls'
    mid-planes at the bearings, ±40 mm; centred across the two axes; a bore round each axis in
    both walls; feet of 3 walls; each shaft's bearings on the seats of its own bores, the
    condensed wheel's too); and as the housing grows stiff (E × 1000 of steel's) its natural
    frequencies below 5 kHz are the grounded hybrid pair's to 1e-3, while the soft box
    (E = 7 GPa) moves the first one by more than 5 %."""
    case = soft_case
    kw = case.hybrid_housing()
    assert kw["seats"] == [0, 2, 1, 3]  # x- wall's pinion bore, x+ wall's; the wheel's
    scene, _ = jio.static_scene(case, bodies=(None, body))
    ref = soft_scene
    for got, want in ((scene.structure.K, ref.structure.K), (scene.structure.M, ref.structure.M)):
        got, want = np.asarray(got), np.asarray(want)
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-9 * np.abs(want).max())
    f0 = _freqs(grounded_case_scene.structure, 5000.0)
    f_soft = _freqs(scene.structure, 5000.0)
    assert abs(f_soft[0] / f0[0] - 1) > 0.05
    stiff = jio.load_case(_case_file(tmp_path, HOUSING.format(E=210e3, rho=7800.0)))
    st = jio.static_scene(stiff, bodies=(None, body))[0].structure
    np.testing.assert_allclose(_freqs(st, math.inf)[: f0.size], f0, rtol=1e-3)


def test_the_condensed_wheels_seated_bearings_carry_the_mesh_force(soft_case, soft_box,
                                                                  soft_scene):
    """Static equilibrium in the soft box, every bearing seated (the condensed wheel's shaft
    meets its seats at its body frame's angle at θ = 0), the contact solved at θ = 0: the
    wheel's two bearings carry together, in the fixed frame, the normal mesh force
    T / r_b1 (spur; to 1e-3: the lever of a deflected contact), as the pinion's do; the four
    sum to zero (1e-6 of it); and the housing, a free body loaded only by its seats (its feet
    clamped), feels no net force: the seats' forces (K_h q on their translations, turned into
    the scene frame) sum to zero too (1e-6), which holds only if the wheel's bearings press on
    their seats along the fixed-frame direction of their load (a frame off by the body's
    angle, 5.1°, would leave 9 % of the mesh force)."""
    case, scene = soft_case, soft_scene
    res = jg.quasi_static(scene, case.modifications, case.torque, np.zeros(1))
    F = np.asarray(scene.bearing_forces(res.theta, res.x))[0]
    names = scene.structure.reaction_names
    total = {m: np.array([sum(f for k, f in zip(names, F, strict=True)
                              if k.startswith(m) and k.endswith(c)) for c in ("Fx", "Fy")])
             for m in ("pinion", "gear")}
    F_n = case.torque / case.pair.base_radii[0]
    for m in ("pinion", "gear"):
        np.testing.assert_allclose(np.linalg.norm(total[m]), F_n, rtol=1e-3)
    assert np.linalg.norm(total["pinion"] + total["gear"]) < 1e-6 * F_n
    h0 = scene.structure.node("housing seat0")
    q = np.asarray(res.x)[0, h0 : h0 + soft_box.size]
    on_seats = (np.asarray(soft_box.K) @ q)[: 6 * soft_box.n_seats].reshape(-1, 6)[:, :3]
    net = R @ on_seats.sum(axis=0)
    assert np.linalg.norm(net) < 1e-6 * F_n
    assert np.linalg.norm(on_seats[[1, 3]].sum(axis=0)) > 0.5 * F_n  # the wheel's seats loaded


def test_a_soft_box_lowers_every_hybrid_frequency(grounded_case_scene, soft_scene, soft_box):
    """The grounded hybrid pair is the housed one with the seats held (q = 0): a constraint,
    which by Rayleigh's theorem of constraint raises no natural frequency of the housed pair
    above the grounded one's: f_k(housed) <= f_k(grounded) for every k (asserted for those
    below 5 kHz); the soft box (E = 7 GPa) lowers the first one by more than 5 %, and a mode
    below 5 kHz lives mostly in the housing (kinetic energy share above 1/2, of a
    mass-normalised mode)."""
    st0, st = grounded_case_scene.structure, soft_scene.structure
    f0 = _freqs(st0, 5000.0)
    K, M = np.asarray(st.K), np.asarray(st.M)
    lam, phi = sla.eigh(K, M)
    f = np.sqrt(np.abs(lam)) / (2 * math.pi)
    elastic = f > 1.0
    f, phi = f[elastic], phi[:, elastic]
    assert np.all(f[: f0.size] <= f0 * (1 + 1e-9))
    assert f[0] < 0.95 * f0[0]
    h0 = st.node("housing seat0")
    hh = np.arange(h0, h0 + soft_box.size)
    share = np.einsum("im,ij,jm->m", phi[hh], M[np.ix_(hh, hh)], phi[hh])
    assert share[f < 5000.0].max() > 0.5


def scene_masses(case):
    """The rigid pinion's disc mass (kg) of the case's scene (jaxgear.io's default: a solid
    disc of the tip radius and the face width); the wheel's is its body's."""
    r, b = case.pair.tip_radii[0], case.pair.pinion.face_width
    return (case.density * math.pi * r * r * b, None)


def scene_inertias(case):
    """The rigid pinion's (diametral, polar) inertias (kg m²) of a solid disc."""
    r, b = case.pair.tip_radii[0], case.pair.pinion.face_width
    m = case.density * math.pi * r * r * b
    ip = 0.5 * m * r * r
    return ((ip / 2 + m * b * b / 12, ip), (1.0, 1.0))


def test_a_hybrid_train_case_files_housing_seats_the_rigid_gears_shafts(tmp_path, body):
    """``[housing]`` in the small idler train whose idler is a condensed body: the box's bores
    round the three shafts in both walls (seats x- then x+, input, idler, output each); every
    shaft's bearings on the seats of its own bores, the condensed idler's too: in the case's
    hybrid train (jaxgear.io's static_train) every seat has stiffness terms with the rest of
    the structure (its bearing), no seat has a mass term; the structure is the grounded
    train's plus the housing's coordinates."""
    text = (DATA / "hybrid-test-train.toml").read_text()
    text = text.replace('"hybrid-test-wheel.toml"', repr(str(DATA / "hybrid-test-wheel.toml")))
    housing = HOUSING.format(E=7.0, rho=2700.0).replace("120.0", "140.0")
    (tmp_path / "t.toml").write_text(text + housing)
    (tmp_path / "g.toml").write_text(text)
    case = jio.load_case(tmp_path / "t.toml")
    kw = case.hybrid_housing()
    assert kw["seats"] == [0, 3, 1, 4, 2, 5]
    bodies = (None, body, None)
    st = case.static_train(bodies=bodies).structure
    g = jio.load_case(tmp_path / "g.toml").static_train(bodies=bodies).structure
    assert st.size == g.size + kw["housing"].size
    h0 = st.node("housing seat0")
    outside = np.r_[0:h0, h0 + kw["housing"].size : st.size]
    K = np.asarray(st.K)
    for k in range(6):  # each seat's stiffness terms with the rest of the structure
        seat = np.arange(st.node(f"housing seat{k}"), st.node(f"housing seat{k}") + 6)
        assert np.any(K[np.ix_(outside, seat)]), k
    assert not np.any(np.asarray(st.M)[np.ix_(outside, np.arange(h0, h0 + kw["housing"].size))])


@pytest.mark.slow
def test_jaxgear_run_of_a_housed_hybrid_case(tmp_path, body):
    """``jaxgear run`` on the hybrid pair in the soft box (about a minute): its quasi-static TE
    is that of the hybrid pair built here on the box written out (jaxgear.quasi_static, the
    case's positions and modifications; to 1e-9), and its mean bearing forces balance the mesh:
    each shaft's two bearings (in the housing's seats, the condensed wheel's too) carry together
    the normal mesh force T / r_b1 (spur; to 1e-3, measured 1.6e-4: the mean over the mesh
    period of a deflected contact), all four sum to zero (to 1e-5 of it); the summary's
    ``housing`` says where each bearing sits."""
    path = _case_file(tmp_path, HOUSING.format(E=7.0, rho=2700.0))
    case = jio.load_case(path)
    assert main(["run", str(path), "--out", str(tmp_path / "run"), "--quiet"]) == 0
    q = json.loads((tmp_path / "run" / "summary.json").read_text())["quasi_static_scene"]
    res = jg.quasi_static(_table_box_scene(case, body), case.modifications, case.torque,
                          positions_per_pitch=case.positions_per_pitch)
    np.testing.assert_allclose(q["exact"]["te_mean_m"], float(res.te_mean), rtol=1e-9)
    forces = q["exact"]["bearing_forces_mean_N"]
    total = {m: np.array([sum(v for k, v in forces.items() if k.startswith(m) and k.endswith(c))
                          for c in ("Fx", "Fy")]) for m in ("pinion", "gear")}
    F_n = case.torque / case.pair.base_radii[0]
    np.testing.assert_allclose(np.linalg.norm(total["pinion"]), F_n, rtol=1e-3)
    np.testing.assert_allclose(np.linalg.norm(total["gear"]), F_n, rtol=1e-3)
    assert np.linalg.norm(total["pinion"] + total["gear"]) < 1e-5 * F_n
    seats = [(b["shaft"], b["position_mm"], b["seat"]) for b in q["housing"]["bearings"]]
    assert seats == [("pinion", 0.0, "seat0"), ("pinion", 80.0, "seat2"), ("gear", 0.0, "seat1"),
                     ("gear", 80.0, "seat3")]


@pytest.mark.slow
def test_jaxgear_modes_gives_the_housings_share_of_each_hybrid_mode(tmp_path, fem_prep_cache):
    """``jaxgear modes`` on the hybrid pair in the soft box (E = 7 GPa) and in a box stiffened
    × 1000 from steel's: each of the 20 listed modes has its housing_kinetic_energy_share (of a
    mass-normalised mode, in [0, 1]); in the soft box a mode lives mostly in the housing (a
    share above 1/2), in the stiff one the housing's seats hardly move in any mode below its
    cut-off (every share below 1e-3: the seated bearings' deflection is 1e-3 of the shafts';
    about 1 min)."""
    shares = {}
    for E, rho in ((7.0, 2700.0), (210e3, 7800.0)):
        path = _case_file(tmp_path, HOUSING.format(E=E, rho=rho))
        out = tmp_path / f"modes{E:g}"
        assert main(["modes", str(path), "--out", str(out)]) == 0
        rows = json.loads((out / "modes.json").read_text())["modes"]
        assert len(rows) == 20
        elastic = [r for r in rows if r["type"] != "rigid"]
        shares[E] = np.array([r["housing_kinetic_energy_share"] for r in elastic])
        assert np.all(shares[E] > -1e-12) and np.all(shares[E] < 1 + 1e-9)
    assert shares[7.0].max() > 0.5
    assert shares[210e3].max() < 1e-3


def test_a_hybrid_case_with_whine_and_housing_is_a_one_line_error(tmp_path):
    """``[whine]`` beside condensed bodies and a ``[housing]``: the harmonic balance of a hybrid
    pair has no housing yet; one line naming ``[whine]``, when the case is loaded (before any
    body or housing is built). Without the housing the case loads (docs/whine.md, "Hybrid
    model")."""
    whine = "\n[whine]\nspeed_min_rad_s = 100.0\nspeed_max_rad_s = 200.0\nspeeds = 3\n"
    with pytest.raises(ValueError, match=r"^\[whine\].*condensed bodies with a \[housing\]") as err:
        jio.load_case(_case_file(tmp_path, HOUSING.format(E=70.0, rho=2700.0) + whine))
    assert "\n" not in str(err.value)
    assert jio.load_case(_case_file(tmp_path, whine)).scene.hybrid


@pytest.mark.slow
def test_hybrid_train_on_a_stiffening_housing_tends_to_the_grounded_train(fem_prep_cache):
    """The small idler train whose idler is a condensed body: the input's and the output's
    shafts in a box housing (bores round their axes), the idler's on the ground; × 10 on the
    housing's Young's modulus divides the difference of the structure's natural frequencies
    below 5 kHz to the grounded hybrid train by 10 (measured 0.34, 0.018, 0.0016 on steel, at
    E × 10, 100: the softest not yet in the asymptotic range; asserted <= / 8; 10 s)."""
    case = jio.load_case(DATA / "hybrid-test-train.toml")
    bodies = jio.load_bodies(case.scene)
    grounded = case.hybrid_train(bodies).structure
    centres = np.asarray(case.layout().centres)
    width = height = 0.16
    L = 0.088
    off = np.array([-0.05, -0.06, -L / 2])
    bores = tuple(
        Bore(w, (centres[g, 0] - off[0], centres[g, 1] - off[1]), 0.012)
        for w in ("x-", "x+")
        for g in (0, 2)
    )
    f = 0.025
    feet = tuple(Foot((x0, x0 + f), (y0, y0 + f)) for x0 in (0.0, L - f) for y0 in (0.0, width - f))
    box = HousingBox(L, width, height, 0.008, bores=bores, feet=feet)
    mesh = mesh_box(box, 0.03, element=Tet4())
    seats = [0, 2, None, None, 1, 3]  # input, idler (grounded), output; x- then x+ wall
    f0 = _freqs(grounded, 5000.0)
    errs = []
    for scale in (1.0, 1e1, 1e2):
        ph = prepare_housing(mesh, fem_prep.Material(210e9 * scale, 0.3, 7800.0), 5000.0)
        housing = Housing.of(ph.condensed_housing(), rotation=R, offset=off)
        st = case.hybrid_train(bodies, housing=housing, seats=seats).structure
        assert st.size == grounded.size + housing.size
        errs.append(np.abs(_freqs(st, math.inf)[: f0.size] / f0 - 1).max())
    errs = np.array(errs)
    assert errs[0] > 1e-3 and np.all(errs[1:] < errs[:-1] / 8)
