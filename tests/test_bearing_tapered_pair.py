"""A pair of tapered roller bearings facing both ways (:class:`jaxgear.bearings.TaperedRollerPair`)
against references written here.

- The load: two :class:`~jaxgear.bearings.TaperedRoller` rows evaluated separately here, the
  mirrored row by the reflection z → −z written out in components (δ_z, γ_x, γ_y and F_z, M_x,
  M_y change sign), each displaced by the rigid inner ring's lever to its mid-plane
  (δ_x + z γ_y, δ_y − z γ_x) and its moment carried to the node by hand (M_x − z F_y,
  M_y + z F_x); the pressure centres ±(s/2 ± (d_m/2) tan α) by hand.
- The stiffness: central differences of the load, and the rows' stiffnesses transformed by hand
  (Σ A_iᵀ K_row A_i with the lever and mirror matrices written here).
- Zero end play under a radial load: each row carries F_r/2 over a half-loaded raceway, its
  induced axial load 1.260 (F_r/2) tan α (Sjövall's line-contact integrals by quadrature, and
  the published 1.260), the two opposite; under an axial load one row only, each roller's load
  K_n (δ_z sin α)^(10/9) by hand; under a moment the rows' opposite reactions.
- Preload: both rows loaded at zero external load, each roller at K_n (−e sin α / 2)^(10/9); the
  stiffness against its closed form for a uniformly loaded pair (derived in
  :func:`preloaded_stiffness`): K_r = Z k cos²α, K_a = 2 Z k sin²α,
  K_tilt = Z k cos²α (L²/4 + ⟨x²⟩), so K_tilt = K_r L²/4 + ...; O against X (same radial,
  larger tilt in O, the larger spread L).
- ISO 281: C = 2^(7/9) C_row = 1.715 C_row, P of a double-row roller bearing by hand, L10;
  the tones the row's by hand; the refusals (the kind's and the case file's), one line each.
"""

from __future__ import annotations

import math
import tomllib
from pathlib import Path

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest
from test_bearings import _element_loads, _load, refused_in_one_line, sjovall

import jaxgear.bearings as jb
import jaxgear.io as jio
import jaxgear.scenes as js

ROOT = Path(__file__).resolve().parents[1]
ALPHA = math.atan(0.37 / 1.5)
#: one row: a 30206-sized tapered roller bearing (rollers a representative estimate)
ROW = {"bore": 0.03, "outer_diameter": 0.062, "width": 0.01725, "elements": 17,
       "element_diameter": 0.0065, "pitch_diameter": 0.046, "effective_length": 0.012,
       "contact_angle": ALPHA}


def pair(arrangement="O", end_play=0.0, **kw):
    return jb.TaperedRollerPair(**{**ROW, **kw}, arrangement=arrangement, end_play=end_play)


def many(arrangement="O", end_play=0.0):
    """72 small rollers per row on a 100 mm pitch circle (the continuous limit), one slice."""
    return jb.TaperedRollerPair(bore=0.09, outer_diameter=0.11, width=0.01, elements=72,
                                element_diameter=0.002, pitch_diameter=0.1,
                                effective_length=0.004, contact_angle=ALPHA, slices=1,
                                arrangement=arrangement, end_play=end_play)


def row_of(p, end_play):
    """The pair's row as a separate TaperedRoller, its clearance e tan α."""
    return jb.TaperedRoller(bore=float(p.row.bore), outer_diameter=float(p.row.outer_diameter),
                            width=float(p.row.width), elements=p.elements,
                            element_diameter=float(p.element_diameter),
                            pitch_diameter=float(p.pitch_diameter),
                            effective_length=float(p.effective_length),
                            contact_angle=float(p.contact_angle), slices=p.row.slices,
                            clearance=end_play * math.tan(float(p.contact_angle)))


def layout(arrangement, s):
    """[(z_i, mirrored_i)]: the rows' mid-planes at ∓s/2; in O the row at +z carries −z (its
    pressure centre outside), in X the row at −z does."""
    return [(-s / 2, arrangement == "X"), (s / 2, arrangement == "O")]


def rows_by_hand(p, d, end_play, arrangement, s):
    """Each row's (z_i, its load (5,) about its own mid-plane in the pair's axes): the row's
    displacement by the lever and the mirror written out, the row's load mirrored back."""
    row = row_of(p, end_play)
    ux, uy, uz, gx, gy = (float(v) for v in d)
    out = []
    for z, m in layout(arrangement, s):
        local = np.array([ux + z * gy, uy - z * gx, uz, gx, gy])  # the rigid ring's lever
        if m:  # the mirror image: z → −z (a translation's z, a rotation's x and y)
            local = local * np.array([1, 1, -1, -1, -1])
        f = np.asarray(_load(row, jnp.asarray(local)))
        if m:
            f = f * np.array([1, 1, -1, -1, -1])
        out.append((z, f))
    return out


