"""The lumped 3D scene on a flexible housing (jaxgear.scenes.Housing): the bearings join the shafts
to the condensed housing's seats. Evidence against references written here: the full,
uncondensed housing FE with the shafts and bearings assembled separately (modes, statics), and
the grounded scene as the housing grows stiff and light."""

import math

import numpy as np
import pytest
import scipy.linalg as sla
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from _housing import HOUSING_BOX

import fem_prep
import jaxgear.io as jio
from fem_prep.housing import Bore, Foot, HousingBox, Tet4, mesh_box, prepare_housing
from jaxgear.dynamics import (
    HarmonicBalance,
    Newmark,
    Outputs,
    SteadyState,
    dynamic_model,
    simulate,
    whine_response,
)
from jaxgear.scenes import Housing, lumped_pair, shaft_matrices

# housing frame -> scene frame: the shafts' axis (scene z) is the box's length (housing x), the
# shafts' plane (scene x) its width (housing y), scene y its height (housing z)
R = np.array([[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]])
MASSES = (1.0, 2.5)
INERTIAS = ((1e-3, 2e-3), (4e-3, 8e-3))


def _case():
    return jio.load_case("accessory-spur").replace(slices=4)


def _placed_box(case, t=0.01, width=0.25, height=0.16):
    """A box whose end walls' mid-planes hold the shafts' bearings (at ±50 mm of the gears),
    bores round both shafts in both end walls, four feet at the bottom corners; and its offset
    (m) in the scene frame."""
    a = case.pair.center_distance
    L = 0.1 + t
    off = np.array([-(width / 2 - a / 2), -height / 2, -L / 2])
    bores = tuple(Bore(w, (x - off[0], height / 2), 0.025) for w in ("x-", "x+") for x in (0.0, a))
    f = 0.03
    feet = tuple(Foot((x0, x0 + f), (y0, y0 + f)) for x0 in (0.0, L - f) for y0 in (0.0, width - f))
    return HousingBox(L, width, height, t, bores=bores, feet=feet), off


def _prepared(material, cutoff_hz, size=0.04):
    case = _case()
    box, off = _placed_box(case)
    ph = prepare_housing(mesh_box(box, size, element=Tet4()), material, cutoff_hz)
    return case, ph, off


def _scene(case, housing=None):
    s = case.scene
    return lumped_pair(
        case.pair,
        case.mesh_model(),
        s.pinion_shaft,
        s.gear_shaft,
        masses=MASSES,
        inertias=INERTIAS,
        housing=housing,
    )


def _skew(a):
    return np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])


def _reference_assembly(case, ph, off):
    """Shafts (fem shaft matrices), gear bodies and bearings assembled here on the FULL housing
    FE (its clamped, seat-coupled K and M, uncondensed): sparse (K, M), the shafts' size, the
    housing's offset, and each bearing's (shaft DOFs, seat DOFs, G, K_b)."""
    s = case.scene
    E, nu, rho = case.youngs_modulus, case.poisson_ratio, case.density
    G_mod = E / (2 * (1 + nu))
    a = case.pair.center_distance
    shafts = []
    for spec, m, (idia, ipol) in zip((s.pinion_shaft, s.gear_shaft), MASSES, INERTIAS):
        sm = shaft_matrices(spec, E, G_mod, rho)
        Ms = sm.M.copy()
        g = 6 * sm.gear_node
        Ms[g : g + 3, g : g + 3] += m * np.eye(3)
        Ms[g + 3, g + 3] += idia
        Ms[g + 4, g + 4] += idia
        Ms[g + 5, g + 5] += ipol
        shafts.append((spec, sm, Ms))
    ns = sum(sm.K.shape[0] for _, sm, _ in shafts)
    nh = ph.K.shape[0]
    K = np.zeros((ns + nh, ns + nh))  # the shafts' and the bearings' entries (dense, few)
    M = np.zeros((ns, ns))
    first = 0
    seats = off + np.array([s_.centre for s_ in ph.mesh.seats]) @ R.T  # scene frame
    links = []
    for i, (spec, sm, Ms) in enumerate(shafts):
        n = sm.K.shape[0]
        K[first : first + n, first : first + n] = sm.K
        M[first : first + n, first : first + n] = Ms
        for b in spec.bearings:
            p = np.array([i * a, 0.0, b.z - spec.gear_z])
            k = int(np.argmin(np.linalg.norm(seats - p, axis=1)))
            u = first + 6 * int(np.argmin(np.abs(sm.nodes - b.z))) + np.arange(6)
            q = ns + ph.seat_dofs[k]
            G = np.zeros((6, 6))
            G[:3, :3] = G[3:, 3:] = R
            G[:3, 3:] = -_skew(p - seats[k]) @ R
            B = np.hstack([np.eye(6), -G])  # relative displacement [u; q] -> d
            kb = b.stiffness_matrix()
            idx = np.concatenate([u, q])
            K[np.ix_(idx, idx)] += B.T @ kb @ B
            links.append((u, q, G, kb, p, seats[k], k))
        first += n
    K = sp.csc_matrix(K) + sp.block_diag([sp.csr_matrix((ns, ns)), ph.K]).tocsc()
    M = sp.block_diag([sp.csr_matrix(M), ph.M]).tocsc()
    return K.tocsc(), M.tocsc(), ns, links


