"""``jaxgear run`` with ``[housing]`` and ``[whine]``: the housing's
outputs from the coupled whine response (docs/housing.md, "In jaxgear run").

References: the one path (a housing's coordinates to its skin velocity and ERP) against a NumPy
evaluation of the recovery and the skin operator; the run's ERP and point velocities against
the *full* (uncondensed) housing FE model solved at each order's frequency under the loads the
bearings put on its seats in the coupled response (the housing rows of the coupled equations,
which the mesh's time-varying stiffness does not enter): within the condensation's error below
its band; the files complete; the one-line errors of the points' keys."""

from __future__ import annotations

import csv
import dataclasses
import json
import math

import numpy as np
import pytest
import scipy.sparse.linalg as spla
from _housing import HOUSING_TABLE, WHINE_TABLE, housed_case, housed_train

import fem_prep
import jaxgear.io as jio
from fem_prep.acoustics import AIR
from fem_prep.housing import (
    Bore,
    Foot,
    HousingBox,
    Tet4,
    condensed_housing,
    mesh_box,
    outer_surface,
    prepare_housing,
)
from jaxgear.acoustics import housing_acoustics, housing_response, housing_vibration

TABLE, WHINE = HOUSING_TABLE, WHINE_TABLE


def _case(tmp_path, table=TABLE, whine="", damping=None):
    return housed_case(tmp_path, table, whine, damping)


# -------------------------------------------------------------------------------------------
# the one path: condensed coordinates -> skin velocity and ERP


def test_housing_vibration_is_the_recovery_on_the_skin():
    """v_n = iω N (recovery q) and ERP = ½ρc ∫|v_n|² dS (the skin's square_operator) by NumPy
    on the full field, for random
    coordinates; housing_response's result is housing_vibration of its own coordinates."""
    box = HousingBox(0.2, 0.15, 0.12, 0.01, bores=(Bore("x-", (0.07, 0.06), 0.02),),
                     feet=(Foot((0.0, 0.03), (0.0, 0.03)), Foot((0.17, 0.2), (0.12, 0.15))))
    mesh = mesh_box(box, 0.05, element=Tet4())  # (Tet4: half a second)
    ch = condensed_housing(mesh, fem_prep.Material(70e9, 0.33, 2700.0), 6000.0, cache=False)
    s = outer_surface(mesh, {"top": (0.1, 0.07, 0.12)})
    ac = housing_acoustics(ch, s, loss_factor=0.02)
    rng = np.random.default_rng(1)
    n_c = ch.K.shape[0]
    q = rng.normal(size=(3, n_c)) + 1j * rng.normal(size=(3, n_c))
    f = np.array([100.0, 900.0, 2500.0])
    r = housing_vibration(ac, q, f)
    u = ch.recovery @ q.T  # (n_full, 3)
    vn = (2j * math.pi * f) * (s.normal_operator @ u)  # (F, 3)
    vp = (2j * math.pi * f) * (s.point_operator @ u)
    vs = (2j * math.pi * f) * (s.square_operator @ u)  # ‖S v‖² = ∫ |v_n|² dS
    ref = 0.5 * AIR.density * AIR.sound_speed * np.sum(np.abs(vs) ** 2, 0)
    np.testing.assert_allclose(np.asarray(r.normal_velocity), vn.T, rtol=1e-10, atol=0)
    np.testing.assert_allclose(np.asarray(r.point_velocity), vp.T, rtol=1e-10, atol=0)
    np.testing.assert_allclose(np.asarray(r.power), ref, rtol=1e-10)
    loads = rng.normal(size=6 * len(ch.seat_names))
    one_way = housing_response(ac, loads, 700.0)
    again = housing_vibration(ac, one_way.coordinates, 700.0)
    np.testing.assert_allclose(np.asarray(again.power), np.asarray(one_way.power), rtol=1e-12)
    with pytest.raises(ValueError, match=rf"coordinates: shape \(3,\), allowed \(\.\.\., {n_c}\)"):
        housing_vibration(ac, np.zeros(3), 1.0)