def to_node(rows):
    """The rows' loads summed at the node: forces, moments plus the lever's z × F."""
    total = np.zeros(5)
    for z, f in rows:
        Fx, Fy, Fz, Mx, My = f
        total += np.array([Fx, Fy, Fz, Mx - z * Fy, My + z * Fx])
    return total


D_GENERAL = np.array([14e-6, -6e-6, 3e-6, 2.0e-4, -1.5e-4])


@pytest.mark.parametrize("arrangement,end_play", [("O", 0.0), ("X", 0.0), ("O", 20e-6),
                                                  ("X", -8e-6)])
def test_load_is_the_two_rows_by_hand(arrangement, end_play):
    """At a displacement with every DOF: the pair's load = its two rows evaluated separately,
    combined with their levers (1e-12 of the largest force, moments over the pitch radius);
    the pressure centres ±(s/2 + a) (O) and ±(s/2 − a) (X), a = (d_m/2) tan α."""
    p = pair(arrangement, end_play)
    s, a = ROW["width"], 0.5 * ROW["pitch_diameter"] * math.tan(ALPHA)
    f = np.asarray(_load(p, jnp.asarray(D_GENERAL)))
    ref = to_node(rows_by_hand(p, D_GENERAL, end_play, arrangement, s))
    r = 0.5 * ROW["pitch_diameter"]
    scale = np.array([1, 1, 1, 1 / r, 1 / r])
    assert np.max(np.abs(ref[:3])) > 100.0  # loaded
    np.testing.assert_allclose(f * scale, ref * scale, rtol=0,
                               atol=1e-12 * np.max(np.abs(ref * scale)))
    half = s / 2 + (a if arrangement == "O" else -a)
    np.testing.assert_allclose(np.asarray(p.centres), [-half, half], rtol=1e-12)
    assert float(p.spread) == pytest.approx(2 * half, rel=1e-12)


def lever(z):
    T = np.eye(5)
    T[0, 4], T[1, 3] = z, -z
    return T


@pytest.mark.parametrize("arrangement,end_play", [("O", 0.0), ("X", -8e-6)])
def test_stiffness_is_the_jacobian_and_the_rows_transformed(arrangement, end_play):
    """K against central differences of the load (1e-6) and against Σ A_iᵀ K_row(A_i d) A_i,
    A_i = S_i T_i with the lever T_i and the mirror S_i written here (1e-10); symmetric."""
    p = pair(arrangement, end_play)
    d = jnp.asarray(D_GENERAL)
    K = np.asarray(p.stiffness(d))
    r = 0.5 * ROW["pitch_diameter"]
    steps = np.array([1e-9, 1e-9, 1e-9, 1e-9 / r, 1e-9 / r])
    fd = np.empty((5, 5))
    for j in range(5):
        e = np.zeros(5)
        e[j] = steps[j]
        fd[:, j] = (np.asarray(_load(p, d + e)) - np.asarray(_load(p, d - e))) / (2 * steps[j])
    unit = np.array([1, 1, 1, r, r])  # N/m and N·m/rad in one size: K_ij u_i u_j
    Ks, fds = K * unit[:, None] * unit[None, :], fd * unit[:, None] * unit[None, :]
    np.testing.assert_allclose(Ks, fds, rtol=0, atol=1e-6 * np.max(np.abs(Ks)))
    row = row_of(p, end_play)
    ref = np.zeros((5, 5))
    for z, m in layout(arrangement, ROW["width"]):
        A = np.diag([1, 1, -1, -1, -1] if m else [1] * 5) @ lever(z)
        ref += A.T @ np.asarray(row.stiffness(jnp.asarray(A @ np.asarray(d)))) @ A
    refs = ref * unit[:, None] * unit[None, :]
    np.testing.assert_allclose(Ks, refs, rtol=0, atol=1e-10 * np.max(np.abs(refs)))
    np.testing.assert_allclose(Ks, Ks.T, rtol=0, atol=1e-10 * np.max(np.abs(Ks)))