def test_coupled_modes_match_the_full_housing_below_the_cutoff():
    """A soft housing (E = 7 GPa, ρ = 2700 kg/m³: several housing modes low) condensed to
    f_c = 2 kHz: the coupled scene's natural frequencies below f_c / 1.5 (the band the default
    cut-off rule serves: f_c = 1.5 x the highest mesh order) within 1 % of the full,
    uncondensed housing FE with the same shafts and bearings assembled here (sparse
    shift-invert eigenvalues; measured 0.50 %, 8 modes). Just below f_c a coupled mode
    that leans on the dropped housing modes is 8 % high: the truncation the rule leaves out."""
    cutoff = 2000.0
    case, ph, off = _prepared(fem_prep.Material(7e9, 0.33, 2700.0), cutoff)
    housing = Housing.of(ph.condensed_housing(), rotation=R, offset=off)
    assert len(housing.modes_hz) >= 2
    scene = _scene(case, housing)
    lam = sla.eigvalsh(np.asarray(scene.structure.K), np.asarray(scene.structure.M))
    f = np.sqrt(np.abs(lam)) / (2 * math.pi)
    got = f[(f > 1.0) & (f < cutoff / 1.5)]
    K, M, _, _ = _reference_assembly(case, ph, off)
    # two free shaft rotations: shift below zero
    mu = spla.eigsh(K, k=len(got) + 8, M=M, sigma=-((2 * math.pi * 5.0) ** 2), which="LM")[0]
    ref = np.sort(np.sqrt(np.abs(mu)) / (2 * math.pi))
    ref = ref[ref > 1.0][: len(got)]
    assert len(got) >= 6
    np.testing.assert_allclose(got, ref, rtol=0.01)
    # and the condensation is what the agreement needs: the grounded scene is far off
    grounded = sla.eigvalsh(
        np.asarray(_scene(case).structure.K), np.asarray(_scene(case).structure.M)
    )
    g = np.sqrt(np.abs(grounded)) / (2 * math.pi)
    assert abs(g[g > 1.0][0] / got[0] - 1) > 0.05


def test_bearing_loads_give_the_housing_static_seat_deflection():
    """Radial forces on the gear nodes of the coupled scene: each seat's deflection in the
    coupled static solution equals the full housing FE's static deflection under the forces
    the bearings transmit (their force rows, moved to the seat centres here), to 1e-6."""
    case, ph, off = _prepared(fem_prep.Material(7e9, 0.33, 2700.0), 2000.0)
    housing = Housing.of(ph.condensed_housing(), rotation=R, offset=off)
    scene = _scene(case, housing)
    st = scene.structure
    K = np.asarray(st.K)
    f = np.zeros(st.size)
    f[st.node("pinion") + 0] = 3e3  # N along x
    f[st.node("pinion") + 1] = -1e3
    f[st.node("gear") + 1] = 2e3
    f[st.node("gear") + 2] = 5e2  # axial
    x = np.linalg.lstsq(K, f, rcond=None)[0]  # the shafts' free rotations: any solution
    np.testing.assert_allclose(K @ x, f, atol=1e-6 * np.abs(f).max())
    F = (np.asarray(st.reaction) @ x).reshape(-1)  # bearing forces (N), in row order
    # the rows: per bearing, its non-zero translational stiffness rows (x, y, then z if axial)
    _, _, _, links = _reference_assembly(case, ph, off)
    load = np.zeros(ph.K.shape[0])
    row = 0
    for _, q, _, kb, p, c, k in links:
        Fb = np.zeros(3)
        for d in range(3):
            if np.any(kb[d] != 0):
                Fb[d] = F[row]
                row += 1
        # the bearing pushes the housing with the force it transmits (its reaction on the shaft
        # is -Fb): force Fb and moment (p - c) x Fb at the seat, in the housing frame
        load[ph.seat_dofs[k]] += np.concatenate([R.T @ Fb, R.T @ np.cross(p - c, Fb)])
    assert row == F.size
    u = spla.spsolve(ph.K.tocsc(), load)
    n = st.node("housing seat0")
    seats = ph.seat_dofs.ravel()
    got = x[n : n + seats.size]
    np.testing.assert_allclose(got, u[seats], rtol=0, atol=1e-6 * np.abs(u[seats]).max())
    assert np.abs(u[seats]).max() > 1e-7  # the housing does deflect (m)