# -------------------------------------------------------------------------------------------
# bad input: one line naming the key


@pytest.mark.parametrize(
    ("points", "match"),
    [
        ('top = [50.0, 80.0]\n', r"\[housing\.points_mm\] top = \[50, 80\]: must be an array of 3"),
        ('top = "lid"\n', r"\[housing\.points_mm\] top"),
        ('top = [50.0, 80.0, nan]\n', r"\[housing\.points_mm\] top.*finite"),
    ],
)
def test_points_table_errors_one_line(tmp_path, points, match):
    table = TABLE[: TABLE.index("[housing.points_mm]")] + "[housing.points_mm]\n" + points
    with pytest.raises(ValueError, match=match) as e:
        _case(tmp_path, table)
    assert "\n" not in str(e.value)


def test_unknown_housing_key_one_line(tmp_path):
    table = TABLE.replace("[housing.points_mm]", 'point_mm = [0.0, 0.0, 0.0]\n[housing.points_mm]')
    with pytest.raises(ValueError, match=r"point_mm") as e:
        _case(tmp_path, table)
    assert "\n" not in str(e.value)


@pytest.mark.parametrize(
    ("xyz", "why"),
    [("[50.0, 300.0, 0.0]", "outside the housing, 220 mm from its outer faces"),
     ("[50.0, 0.0, 0.0]", "in the housing's cavity")],
)
def test_point_off_the_housing_one_line(tmp_path, xyz, why):
    """A point 220 mm above the lid, or at the box's centre: one line naming the point's key
    when the case is loaded (the box's outer faces, before anything is meshed); the same
    points given to the built housing's skin (a mesh file's check, housing_surface): one line
    too (70 mm from every wall, more than 0.6 of the 40 mm cells' longest skin edge)."""
    table = TABLE.replace('top = [50.0, 80.0, 0.0]', f"top = {xyz}")
    with pytest.raises(ValueError, match=r"\[housing\.points_mm\] top = .*: " + why
                       + r": allowed on its outer skin, within") as e:
        _case(tmp_path, table)
    assert "\n" not in str(e.value)
    case = _case(tmp_path)
    body = case.housing_body()
    far = tuple(float(x) * 1e-3 for x in xyz.strip("[]").split(","))
    spec = dataclasses.replace(case.housing, points=(("top", far),))
    with pytest.raises(ValueError, match=r"\[housing\.points_mm\] top = .*from the housing's "
                       r"outer surface.*allowed within") as e:
        jio.housing_surface(spec, body)
    assert "\n" not in str(e.value)


def test_named_points_snap_to_the_nearest_skin_node(tmp_path):
    """Each named point (scene frame, mm) is read at the outer skin's node nearest it, found
    here by brute force over the skin facets' nodes in the scene frame."""
    case = _case(tmp_path)
    body = case.housing_body()
    s = jio.housing_surface(case.housing, body)
    R = np.asarray(body.housing.rotation)
    nodes = body.mesh.nodes @ R.T + body.offset  # the scene frame
    skin = np.unique(body.mesh.mesh.facets[:, s.facets])  # (Tet4: the vertices)
    for k, (name, xyz) in enumerate(case.housing.points):
        d = np.linalg.norm(nodes[skin] - np.asarray(xyz), axis=1)
        np.testing.assert_allclose(R @ s.point_positions[k] + body.offset,
                                   nodes[skin[np.argmin(d)]], atol=1e-12)
        assert s.point_names[k] == name


# -------------------------------------------------------------------------------------------
# the run