def test_radial_load_zero_end_play_half_loaded_raceways():
    """Zero end play, F_r alone (O; X is its mirror image here): the solve leaves δ_z and the
    tilts at 0; each row carries F_r/2 over a half-loaded raceway, its induced axial load
    J_a/J_r (F_r/2) tan α with Sjövall's integrals for Q ∝ δ^(10/9) by quadrature (2e-3 with 72
    rollers) and the published 1.260 (3e-3), the rows' axial loads opposite;
    Q_max Z cos α / (F_r/2) = 4.08 (3e-3)."""
    arrangement = "O"
    p = many(arrangement)
    Fr = 5000.0
    st = jb.solve_displacement(p, jnp.array([Fr, 0, 0, 0, 0]))
    assert float(st.residual) < 1e-9
    d = np.asarray(st.displacement)
    assert abs(d[2]) < 1e-9 * d[0] and np.all(np.abs(d[3:]) * 0.05 < 1e-9 * d[0])
    rows = [f for _, f in rows_by_hand(p, d, 0.0, arrangement, 0.01)]
    Jr, Ja = sjovall(10.0 / 9.0)
    for f in rows:
        assert f[0] == pytest.approx(Fr / 2, rel=1e-9)
        ratio = abs(f[2]) / (f[0] * math.tan(ALPHA))
        assert ratio == pytest.approx(Ja / Jr, rel=2e-3)
        assert ratio == pytest.approx(1.260, rel=3e-3)
    assert rows[0][2] == pytest.approx(-rows[1][2], rel=1e-9)
    q = np.asarray(_element_loads(p, jnp.asarray(d)))  # (2, Z, 1)
    assert q.shape == (2, 72, 1)
    for i in range(2):
        assert q[i].max() * 72 * math.cos(ALPHA) / (Fr / 2) == pytest.approx(4.08, rel=3e-3)


@pytest.mark.parametrize("arrangement", ["O", "X"])
def test_axial_load_one_row_only(arrangement):
    """Zero end play, an axial approach δ_z either way, chosen by hand to carry F_a: each roller
    of one row Q = K_n (|δ_z| sin α)^(10/9), Z Q sin α = F_a; the pair's load (0, 0, ±F_a, 0, 0)
    (1e-12), that row's rollers each at Q (1e-12), the other row unloaded. +z is carried by the
    row at −z in O, at +z in X."""
    p = pair(arrangement)
    Kn, Z, sa = float(p.hertz_constant), ROW["elements"], math.sin(ALPHA)
    Fa = 3000.0
    Q = Fa / (Z * sa)
    dz = (Q / Kn) ** 0.9 / sa
    for sign in (1.0, -1.0):
        d = jnp.array([0.0, 0.0, sign * dz, 0.0, 0.0])
        f = np.asarray(_load(p, d))
        np.testing.assert_allclose(f, [0, 0, sign * Fa, 0, 0], rtol=0, atol=1e-12 * Fa)
        q = np.asarray(_element_loads(p, d))
        loaded = (0 if arrangement == "O" else 1) if sign > 0 else (1 if arrangement == "O" else 0)
        assert np.all(q[1 - loaded] == 0.0)
        np.testing.assert_allclose(q[loaded].sum(axis=1), Q, rtol=1e-12)


def test_moment_opposite_row_reactions():
    """Zero end play, a moment M_y alone (O): no net force; the rows' radial and axial forces
    opposite (1e-9), the row at +z pushed +x by the positive tilt; the moment is the rows'
    moments plus their forces' levers (the balance, 1e-9)."""
    p = pair("O")
    My = 200.0
    st = jb.solve_displacement(p, jnp.array([0, 0, 0, 0, My]))
    assert float(st.residual) < 1e-9
    rows = rows_by_hand(p, np.asarray(st.displacement), 0.0, "O", ROW["width"])
    (_, f0), (_, f1) = rows
    scale = abs(f1[0])
    assert f1[0] > 0 and float(st.displacement[4]) > 0
    assert f0[0] == pytest.approx(-f1[0], rel=1e-9)
    assert abs(f0[2] + f1[2]) < 1e-9 * scale and abs(f0[2]) > 0.1 * scale
    assert to_node(rows)[4] == pytest.approx(My, rel=1e-9)


def preloaded_stiffness(p, e, L):
    """The closed form of a pair preloaded by an end play e < 0, no external load: every slice
    of both rows at the approach δ₀ = −e sin α / 2, its stiffness k/S, k = (10/9) K_n δ₀^(1/9).
    A slice at azimuth ψ and offset x along the axis (x = t cos α) of a row whose pressure centre
    is z_c approaches by (δ_x cos ψ) cos α ± δ_z sin α + γ_y cos ψ cos α (z_c + x) under δ_x,
    δ_z, γ_y (the lever z_i γ_y, the row's own θ = γ_y cos ψ: (z_i + x) cos α − r_p sin α =
    (z_c + x) cos α). Summing over Z slices' azimuths (Σ cos²ψ = Z/2) and both rows:
    K_r = Z k cos²α, K_a = 2 Z k sin²α, K_tilt = Z k cos²α (L²/4 + ⟨x²⟩), the centres ±L/2
    (the cross terms Σ x cancel over the roller's symmetric slices)."""
    a, S, ell = float(p.contact_angle), p.row.slices, float(p.effective_length)
    k = 10 / 9 * float(p.hertz_constant) * (-e * math.sin(a) / 2) ** (1 / 9)
    t = ((np.arange(S) + 0.5) / S - 0.5) * ell
    x2 = np.mean((t * math.cos(a)) ** 2)
    Z = p.elements
    return (Z * k * math.cos(a) ** 2, 2 * Z * k * math.sin(a) ** 2,
            Z * k * math.cos(a) ** 2 * (L**2 / 4 + x2))