def test_stiff_housing_structure_tends_to_the_grounded_one():
    """The housing's Young's modulus x 10 per step (steel's density: a stiff housing does not
    move, so its mass drops out): the coupled structure's natural frequencies below 5 kHz tend
    to the grounded structure's, the difference falling as the housing's compliance (measured
    x 0.100 per step; asserted <= x 0.125)."""
    case = _case()
    g = _scene(case).structure
    f0 = np.sqrt(np.abs(sla.eigvalsh(np.asarray(g.K), np.asarray(g.M)))) / (2 * math.pi)
    f0 = f0[(f0 > 1.0) & (f0 < 5000.0)]
    errs = []
    for scale in (1e1, 1e2, 1e3):
        _, ph, off = _prepared(fem_prep.Material(210e9 * scale, 0.3, 7800.0), 5000.0)
        st = _scene(case, Housing.of(ph.condensed_housing(), rotation=R, offset=off)).structure
        f = np.sqrt(np.abs(sla.eigvalsh(np.asarray(st.K), np.asarray(st.M)))) / (2 * math.pi)
        f = f[f > 1.0][: f0.size]
        errs.append(np.abs(f / f0 - 1).max())
    errs = np.array(errs)
    assert np.all(errs[1:] < errs[:-1] / 8) and errs[-1] < 1e-4


@pytest.mark.slow
def test_stiff_housing_dynamics_tend_to_the_grounded_ones():
    """As above through the engine (16 s): the coupled pair's mesh-averaged modes below 5 kHz
    (:class:`~jaxgear.dynamics.DynamicModel`) and its order-1 mesh force by the harmonic
    balance (:func:`~jaxgear.dynamics.whine_response`, a 2 % loss factor on the housing) tend
    to the grounded pair's (measured differences 6.2e-3, 6.2e-4, 6.2e-5 and 5.3e-3, 5.3e-4,
    5.3e-5 at E x 10, 100, 1000); at E x 1000 Newmark's mesh force over the kept window
    (``simulate``) is the grounded pair's to 1e-3."""
    case = _case()
    grounded = dynamic_model(_scene(case), case.modifications, case.torque)
    f0 = np.asarray(grounded.modes.frequency)
    f0 = f0[(f0 > 1.0) & (f0 < 5000.0)]
    speed = 300.0
    w0 = whine_response(grounded, speed, HarmonicBalance(8), positions=64)
    F0 = complex(w0.mesh_force[0, 1, 0])
    errs_f, errs_w = [], []
    for scale in (1e1, 1e2, 1e3):
        _, ph, off = _prepared(fem_prep.Material(210e9 * scale, 0.3, 7800.0), 5000.0)
        housing = Housing.of(ph.condensed_housing(), loss_factor=0.02, rotation=R, offset=off)
        model = dynamic_model(_scene(case, housing), case.modifications, case.torque)
        f = np.asarray(model.modes.frequency)
        f = f[(f > 1.0)][: f0.size]
        errs_f.append(np.abs(f / f0 - 1).max())
        w = whine_response(model, speed, HarmonicBalance(8), positions=64)
        errs_w.append(abs(complex(w.mesh_force[0, 1, 0]) / F0 - 1))
        if scale == 1e3:  # the time domain takes the housing too, and tends alike
            r = simulate(model, speed, integrator=Newmark(64), window=SteadyState(40, 2))
            r0 = simulate(grounded, speed, integrator=Newmark(64), window=SteadyState(40, 2))
            np.testing.assert_allclose(
                np.asarray(r.mesh_force), np.asarray(r0.mesh_force), rtol=1e-3
            )
    errs_f, errs_w = np.array(errs_f), np.array(errs_w)
    assert np.all(errs_f[1:] < errs_f[:-1] / 8) and errs_f[-1] < 1e-4
    assert np.all(errs_w[1:] < errs_w[:-1] / 8) and errs_w[-1] < 1e-4