@pytest.fixture(scope="module")
def housed_run(tmp_path_factory):
    """whine_outputs on the undamped housed pair (damping "none", loss factor 0: the full FE
    reference below has no damping to match), and the same response solved again here."""
    from jaxgear.cli.run import whine_outputs
    from jaxgear.dynamics import whine_response

    tmp = tmp_path_factory.mktemp("housed")
    case = _case(tmp, whine=WHINE, damping='model = "none"')
    section = whine_outputs(case, str(tmp))
    model, _ = jio.build_dynamic_model(case)
    inputs = jio.whine_of(case)
    w = whine_response(model, np.asarray(inputs.speeds), inputs.method,
                       positions=inputs.positions)
    return case, tmp / "whine", section, model, w


@pytest.mark.slow  # about 40 s on the 2-core host (the housed pair's whine)
def test_run_files_are_complete(housed_run):
    _, folder, section, _, _ = housed_run
    h = section["housing"]
    names = ["housing.json", "housing.csv", "erp_orders.png", "erp_waterfall.png",
             "point_top_orders.png", "point_top_waterfall.png", "point_side_wall_orders.png",
             "point_side_wall_waterfall.png", "housing_ods.vtu"]
    assert h["files"] == [f"whine/{n}" for n in names]
    for n in names:
        assert (folder / n).stat().st_size > 0, n
    d = json.loads((folder / "housing.json").read_text())
    assert d["cutoff_source"] == "cutoff_Hz"  # the table's key (HOUSING_TABLE's cutoff_Hz)
    S, K = 3, 2
    assert d["orders"] == [1.0, 2.0] and d["speeds_rad_s"] == [40.0, 100.0, 160.0]
    for key in ("frequency_Hz", "in_band", "erp_W", "erp_level_dB"):
        assert np.shape(d[key]) == (S, K), key
    assert set(d["points"]) == {"top", "side wall"}
    for p in d["points"].values():
        assert np.shape(p["velocity_m_s"]["amplitude"]) == (S, K)
        assert abs(np.linalg.norm(p["normal"]) - 1) < 1e-12
    # the overall: the in-band orders' powers summed, in dB re 1 pW
    P, band = np.array(d["erp_W"]), np.array(d["in_band"])
    tot = np.where(band, P, 0).sum(axis=1)
    np.testing.assert_allclose(d["overall_erp_W"], tot, rtol=1e-12)
    np.testing.assert_allclose(d["overall_erp_level_dB"], 10 * np.log10(tot / 1e-12), rtol=1e-12)
    with open(folder / "housing.csv") as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == S * K
    assert {"erp_W", "erp_dB", "point_top_mm_s", "point_side_wall_phase_deg"} <= set(rows[0])
    np.testing.assert_allclose([float(r["erp_W"]) for r in rows], P.ravel(), rtol=1e-10)
    import meshio

    m = meshio.read(folder / "housing_ods.vtu")
    labels = [o["label"] for o in d["operating_deflection_shapes"]]
    assert labels and all(f"{lab}_amplitude" in m.point_data for lab in labels)
    w = json.loads((folder / "whine.json").read_text())
    assert w["housing"]["files"] == h["files"]


def _full_fe_check(case, folder, model, w, max_hz):
    """The run's ERP and point velocities in ``folder``/housing.json against the full FE
    model at every speed and order up to ``max_hz`` (the test below); returns how many."""
    d = json.loads((folder / "housing.json").read_text())
    body = case.housing_body()
    prepared = prepare_housing(body.mesh, fem_prep.Material(*case.housing.material),
                               case.housing.cutoff)
    s = outer_surface(body.mesh)
    st = model.scene.structure
    first = st.node(f"housing {body.condensed.seat_names[0]}")
    nb = 6 * len(body.condensed.seat_names)
    Kb = np.asarray(st.stiffness_parts()["bearings"])[first : first + nb]
    X = np.asarray(w.coordinates)
    pop = jio.housing_surface(case.housing, body).point_operator
    names = list(d["points"])
    checked = 0
    for i in range(len(d["speeds_rad_s"])):
        for j, order in enumerate(d["orders"]):
            f = d["frequency_Hz"][i][j]
            if f > max_hz:
                continue
            h = int(np.argmin(np.abs(np.asarray(w.orders) - order)))
            loads = -(Kb @ X[i, h])
            rhs = np.zeros(prepared.K.shape[0], complex)
            rhs[prepared.seat_dofs.ravel()] = loads
            A = (prepared.K - (2 * math.pi * f) ** 2 * prepared.M).tocsc()
            u = prepared.full_field(spla.spsolve(A, rhs))
            vn = 2j * math.pi * f * (s.square_operator @ u)  # ‖S v‖² = ∫ |v_n|² dS
            ref = 0.5 * AIR.density * AIR.sound_speed * np.sum(np.abs(vn) ** 2)
            np.testing.assert_allclose(d["erp_W"][i][j], ref, rtol=0.004)
            if names:
                vp = np.abs(2j * math.pi * f * (pop @ u))
                got = [d["points"][n]["velocity_m_s"]["amplitude"][i][j] for n in names]
                np.testing.assert_allclose(got, vp, rtol=0, atol=0.01 * vp.max())
            checked += 1
    return checked