def test_preload_loads_both_rows_and_stiffens_o_against_x():
    """A preload e = −10 µm, no load: both rows loaded, each slice at K_n/S (−e sin α/2)^(10/9)
    (1e-12), the pair's load zero; K_r, K_a, K_tilt against the closed form
    (:func:`preloaded_stiffness`, 1e-9) with L from the hand geometry; O and X alike radially
    and axially, the tilt stiffness larger in O (its spread s + 2a against |s − 2a|); the
    preloaded pair stiffer than the one with zero end play under the same radial load."""
    e = -10e-6
    out = {}
    for arr in ("O", "X"):
        p = pair(arr, e)
        zero = jnp.zeros(5)
        np.testing.assert_allclose(np.asarray(_load(p, zero)), 0.0, atol=1e-9)
        q = np.asarray(_element_loads(p, zero))
        S = p.row.slices
        np.testing.assert_allclose(
            q, float(p.hertz_constant) / S * (-e * math.sin(ALPHA) / 2) ** (10 / 9), rtol=1e-12)
        a = 0.5 * ROW["pitch_diameter"] * math.tan(ALPHA)
        L = ROW["width"] + (2 * a if arr == "O" else -2 * a)
        Kr, Ka, Kt = preloaded_stiffness(p, e, L)
        K = np.asarray(p.stiffness(zero))
        assert K[0, 0] == pytest.approx(Kr, rel=1e-9) and K[1, 1] == pytest.approx(Kr, rel=1e-9)
        assert K[2, 2] == pytest.approx(Ka, rel=1e-9)
        assert K[3, 3] == pytest.approx(Kt, rel=1e-9) and K[4, 4] == pytest.approx(Kt, rel=1e-9)
        out[arr] = K
    assert out["O"][0, 0] == pytest.approx(out["X"][0, 0], rel=1e-12)
    assert out["O"][4, 4] > 3 * out["X"][4, 4]
    F = jnp.array([2000.0, 0, 0, 0, 0])
    pre = jb.solve_displacement(pair("O", e), F)
    free = jb.solve_displacement(pair("O", 0.0), F)
    assert float(pre.stiffness[0, 0]) > float(free.stiffness[0, 0])
    assert float(pre.displacement[0]) < float(free.displacement[0])


def test_preload_derivative_of_the_stiffness():
    """The end play is a design variable: ∂K_r/∂e by ``jax.grad`` through the pair's stiffness
    at a preload, against the closed form's K_r ∝ (−e)^(1/9): ∂K_r/∂e = K_r / (9 e) (1e-9)."""
    e = -10e-6
    p = pair("O", e)

    def radial(end_play):
        q = eqx.tree_at(lambda b: b.end_play, p, end_play)
        return jax.jacfwd(q.load)(jnp.zeros(5))[0, 0]

    Kr = preloaded_stiffness(p, e, 0.0)[0]
    got = float(jax.jit(jax.grad(radial))(jnp.asarray(e)))
    assert got == pytest.approx(Kr / (9 * e), rel=1e-9)


def test_iso281_life_and_ratings_of_the_pair():
    """C = 2^(7/9) C_row (1.7145, ISO 281's paired single-row roller bearings), C₀ = 2 C₀_row;
    P = F_r + 0.45 cot α F_a below e = 1.5 tan α, else 0.67 F_r + 0.67 cot α F_a, by hand;
    L10 = (C/P)^(10/3) 10⁶ revolutions; the kind declares what it carries."""
    p = pair(dynamic_rating=64e3, static_rating=70e3)
    assert float(p.dynamic_rating) == pytest.approx(64e3 * 1.7145, rel=1e-4)
    assert float(p.static_rating) == pytest.approx(140e3, rel=1e-12)
    assert p.axial_load == "both" and not p.self_aligning and p.carried() == (True,) * 5
    cot = 1.5 / 0.37
    for Fr, Fa, P in ((5000.0, 1000.0, 5000.0 + 0.45 * cot * 1000.0),
                      (5000.0, -3000.0, 0.67 * 5000.0 + 0.67 * cot * 3000.0)):
        life = jb.rating_life(p, Fr, Fa, 100.0)
        assert float(life.equivalent_load) == pytest.approx(P, rel=1e-12)
        C = 64e3 * 2 ** (7 / 9)
        assert float(life.revolutions) == pytest.approx((C / P) ** (10 / 3) * 1e6, rel=1e-12)