@pytest.mark.slow
def test_soft_housing_whine_against_newmark():
    """The harmonic balance of the coupled model against Newmark on the same model, where the
    housing matters (each order within 1 % and 1°). The pair on a soft
    box (E = 7 GPa, Tet4 40 mm, fixed-interface modes to 6 kHz, the first at 1.38 kHz, loss
    factor 0.02) at 95 rad/s (mesh 680 Hz; no contact loss, ``nonlinearity`` 1e-16): the
    housing moves the mesh force's orders 1-3 by +48, −69, +61 % from the grounded pair's,
    and orders 1-3 of the TE, the mesh force, the largest bearing force component and the
    first seat's largest translation are Newmark's (256 steps per period, 60 periods, 4 kept)
    within 1 % and 1° (measured 0.89 % and 0.57°, the seat's orders 2 and 3 the farthest).
    About 55 s on the loaded 2-core host (the whine's compilation most of it)."""
    case, ph, off = _prepared(fem_prep.Material(7e9, 0.33, 2700.0), 6000.0)
    housing = Housing.of(ph.condensed_housing(), loss_factor=0.02, rotation=R, offset=off)
    model = dynamic_model(_scene(case, housing), case.modifications, case.torque)
    grounded = dynamic_model(_scene(case), case.modifications, case.torque)
    speed = 95.0
    w = whine_response(model, speed, HarmonicBalance(32), positions=256)
    w0 = whine_response(grounded, speed, HarmonicBalance(32), positions=256)
    assert not bool(w.contact_loss[0, 0]) and float(w.nonlinearity[0, 0]) < 1e-3
    moved = np.abs(np.asarray(w.mesh_force[0, 1:4, 0]) / np.asarray(w0.mesh_force[0, 1:4, 0]))
    assert np.all(np.abs(moved - 1) > 0.3), moved  # the housing is in the response
    r = simulate(model, speed, integrator=Newmark(256), window=SteadyState(60, 4),
                 outputs=Outputs(states=True))
    assert float(r.contact_loss) == 0.0
    t = np.asarray(r.time)
    wf = 2 * math.pi * speed / float(model.mesh_period_angle())

    def orders(x):  # orders 1-3 of Newmark's kept record (whole mesh periods)
        return np.array([2 * np.mean(np.asarray(x) * np.exp(-1j * h * wf * t)) for h in (1, 2, 3)])

    bf = np.asarray(w.bearing_force)[0, 1:4]
    j = int(np.argmax(np.abs(bf[0])))
    seat = model.scene.structure.node("housing seat0")
    X = np.asarray(w.coordinates)[0, 1:4, seat : seat + 3]
    k = int(np.argmax(np.abs(X[0])))
    pairs = {
        "TE": (np.asarray(w.transmission_error)[0, 1:4, 0], r.transmission_error),
        "mesh force": (np.asarray(w.mesh_force)[0, 1:4, 0], r.mesh_force),
        "bearing force": (bf[:, j], np.asarray(r.bearing_force)[:, j]),
        "seat translation": (X[:, k], np.asarray(r.states)[:, seat + k]),
    }
    for name, (got, record) in pairs.items():
        ref = orders(record)
        np.testing.assert_allclose(np.abs(got) / np.abs(ref), 1.0, atol=0.01, err_msg=name)
        np.testing.assert_allclose(np.degrees(np.angle(got / ref)), 0.0, atol=1.0, err_msg=name)