@pytest.mark.slow  # shares the run above; the full FE solves take a few seconds
def test_run_erp_and_points_against_the_full_fe_model(housed_run):
    """At the speeds and orders up to an eighth of the cut-off (6 kHz): the loads the bearings
    put on the seats in the coupled response, −K_bearings[seats, :] X (the bearings' stiffness
    part of the structure), applied to the full clamped housing FE model solved at the order's
    frequency (sparse LU): its skin ERP (½ρc ∫|iω u·n|² dS) equals the run's within 0.4 %
    (measured 0.01-0.1 % at 290-720 Hz) and its normal velocity at the named points' nodes
    within 1 % of the largest (measured 0.7 %). Higher, the condensation's error grows as
    (f / f_c)²: 1.7-3.7 % at 1.1-1.4 kHz (docs/housing.md, "In jaxgear run")."""
    case, folder, _, model, w = housed_run
    assert _full_fe_check(case, folder, model, w, case.housing.cutoff / 8) == 3


@pytest.mark.slow  # about 40 s on the 2-core host
def test_train_run_erp_against_the_full_fe_model(tmp_path):
    """The same on a lumped 3D idler train (three shafts, six bearings, tests/_kinds.py) in a
    box: the run's housing files, and its ERP against the full FE model up to f_c / 8."""
    from jaxgear.cli.run import whine_outputs
    from jaxgear.dynamics import whine_response

    case = housed_train(tmp_path)
    section = whine_outputs(case, str(tmp_path))
    assert {"whine/housing.json", "whine/erp_orders.png", "whine/housing_ods.vtu"} <= set(
        section["housing"]["files"])
    model, _ = jio.build_dynamic_model(case)
    inputs = jio.whine_of(case)
    w = whine_response(model, np.asarray(inputs.speeds), inputs.method,
                       positions=inputs.positions)
    assert _full_fe_check(case, tmp_path / "whine", model, w, case.housing.cutoff / 8) >= 2


# -------------------------------------------------------------------------------------------
# [acoustics] on the housed run: the radiated sound of the same skin


@pytest.mark.parametrize(
    "tables, match",
    [("[acoustics]\nmethod = 'erp-only'\n", r"needs \[housing\]"),
     (TABLE + "[acoustics]\nmethod = 'erp-only'\n", r"needs \[whine\]"),
     (TABLE + WHINE + "[acoustics]\nmethod = 'rayleigh'\n", r"\[acoustics\] method")],
)
def test_acoustics_table_needs_a_housed_whine_one_line(tmp_path, tables, match):
    text = jio.embedded_case_text("accessory-spur") + tables
    path = tmp_path / "a.toml"
    path.write_text(text)
    with pytest.raises(jio.SchemaError, match=match) as e:
        jio.load_case(str(path))
    assert "\n" not in str(e.value)