def test_tones_are_the_rows():
    """FTF, BPFO, BPFI, BSF with the row's Z, D_w, d_m and α by hand (1e-12)."""
    p = pair()
    t = jb.bearing_tones(p)
    Z, D, dm = ROW["elements"], ROW["element_diameter"], ROW["pitch_diameter"]
    g = D * math.cos(ALPHA) / dm
    for got, want in ((t.ftf, (1 - g) / 2), (t.bpfo, Z * (1 - g) / 2),
                      (t.bpfi, Z * (1 + g) / 2), (t.bsf, dm / (2 * D) * (1 - g * g))):
        assert float(got) == pytest.approx(want, rel=1e-12)


def test_a_scene_bearing_takes_the_pair():
    """``Bearing(z, rolling=pair)``: its hash and equality see the row's geometry (two pairs of
    one geometry equal, another roller count not), at an operating point the pair's
    stiffness6."""
    b1, b2 = js.Bearing(0.1, rolling=pair()), js.Bearing(0.1, rolling=pair())
    assert b1 == b2 and hash(b1) == hash(b2)
    assert b1 != js.Bearing(0.1, rolling=pair(elements=16))
    assert b1 != js.Bearing(0.1, rolling=pair("X"))
    d = jnp.asarray(D_GENERAL)
    np.testing.assert_allclose(b1.at(d).stiffness_matrix()[:5, :5],
                               np.asarray(pair().stiffness(d)), rtol=1e-9, atol=1e-3)


@pytest.mark.parametrize("build,words", [
    (lambda: pair("Y"), "arrangement = 'Y' is out of range"),
    (lambda: pair(end_play=0.0065 / math.tan(ALPHA)), "end_play = 0.0263514 m is out of range"),
    (lambda: pair(end_play=-1e-3), "end_play = -0.001 m is out of range"),
    (lambda: jb.TaperedRollerPair(**ROW, spacing=0.01), "spacing = 0.01 m is out of range"),
    (lambda: pair(element_diameter=0.017), "element_diameter = 0.017 m is out of range"),
    (lambda: pair(contact_angle=0.0), "contact_angle = 0 rad"),
])
def test_bad_pair_data_is_refused_in_one_line(build, words):
    refused_in_one_line(build, words)


def _pair_case(**change):
    """examples/accessory-lumped3d-rolling.toml with its first pinion bearing a 30206-sized
    tapered roller pair."""
    data = tomllib.loads((ROOT / "examples" / "accessory-lumped3d-rolling.toml").read_text())
    bearing = {"position_mm": data["scene"]["pinion_shaft"]["bearings"][0]["position_mm"],
               "kind": "tapered_roller_pair", "bore_mm": 30.0, "outer_diameter_mm": 62.0,
               "width_mm": 17.25, "rollers": 17, "roller_diameter_mm": 6.5,
               "roller_length_mm": 12.0, "pitch_diameter_mm": 46.0,
               "contact_angle_deg": math.degrees(ALPHA), "arrangement": "X",
               "end_play_um": -5.0, "row_spacing_mm": 20.0}
    data["scene"]["pinion_shaft"]["bearings"][0] = {**bearing, **change}
    return data


def test_case_file_tapered_roller_pair_keys():
    """``kind = "tapered_roller_pair"`` builds the kind (SI: end play, spacing, arrangement);
    a clearance_um, an end play beyond the roller's range, a spacing below the width, a missing
    arrangement, an arrangement on another kind refused in one line naming the key, in the
    file's units."""
    b = jio.parse_case(_pair_case()).scene.pinion_shaft.bearings[0].rolling
    assert isinstance(b, jb.TaperedRollerPair) and b.arrangement == "X" and b.elements == 17
    assert float(b.end_play) == pytest.approx(-5e-6, rel=1e-12)
    assert float(b.spacing) == pytest.approx(0.02, rel=1e-12)
    assert float(b.contact_angle) == pytest.approx(ALPHA, rel=1e-12)
    data = _pair_case()
    for key in ("end_play_um", "row_spacing_mm"):
        del data["scene"]["pinion_shaft"]["bearings"][0][key]
    b = jio.parse_case(data).scene.pinion_shaft.bearings[0].rolling
    assert float(b.end_play) == 0.0 and float(b.spacing) == pytest.approx(0.01725, rel=1e-12)
    where = "[scene.pinion_shaft.bearings[0]] "
    top = 6.5e3 * 1.5 / 0.37
    for change, start in (
        ({"clearance_um": 10.0}, "clearance_um: not a key of kind = 'tapered_roller_pair'"),
        ({"end_play_um": -300.0}, (f"end_play_um = -300: out of range, allowed "
                                   f"[{-top / 100:.6g}, {top:.6g}) µm")),
        ({"row_spacing_mm": 17.0}, "row_spacing_mm = 17: out of range, allowed >= width_mm"),
        ({"arrangement": "Y"}, "arrangement"),
    ):
        with pytest.raises(ValueError) as err:
            jio.parse_case(_pair_case(**change))
        text = str(err.value)
        assert text.startswith(where + start) and "\n" not in text, text
    data = _pair_case()
    del data["scene"]["pinion_shaft"]["bearings"][0]["arrangement"]
    with pytest.raises(ValueError) as err:
        jio.parse_case(data)
    assert str(err.value).startswith(
        where + "arrangement: missing: kind = 'tapered_roller_pair' needs"), str(err.value)
    data = _pair_case(kind="tapered_roller")
    for key in ("end_play_um", "row_spacing_mm"):
        del data["scene"]["pinion_shaft"]["bearings"][0][key]
    with pytest.raises(ValueError) as err:
        jio.parse_case(data)
    assert str(err.value).startswith(
        where + "arrangement: not a key of kind = 'tapered_roller'"), str(err.value)