def test_housing_bad_input_one_line():
    case, ph, off = _prepared(fem_prep.Material(7e9, 0.33, 2700.0), 2000.0)
    ch = ph.condensed_housing()
    with pytest.raises(ValueError, match="loss_factor = -0.1"):
        Housing.of(ch, loss_factor=-0.1)
    with pytest.raises(ValueError, match="rotation"):
        Housing.of(ch, rotation=np.diag([1.0, 1.0, -1.0]))
    with pytest.raises(ValueError, match="offset"):
        Housing.of(ch, offset=(0.0, 1.0))
    h = Housing.of(ch, rotation=R, offset=off)
    s = case.scene
    with pytest.raises(ValueError, match=r"seats\[1\] = 9"):
        lumped_pair(
            case.pair,
            case.mesh_model(),
            s.pinion_shaft,
            s.gear_shaft,
            masses=MASSES,
            inertias=INERTIAS,
            housing=h,
            seats=(0, 9, 1, 3),
        )


# -------------------------------------------------------------------------------------------
# the [housing] case table

_TABLE = HOUSING_BOX + """cutoff_Hz = 2000.0
loss_factor = 0.02
"""


def _case_with(tmp_path, table=_TABLE, name="accessory-spur", cut_scene=False):
    text = jio.embedded_case_text(name)
    if cut_scene:
        text = text[: text.index("[scene]")]
    path = tmp_path / "case.toml"
    path.write_text(text + table)
    return jio.load_case(path)


def test_case_housing_seats_hold_the_bearings(tmp_path):
    """The box of ``[housing]`` round the pair: its end walls' mid-planes at the outermost
    bearings (±50 mm of the gears), a seat on each shaft's axis in each wall, so that every
    bearing sits at its seat's centre; the case's scene carries the housing (its part, its
    seats' nodes, its coordinates after the shafts')."""
    case = _case_with(tmp_path)
    a = case.pair.center_distance
    s = case.scene
    shafts = (s.pinion_shaft, s.gear_shaft)
    h = case.build_housing(shafts, [(0.0, 0.0, 0.0), (a, 0.0, 0.0)], [0.05, 0.05])
    want = {(x, 0.0, z) for x in (0.0, a) for z in (-0.05, 0.05)}
    got = np.array(h.seat_positions)
    assert len(got) == 4
    for p in want:
        assert np.min(np.linalg.norm(got - np.array(p), axis=1)) < 1e-12
    base = jio.static_scene(case, slices=4)[0].base
    st = base.structure
    assert st.part_names[-1] == "housing"
    assert st.size == 60 + h.size and st.node("housing seat0") == 60
    np.testing.assert_allclose(np.asarray(st.M)[60:, 60:], np.asarray(h.M))


@pytest.mark.parametrize(
    "table, match",
    [
        (_TABLE.replace("cutoff_Hz = 2000.0", ""), "cutoff_Hz"),
        (_TABLE.replace("wall_thickness_mm = 10.0", "wall_thickness_mm = -1.0"), "-1"),
        (_TABLE + "colour = 1\n", "colour"),
        (_TABLE.replace('"tet4"', '"hex8"'), "hex8"),
        (_TABLE + "loss_factor_x = 0.1\n", "loss_factor_x"),
        (_TABLE.replace("loss_factor = 0.02", "loss_factor = 3.0"), r"loss_factor.*\[0, 1\]"),
        (_TABLE + 'mesh_file = "nowhere.msh"\n', "wall|mesh_file"),
        (_TABLE.replace("width_mm = 250.0", "width_mm = 60.0"),
         r"width_mm = 60: the housed axes span 99\.45 mm along scene x .*allowed >= 169\.5 mm"),
    ],
)
def test_housing_table_errors_one_line(tmp_path, table, match):
    with pytest.raises(ValueError, match=match) as err:
        case = _case_with(tmp_path, table)
        jio.static_scene(case, slices=4)  # the box's fit is checked when it is built
    assert "\n" not in str(err.value)


def test_housing_needs_a_lumped_scene(tmp_path):
    with pytest.raises(ValueError, match="lumped3d") as err:
        _case_with(tmp_path, cut_scene=True)
    assert "\n" not in str(err.value)