@pytest.mark.slow  # the housed pair's whine again (about 40 s on the 2-core host)
def test_run_acoustics_erp_only_is_the_housing_erp(tmp_path):
    """[acoustics] method 'erp-only' (R = ½ρc M on the closed skin's vertices, the caps' velocity
    interpolated from their rims) radiates what the housing's own ERP (½ρc ∫|v_n|² dS on the
    open skin's facets, exact for the FE field) gives for the same response: two
    discretisations of one integral. They differ at the box's edges and corners, where the
    closed skin's vertex normal (area-weighted, between two walls) reads a wall's motion at
    cos 45°, and inside the facets, where the closed skin's P1 field keeps the corner nodes
    only: on this coarse box (40 mm cells) the vertex form is 0.11-0.33 dB below the exact
    one; asserted within 0.5 dB (12 %), which a factor ½ or a lost conjugate (3 dB and more)
    would break."""
    from jaxgear.cli.run import whine_outputs

    case = _case(tmp_path, whine=WHINE + "\n[acoustics]\nmethod = 'erp-only'\nfrequencies = 8\n",
                 damping='model = "none"')
    section = whine_outputs(case, str(tmp_path))
    h = json.loads((tmp_path / "whine" / "housing.json").read_text())
    a = json.loads((tmp_path / "acoustics" / "sound_power.json").read_text())
    assert all(all(row) for row in h["in_band"])  # both sum the same orders
    erp = np.asarray(h["overall_erp_level_dB"])
    lw = np.asarray(a["overall_LW_dB"])
    np.testing.assert_allclose(lw, erp, atol=0.5)
    assert section["housing"]["acoustics"]["files"]


# -------------------------------------------------------------------------------------------
# the library's one call: jaxgear.io.case_sound


def _hand_erp(case, model, w, rho=1.21, c=343.0):
    """The ERP (W, (S, K-1)) of the response ``w`` written here from the recovered skin
    velocities: the housing's condensed coordinates q (the scene's ``housing <first seat>``
    node on), the full field u = Φ q, each skin facet's corner normal velocities
    v_a = iω n·u_a (n from the facet's own corners; Tet4: a flat, linear facet), and
    ERP = ρc Σ_i A_i ⟨|v_n|²⟩_i / 2 with the facet's mean square of the linear field
    ⟨|v_n|²⟩ = (Σ_a |v_a|² + |Σ_a v_a|²) / 12 (∫ N_a N_b dA = A (1 + δ_ab) / 12); ρ, c of air
    at 20 °C."""
    body = case.housing_body()
    ch = body.condensed
    first = model.scene.structure.node(f"housing {ch.seat_names[0]}")
    orders = np.asarray(w.orders, dtype=float)[1:]
    q = np.asarray(w.coordinates)[:, 1:, first : first + ch.K.shape[0]]  # (S, K-1, n_c)
    f = np.asarray(w.frequency, dtype=float)[:, None] * orders[None, :]
    u = np.einsum("dn,skn->skd", np.asarray(ch.recovery), q)  # (S, K-1, n_dofs)
    skin = jio.housing_surface(case.housing, body).facets
    corners = body.mesh.mesh.facets[:, skin]  # (3, F) vertex indices
    p = body.mesh.nodes[corners]  # (3, F, 3)
    cross = np.cross(p[1] - p[0], p[2] - p[0])
    area = 0.5 * np.linalg.norm(cross, axis=1)
    normal = cross / (2 * area[:, None])
    ua = u[..., 3 * corners[:, :, None] + np.arange(3)]  # (S, K-1, 3, F, 3)
    va = 2j * math.pi * f[..., None, None] * np.einsum("skafd,fd->skaf", ua, normal)
    mean_square = (np.sum(np.abs(va) ** 2, axis=2) + np.abs(va.sum(axis=2)) ** 2) / 12
    return 0.5 * rho * c * np.sum(area * mean_square, axis=-1)