def test_catalogue_rows_and_the_nrel_example_pairs():
    """The catalogue's 32060 X and LM 567949/910 rows against the NREL stage-3 table
    (benchmarks/nrel_stage3_bearings.py's transcription: d, D, B, C, α = atan(e/1.5)) and the
    rollers' rule; ``TaperedRollerPair.of`` a row: the example's pairs (their keys written out in
    the case file) carry the same load at a displacement (1e-12); ``of`` refuses another kind."""
    from benchmarks.nrel_stage3_bearings import TABLE

    case = jio.load_case(str(ROOT / "examples" / "nrel-5mw-stage3-rolling.toml"))
    d = jnp.asarray([20e-6, -10e-6, 5e-6, 1e-5, -2e-5])
    for name, designation, shaft in (("HS-B", "32060 X", case.scene.pinion_shaft),
                                     ("IMS-B", "LM 567949/910", case.scene.gear_shaft)):
        t = TABLE[name]
        row = jb.catalogue(designation)
        assert isinstance(row, jb.TaperedRoller)
        for got, want in ((row.bore, t["d"]), (row.outer_diameter, t["D"]),
                          (row.width, t["B"])):
            assert float(got) * 1e3 == pytest.approx(want, rel=1e-12)
        assert float(row.dynamic_rating) == pytest.approx(t["C_kN"] * 1e3, rel=1e-12)
        assert math.tan(float(row.contact_angle)) == pytest.approx(t["e"] / 1.5, rel=1e-12)
        est = jb.estimated_rollers(t["d"] * 1e-3, t["D"] * 1e-3, t["B"] * 1e-3)
        assert row.elements == est["elements"]
        example = shaft.bearings[1].rolling
        built = jb.TaperedRollerPair.of(row, "O", spacing=0.1)
        f = np.asarray(_load(built, d))
        np.testing.assert_allclose(np.asarray(_load(example, d)), f, rtol=0,
                                   atol=1e-12 * np.abs(f).max())
        assert float(built.dynamic_rating) == pytest.approx(2 ** (7 / 9) * t["C_kN"] * 1e3)
    refused_in_one_line(lambda: jb.TaperedRollerPair.of(jb.catalogue("NU 205")),
                        "row = CylindricalRoller: allowed a TaperedRoller")


def _mm(v: float) -> float:
    """The file's mm value whose conversion m * 1e-3 is the SI value v to the bit (the reader's
    conversion), found next to v * 1e3."""
    m = v * 1e3
    for _ in range(4):
        if m * 1e-3 == v:
            return m
        m = math.nextafter(m, math.inf if m * 1e-3 < v else -math.inf)
    raise AssertionError(f"no mm value converts to {v!r}")


def _catalogue_case(**keys):
    """:func:`_pair_case` with its pair the bearing table ``keys`` (at the same position)."""
    data = _pair_case()
    bearings = data["scene"]["pinion_shaft"]["bearings"]
    bearings[0] = {"position_mm": bearings[0]["position_mm"], **keys}
    return data