def test_train_on_a_stiffening_housing_tends_to_the_grounded_train(tmp_path):
    """The ``two-stage`` train (three shafts, six bearings) with a ``[housing]`` box: its
    structure's natural frequencies below 5 kHz tend to the grounded train's as the housing's
    Young's modulus grows (x 10: the difference / 10; measured 2.6e-3, 2.5e-4 at 100 and
    1000 x steel)."""
    path = tmp_path / "train.toml"
    base = jio.embedded_case_text("two-stage")
    table = """
[housing]
width_mm = 400.0
height_mm = 250.0
wall_thickness_mm = 12.0
mesh_size_mm = 80.0
element = "tet4"
cutoff_Hz = 5000.0
youngs_modulus_GPa = {E}
"""

    def freqs(structure):
        lam = sla.eigvalsh(np.asarray(structure.K), np.asarray(structure.M))
        f = np.sqrt(np.abs(lam)) / (2 * math.pi)
        return f[f > 1.0]

    grounded = jio.load_case("two-stage").lumped_train(slices=4).structure
    f0 = freqs(grounded)
    f0 = f0[f0 < 5000.0]
    errs = []
    for E in (2.1e4, 2.1e5):
        path.write_text(base + table.format(E=E))
        st = jio.load_case(path).lumped_train(slices=4).structure
        assert st.size == grounded.size + 6 * 6 and st.part_names[-1] == "housing"
        errs.append(np.abs(freqs(st)[: f0.size] / f0 - 1).max())
    assert errs[1] < errs[0] / 8 and errs[1] < 1e-3


def test_case_mesh_file_gives_the_boxs_housing(tmp_path, monkeypatch):
    """``[housing] mesh_file`` (a gmsh ``.msh`` in mm, its ``[[housing.seats]]``,
    ``[[housing.feet]]`` and ``offset_mm``) gives the housing the parametric box of the same
    case gives when that box's own mesh is the file: the same condensed modes (to 1e-8) and
    the case's scene the same M and K (to 1e-8 of their largest). The box is gmsh's (round
    bores: its seats are the same facets whichever of the two seat tolerances reads them)."""
    pytest.importorskip("gmsh")
    meshio = pytest.importorskip("meshio")
    monkeypatch.setenv("FEM_PREP_CACHE", str(tmp_path / "cache"))
    table = _TABLE.replace('element = "tet4"', 'element = "tet4"\nmesher = "gmsh"')
    box_case = _case_with(tmp_path, table)
    body = box_case.housing_body()
    hm = body.mesh
    path = tmp_path / "housing.msh"
    meshio.write(path, meshio.Mesh(hm.mesh.p.T * 1e3, [("tetra", hm.mesh.t.T)]),
                 file_format="gmsh22", binary=False)
    lines = [f'mesh_file = "{path.name}"', 'mesh_unit = "mm"',
             f"offset_mm = {[float(x) * 1e3 for x in body.offset]}"]
    for s in hm.seats:
        lines += ["[[housing.seats]]", f"centre_mm = {[float(x) * 1e3 for x in s.centre]}",
                  f"axis = {[float(x) for x in s.axis]}", f"diameter_mm = {2e3 * s.radius}",
                  f"width_mm = {1e3 * s.width}", f'name = "{s.name}"']
    for f in hm.feet:
        lines += ["[[housing.feet]]", f"x_mm = {[float(x) * 1e3 for x in f.x_range]}",
                  f"y_mm = {[float(x) * 1e3 for x in f.y_range]}"]
    keep = [ln for ln in table.splitlines()
            if not ln.startswith(("width_mm", "height_mm", "wall_thickness_mm",
                                  "bore_diameter_mm", "mesh_size_mm", "mesher"))]
    file_case = _case_with(tmp_path, "\n".join(keep) + "\n" + "\n".join(lines) + "\n")
    assert file_case.housing.mesh_file == str(path)
    got = file_case.housing_body()
    for s, t in zip(hm.seats, got.mesh.seats):
        np.testing.assert_array_equal(np.sort(got.mesh.seat_nodes(t)), np.sort(hm.seat_nodes(s)))
    np.testing.assert_allclose(got.condensed.modes_hz, body.condensed.modes_hz, rtol=1e-8)
    a = jio.static_scene(box_case, slices=4)[0].base.structure
    b = jio.static_scene(file_case, slices=4)[0].base.structure
    for name in ("M", "K"):
        x, y = np.asarray(getattr(a, name)), np.asarray(getattr(b, name))
        np.testing.assert_allclose(y, x, rtol=0, atol=1e-8 * np.abs(x).max(), err_msg=name)