@pytest.mark.slow  # one more whine of the housed pair (about 20 s), beside the shared run
def test_case_sound_is_what_the_run_writes(housed_run):
    """jaxgear.io.case_sound of the housed pair equals the run's whine/housing.json (the
    independent path: the file jaxgear run wrote): each order's frequency, band flag, ERP
    (W, dB) and the overall, the named points' velocity amplitudes, to 1e-9; its ERP equals
    the one written in the test from the recovered skin velocities (:func:`_hand_erp`) to
    1e-9; the radiated sound power by an ``erp-only`` [acoustics] (R = ½ρc M on the closed
    skin's vertices) is within 0.5 dB of the housing's ERP at every speed (two discretisations
    of one integral: docs/acoustics.md, measured 0.11-0.33 dB on this box)."""
    case, folder, _, _, _ = housed_run
    d = json.loads((folder / "housing.json").read_text())
    sound = jio.case_sound(case)
    assert sound.sound_power is None  # the case has no [acoustics]
    erp = sound.erp
    np.testing.assert_allclose(sound.whine.speed, d["speeds_rad_s"], rtol=1e-12)
    np.testing.assert_allclose(erp.orders, d["orders"], rtol=0)
    np.testing.assert_allclose(erp.frequency, d["frequency_Hz"], rtol=1e-12)
    assert erp.in_band.tolist() == d["in_band"]
    np.testing.assert_allclose(erp.power, d["erp_W"], rtol=1e-9)
    np.testing.assert_allclose(erp.level, d["erp_level_dB"], rtol=1e-9)
    np.testing.assert_allclose(erp.overall_w, d["overall_erp_W"], rtol=1e-9)
    np.testing.assert_allclose(erp.overall_db, d["overall_erp_level_dB"], rtol=1e-9)
    pv = np.abs(np.asarray(erp.vibration.point_velocity))
    for k, name in enumerate(sound.housed.acoustics.point_names):
        want = d["points"][name]["velocity_m_s"]["amplitude"]
        np.testing.assert_allclose(pv[:, :, k], want, rtol=1e-9)
    np.testing.assert_allclose(erp.power, _hand_erp(case, sound.model, sound.whine), rtol=1e-9)
    radiated = sound.with_sound_power(jio.parse_acoustics({"method": "erp-only",
                                                            "frequencies": 8}))
    assert radiated.whine is sound.whine and radiated.radiation.orders.tolist() == [1.0, 2.0]
    np.testing.assert_allclose(radiated.sound_power.overall, erp.overall_db, atol=0.5)


def test_case_sound_refuses_a_case_that_is_not_housed_in_one_line(tmp_path):
    """No [housing], no [whine], or sound_power=True without [acoustics]: one line naming the
    table, before any work."""
    plain = tmp_path / "plain.toml"
    plain.write_text(jio.embedded_case_text("accessory-spur") + WHINE)
    for case, kw, match in (
        (jio.load_case(str(plain)), {}, r"^\[housing\]: the case has none"),
        (_case(tmp_path), {}, r"^\[whine\]: the case has none"),
        (_case(tmp_path, whine=WHINE), {"sound_power": True},
         r"^\[acoustics\]: the case has none"),
    ):
        with pytest.raises(jio.SchemaError, match=match) as e:
            jio.case_sound(case, **kw)
        assert "\n" not in str(e.value)


def test_housing_coordinates_are_the_placed_columns_and_refuse_unplaced():
    """A housing placed at ``first`` picks the n_c columns from ``first`` of a model's
    coordinates (n_c the skin operator's size); unplaced (``first`` None, as
    ``housed_acoustics`` returns it) it is refused in one line."""
    acoustics = dataclasses.make_dataclass("Ac", ["K"])(np.zeros((3, 3)))
    q = np.arange(2 * 9.0).reshape(2, 9)
    placed = jio.HousedAcoustics(None, None, acoustics, first=4)
    np.testing.assert_array_equal(placed.housing_coordinates(q), [[4, 5, 6], [13, 14, 15]])
    with pytest.raises(ValueError, match=r"^HousedAcoustics.first: None") as e:
        placed._replace(first=None).housing_coordinates(q)
    assert "\n" not in str(e.value)