def test_case_file_catalogue_pair_is_the_spelled_out_pair():
    """``catalogue = "32060 X"`` with ``arrangement`` (``end_play_um``, ``row_spacing_mm``)
    builds the pair of the entry's rows: bit for bit the load and stiffness at a displacement
    of the pair spelled out with ``kind = "tapered_roller_pair"`` and the entry's geometry
    (mm values that convert to the entry's SI values exactly) and of
    ``TaperedRollerPair.of(catalogue("32060 X"), ...)``; the pair's C 2^(7/9) the entry's."""
    row = jb.catalogue("32060 X")
    given = {"arrangement": "X", "end_play_um": -25.0, "row_spacing_mm": 130.0}
    from_catalogue = jio.parse_case(_catalogue_case(catalogue="32060 X", **given)
                                    ).scene.pinion_shaft.bearings[0].rolling
    spelled = {
        "bore_mm": _mm(float(row.bore)), "outer_diameter_mm": _mm(float(row.outer_diameter)),
        "width_mm": _mm(float(row.width)), "rollers": row.elements,
        "roller_diameter_mm": _mm(float(row.element_diameter)),
        "roller_length_mm": _mm(float(row.effective_length)),
        "pitch_diameter_mm": _mm(float(row.pitch_diameter)),
        "contact_angle_deg": math.degrees(float(row.contact_angle))}
    assert math.radians(spelled["contact_angle_deg"]) == float(row.contact_angle)
    by_kind = jio.parse_case(_catalogue_case(kind="tapered_roller_pair", **spelled, **given)
                             ).scene.pinion_shaft.bearings[0].rolling
    api = jb.TaperedRollerPair.of(row, "X", end_play=-25.0 * 1e-6, spacing=130.0 * 1e-3)
    assert isinstance(from_catalogue, jb.TaperedRollerPair)
    assert from_catalogue.arrangement == "X" and from_catalogue.elements == 23
    assert float(from_catalogue.end_play) == pytest.approx(-25e-6, rel=1e-15)
    assert float(from_catalogue.spacing) == pytest.approx(0.13, rel=1e-15)
    assert float(from_catalogue.dynamic_rating) == pytest.approx(2 ** (7 / 9) * 1644e3,
                                                                 rel=1e-12)
    d = jnp.asarray([30e-6, -20e-6, 15e-6, 2e-5, -3e-5])
    f = np.asarray(_load(from_catalogue, d))
    k = np.asarray(from_catalogue.stiffness(d))
    assert np.abs(f[:3]).min() > 0 and np.all(np.diag(k) > 0)
    for other in (by_kind, api):
        assert np.array_equal(np.asarray(_load(other, d)), f)
        assert np.array_equal(np.asarray(other.stiffness(d)), k)
    # without end play and spacing: zero end play, the rows side by side (the width apart)
    b = jio.parse_case(_catalogue_case(catalogue="30205", arrangement="O")
                       ).scene.pinion_shaft.bearings[0].rolling
    assert b.arrangement == "O" and float(b.end_play) == 0.0
    assert float(b.spacing) == float(jb.catalogue("30205").width)


@pytest.mark.parametrize("keys,start", [
    ({"catalogue": "6205", "arrangement": "O"},
     ("arrangement = 'O': not with catalogue = '6205' (a DeepGrooveBall): allowed with a "
     "tapered roller entry ('30205', '30305', '32205', '32060 X', 'LM 567949/910')")),
    ({"catalogue": "231/750 CA", "arrangement": "X"},
     "arrangement = 'X': not with catalogue = '231/750 CA' (a SphericalRoller)"),
    ({"catalogue": "32060 X", "end_play_um": 10.0},
     ("end_play_um = 10: not without arrangement: allowed with catalogue = '32060 X' and "
     "arrangement")),
    ({"catalogue": "32060 X", "row_spacing_mm": 120.0}, ("row_spacing_mm = 120: not without "
     "arrangement")),
    ({"catalogue": "32060 X", "arrangement": "O", "clearance_um": 20.0},
     ("clearance_um = 20: not with arrangement (a pair of the entry's rows): allowed "
     "end_play_um")),
    ({"catalogue": "32060 X", "arrangement": "O", "row_spacing_mm": 90.0},
     "row_spacing_mm = 90: out of range, allowed >= width_mm = 100"),
    # 30205: D_w 6 mm, tan alpha = 0.37/1.5: end play from -D_w/100 / tan alpha = -243 um
    ({"catalogue": "30205", "arrangement": "O", "end_play_um": -300.0},
     (f"end_play_um = -300: out of range, allowed [{-60.0 * 1.5 / 0.37:.6g}, "
     f"{6000.0 * 1.5 / 0.37:.6g}) µm")),
    ({"catalogue": "32060 X", "arrangement": "O", "rollers": 20},
     ("rollers: not with catalogue = '32060 X' (the entry's geometry): allowed "
     "arrangement, end_play_um, row_spacing_mm, clearance_um beside it")),
])
def test_case_file_catalogue_pair_refusals(keys, start):
    """A pair's keys on a catalogue entry that is not a tapered roller row, its end play or
    spacing without an arrangement, a clearance beside it, its end play and spacing out of
    the entry's range, the entry's geometry: one line naming the key, in the file's units."""
    with pytest.raises(ValueError) as err:
        jio.parse_case(_catalogue_case(**keys))
    text = str(err.value)
    assert text.startswith("[scene.pinion_shaft.bearings[0]] " + start), text
    assert "\n" not in text


def test_case_file_crown_um_is_the_kinds_crown():
    """``crown_um`` on a roller kind is the kind's ``crown`` c (m): the case-file pair (kind
    and catalogue forms) and a cylindrical roller bearing carry bit for bit the load and
    stiffness at a tilted displacement of the API kinds built with crown = crown_um × 1e-6,
    (the stiffness: the pair's) which differ from the straight rollers' (the crown unloads the
    rollers' ends); ISO/TS
    16281's c = 0.00045 D_w of a tapered roller (D_w 6.5 mm: 2.925 µm), 0.00035 D_w of a
    cylindrical one."""
    d = jnp.asarray([10e-6, -5e-6, 4e-6, 2e-4, -3e-4])
    c = 0.45 * 6.5  # µm
    by_kind = jio.parse_case(_pair_case(crown_um=c)).scene.pinion_shaft.bearings[0].rolling
    api = pair("X", end_play=-5.0 * 1e-6, crown=c * 1e-6, spacing=20.0 * 1e-3,
               contact_angle=math.radians(math.degrees(ALPHA)))
    straight = pair("X", end_play=-5.0 * 1e-6, spacing=20.0 * 1e-3,
                    contact_angle=math.radians(math.degrees(ALPHA)))
    row = jb.catalogue("32060 X")
    c_cat = 0.45 * float(row.element_diameter) * 1e3  # µm: 0.00045 D_w
    by_catalogue = jio.parse_case(_catalogue_case(catalogue="32060 X", arrangement="O",
                                                  crown_um=c_cat)
                                  ).scene.pinion_shaft.bearings[0].rolling
    api_catalogue = jb.TaperedRollerPair.of(jb.catalogue("32060 X", crown=c_cat * 1e-6), "O")
    nu = {"kind": "cylindrical_roller", "bore_mm": 25.0, "outer_diameter_mm": 52.0,
          "width_mm": 15.0, "rollers": 13, "roller_diameter_mm": 7.0, "roller_length_mm": 8.0,
          "pitch_diameter_mm": 38.5}
    by_nu = jio.parse_case(_catalogue_case(**nu, crown_um=0.35 * 7.0)
                           ).scene.pinion_shaft.bearings[0].rolling
    api_nu = jb.catalogue("NU 205", crown=0.35 * 7.0 * 1e-6)
    assert float(by_kind.crown) == pytest.approx(2.925e-6, rel=1e-12)
    for got, want in ((by_kind, api), (by_catalogue, api_catalogue), (by_nu, api_nu)):
        assert np.array_equal(np.asarray(_load(got, d)), np.asarray(_load(want, d)))
    assert np.array_equal(np.asarray(by_kind.stiffness(d)), np.asarray(api.stiffness(d)))
    f, f0 = np.asarray(_load(by_kind, d)), np.asarray(_load(straight, d))
    assert np.max(np.abs(f - f0)) > 1e-3 * np.max(np.abs(f0))


@pytest.mark.parametrize("keys,start", [
    # 30206-sized row: D_w 6.5 mm, so c <= 65 µm
    ({"crown_um": 70.0}, ("crown_um = 70: out of range, allowed [0, 65] µm (the logarithmic "
                          "crown's scale, at most the roller diameter/100")),
    ({"crown_um": -1.0}, "crown_um = -1: out of range, allowed [0, 5000]"),
    # the 32060 X entry: D_w 40 mm, c <= 400 µm
    ({"catalogue": "32060 X", "arrangement": "O", "crown_um": 450.0},
     "crown_um = 450: out of range, allowed [0, 400] µm"),
    ({"catalogue": "6205", "crown_um": 2.0},
     ("crown_um = 2: not with catalogue = '6205' (a DeepGrooveBall, no crown): allowed on a "
      "roller kind that takes a crown")),
    ({"catalogue": "231/750 CA", "crown_um": 2.0},
     "crown_um = 2: not with catalogue = '231/750 CA' (a SphericalRoller, no crown)"),
    ({"kind": "deep_groove_ball", "bore_mm": 30.0, "outer_diameter_mm": 62.0, "width_mm": 16.0,
      "balls": 9, "ball_diameter_mm": 9.525, "pitch_diameter_mm": 46.0, "crown_um": 2.0},
     "crown_um = 2: not a key of kind = 'deep_groove_ball'"),
    ({"radial_N_per_um": 100.0, "crown_um": 2.0}, "crown_um: is a rolling bearing's key"),
])
def test_case_file_crown_um_refused_in_one_line(keys, start):
    """``crown_um`` above the roller diameter/100 (µm, the kind's or the catalogue entry's
    roller), negative, on a ball or spherical roller kind, on a linear bearing: one line
    naming the key in the file's units."""
    data = _pair_case(**keys) if "crown_um" in keys and len(keys) == 1 else _catalogue_case(
        **keys)
    with pytest.raises(ValueError) as err:
        jio.parse_case(data)
    text = str(err.value)
    assert text.startswith("[scene.pinion_shaft.bearings[0]] " + start), text
    assert "\n" not in text
