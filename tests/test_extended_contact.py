"""Contact beyond the theoretical path (docs/extended-contact.md): the tip-corner gap against an
independent placement of the teeth by their thickness (ISO 21771), its limits, and what the
extended cells change in the quasi-static and dynamic solves."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from _corner import ring_pair

import jaxgear as jg
import jaxgear.io as jio


def _pair(z1=20, z2=40, m=0.004, x1=0.0, x2=0.0, b=0.02):
    return jg.GearPair(
        jg.Member(teeth=z1, face_width=b, profile_shift=x1),
        jg.Member(teeth=z2, face_width=b, profile_shift=x2),
        normal_module=m,
        normal_pressure_angle=math.radians(20.0),
    )


def _psi(pair, member, r):
    """The half angle from a tooth's centre line to its involute flank at radius r (ISO 21771:
    s_t/(2 r_p) + inv α_t − inv α_r), written here from the tooth thickness."""
    rp, rb = pair.pitch_radii[member], pair.base_radii[member]
    at = pair.transverse_pressure_angle
    ar = np.arccos(rb / np.asarray(r))
    inv = lambda a: np.tan(a) - a  # noqa: E731
    return pair.reference_thickness[member] / (2 * rp) + inv(at) - inv(ar)


def _thickness_gap(pair, s):
    """The approach (m) that closes the gap at base-plane coordinate ``s`` < 0 of an external
    pair, from the teeth placed by their thickness: at s = 0 the gear's tip corner touches the
    pinion's flank at the engagement point A (both drive flanks on the side at angle c + ψ(r),
    the pinion turning counter-clockwise, the gear clockwise); rigid conjugate motion turns them
    by s/r_b1 and −s/r_b2; the pinion then turns by Δ until its flank reaches the corner."""
    a = pair.operating_pressure_angle
    rb1, rb2 = pair.base_radii
    ra2 = pair.tip_radii[1]
    O2 = np.array([pair.center_distance, 0.0])
    t = np.array([math.sin(a), math.cos(a)])
    A = rb1 * np.array([math.cos(a), -math.sin(a)]) + pair.start_roll * t
    c1 = math.atan2(A[1], A[0]) - _psi(pair, 0, np.hypot(*A))
    c2 = math.atan2(A[1] - O2[1], A[0] - O2[0]) - _psi(pair, 1, ra2)
    out = []
    for si in np.atleast_1d(s):
        c1s, c2s = c1 + si / rb1, c2 - si / rb2
        ang = c2s + _psi(pair, 1, ra2)
        P = O2 + ra2 * np.array([math.cos(ang), math.sin(ang)])
        delta = math.atan2(P[1], P[0]) - c1s - _psi(pair, 0, np.hypot(*P))
        out.append(rb1 * delta)
    return np.array(out)


@pytest.mark.parametrize("shift", [(0.0, 0.0), (0.3, -0.1)])
def test_corner_gap_matches_teeth_placed_by_thickness(shift):
    pair = _pair(x1=shift[0], x2=shift[1])
    pb = pair.base_pitch
    s = -np.array([1e-3, 0.01, 0.05, 0.1, 0.15]) * pb
    contact = jg.CornerContact(pair, s)
    assert np.all(contact.on_flank)
    ref = _thickness_gap(pair, s)
    np.testing.assert_allclose(contact.gap, ref, rtol=1e-9, atol=1e-15)


def test_corner_gap_vanishes_at_the_path_ends_quadratically():
    # conjugate action: on the line of action the corner's velocity relative to the mating flank
    # is tangent to it, so the gap grows as the square of the distance from the path's ends
    for pair in (_pair(), _pair(z1=17, z2=71, x1=0.4, x2=0.2)):
        g, pb = pair.path_of_contact, pair.base_pitch
        for ends, sign in ((0.0, -1.0), (g, 1.0)):
            h = np.array([1e-4, 2e-4]) * pb
            gap = jg.CornerContact(pair, ends + sign * h).gap
            assert np.all(gap > 0)
            assert gap[1] / gap[0] == pytest.approx(4.0, rel=1e-3)
            assert jg.CornerContact(pair, ends + sign * 1e-9 * pb).gap < 1e-15


def test_internal_corner_gap_positive_and_quadratic():
    ring = ring_pair()
    g, pb = ring.path_of_contact, ring.base_pitch
    span, table = jg.extension_table(ring)
    assert min(span) > 0.02 * pb
    for ends, sign in ((0.0, -1.0), (g, 1.0)):
        h = np.array([1e-4, 2e-4]) * pb
        gap = jg.CornerContact(ring, ends + sign * h).gap
        assert np.all(gap > 0) and gap[1] / gap[0] == pytest.approx(4.0, rel=1e-3)
    assert np.all(np.diff(table, axis=1) > 0)  # the gap grows away from the path


def _mesh(pair, extended, slices=4, stiffness=None):
    s, k = jg.stiffness_table(pair, jg.Weber() if stiffness is None else stiffness)
    return jg.MeshModel.from_pair(
        pair, s, k, slices, contact_geometry=jg.BeyondPath() if extended else jg.TheoreticalPath()
    )


def test_zero_load_extended_path_is_the_theoretical_one():
    pair = _pair()
    torque = 1e-6  # N·m: the approach (~1e-13 m) closes no corner gap beyond a micrometre
    r0 = jg.quasi_static(_mesh(pair, False), jg.Modifications(), torque, positions_per_pitch=32)
    r1 = jg.quasi_static(_mesh(pair, True), jg.Modifications(), torque, positions_per_pitch=32)
    te0 = np.asarray(r0.meshes[0].transmission_error)
    te1 = np.asarray(r1.meshes[0].transmission_error)
    np.testing.assert_allclose(te1, te0, rtol=1e-9)


def test_enough_tip_relief_leaves_no_offline_contact():
    pair = _pair()
    mods = jg.Modifications(
        pinion=jg.MemberModification(tip_relief_depth=40e-6, tip_relief_extent=0.3),
        gear=jg.MemberModification(tip_relief_depth=40e-6, tip_relief_extent=0.3),
    )
    r0 = jg.quasi_static(_mesh(pair, False), mods, 300.0, positions_per_pitch=32)
    r1 = jg.quasi_static(_mesh(pair, True), mods, 300.0, positions_per_pitch=32)
    np.testing.assert_allclose(
        np.asarray(r1.meshes[0].transmission_error),
        np.asarray(r0.meshes[0].transmission_error),
        rtol=1e-9,
    )
    ll = np.asarray(r1.meshes[0].line_load)
    s = np.asarray(r1.meshes[0].cell_s)
    outside = (s < 0) | (s > pair.path_of_contact)
    assert np.all(ll[outside] == 0.0)


def test_loaded_teeth_touch_before_the_start_and_after_the_end():
    pair = _pair()
    r = jg.quasi_static(_mesh(pair, True), jg.Modifications(), 400.0, positions_per_pitch=128)
    ll = np.asarray(r.meshes[0].line_load)
    s = np.asarray(r.meshes[0].cell_s)
    loaded = ll > 0
    assert s[loaded].min() < -0.02 * pair.base_pitch
    assert s[loaded].max() > pair.path_of_contact + 0.02 * pair.base_pitch
    # the extension is wide enough: the farthest cells stay open
    span = _mesh(pair, True).extension_span
    assert s[loaded].min() > -0.8 * float(span[0])


def test_loaded_path_ends_and_the_relief_that_clears_them():
    pair = _pair()
    mesh = _mesh(pair, True)
    torques = np.array([1e-3, 100.0, 400.0])
    hm = jg.loaded_path(mesh, None, torques, positions_per_pitch=256)
    step = pair.base_pitch / 256
    # at (almost) zero load the loaded path is the theoretical one, within a position's roll
    assert -step <= float(hm.start[0]) <= step
    assert abs(float(hm.end[0]) - pair.path_of_contact) <= step
    # the extension grows with the load, the relief with it
    assert np.all(np.diff(np.asarray(hm.start)) < 0) and np.all(np.diff(np.asarray(hm.end)) > 0)
    assert np.all(np.diff(np.asarray(hm.relief_start)) > 0)
    # the relief read off the map: a short linear tip relief of the gear a little deeper keeps
    # the driven tip off the pinion at that torque; a little shallower does not
    T, E = 400.0, float(hm.relief_start[-1])

    def start_with(depth):
        gear = jg.MemberModification(tip_relief_depth=depth, tip_relief_extent=0.05)
        r = jg.quasi_static(mesh, jg.Modifications(gear=gear), T, positions_per_pitch=256)
        on = np.asarray(r.meshes[0].line_load) > 0
        return np.asarray(r.meshes[0].cell_s)[on].min()

    assert start_with(1.02 * E) >= -1e-12
    assert start_with(0.9 * E) < 0.0


def test_internal_mesh_and_the_smooth_law_reach_beyond_the_path():
    ring = ring_pair()
    mesh = _mesh(ring, True, stiffness=jg.ISO6336())
    lp = jg.loaded_path(mesh, None, np.array([50.0, 600.0]), positions_per_pitch=128)
    assert float(lp.start[-1]) < -0.01 * ring.base_pitch
    assert float(lp.end[-1]) > ring.path_of_contact + 0.01 * ring.base_pitch
    assert float(lp.start[-1]) < float(lp.start[0])
    # the smooth law (a softplus ramp of width w) tends to the exact one: TE within a few w
    w = 1e-8
    exact = jg.quasi_static(mesh, None, 600.0, positions_per_pitch=64)
    smooth = jg.quasi_static(
        mesh, None, 600.0, contact=jg.SmoothContact(width=w), positions_per_pitch=64
    )
    te_e = np.asarray(exact.meshes[0].transmission_error)
    te_s = np.asarray(smooth.meshes[0].transmission_error)
    assert np.max(np.abs(te_s - te_e)) < 5 * w


def test_load_map_covers_the_loaded_extension():
    pair = _pair()
    r = jg.quasi_static(_mesh(pair, True), None, 400.0, positions_per_pitch=64)
    edges, z, grid = jg.load_map(r.meshes[0], 64, pair.base_pitch, pair.path_of_contact)
    s = np.asarray(r.meshes[0].cell_s)
    on = np.asarray(r.meshes[0].line_load) > 0
    assert edges[0] <= s[on].min() < edges[0] + pair.base_pitch / 64 * 1.01
    assert edges[-1] >= s[on].max() > edges[-1] - pair.base_pitch / 64 * 1.01
    assert np.all(np.isfinite(grid))
    # without the extension the map is the theoretical path's
    r0 = jg.quasi_static(_mesh(pair, False), None, 400.0, positions_per_pitch=64)
    e0, _, _ = jg.load_map(r0.meshes[0], 64, pair.base_pitch, pair.path_of_contact)
    assert e0[0] == 0.0 and e0[-1] == pytest.approx(pair.path_of_contact, rel=1e-12)


def test_contact_at_the_end_of_the_extension_fails_loudly():
    pair = _pair()
    mesh = _mesh(pair, True)
    r = jg.quasi_static(mesh, None, 8000.0, positions_per_pitch=32, throw=False)
    assert jg.ContactResult.beyond_extension in set(np.asarray(r.result).tolist())
    with pytest.raises(Exception, match="end of the cells beyond the theoretical path"):
        jg.quasi_static(mesh, None, 8000.0, positions_per_pitch=32)
    ok = jg.quasi_static(mesh, None, 400.0, positions_per_pitch=32, throw=False)
    assert set(np.asarray(ok.result).tolist()) == {0}


def _fe_record():
    import json
    import pathlib

    path = pathlib.Path(__file__).resolve().parents[1] / "docs/bench/extended_contact_fe.json"
    return json.loads(path.read_text())


def _entering_share(mesh, pair, torque, s_rows):
    """The share of the total load on the contact line at base-plane coordinate s, at the
    pinion angles θ = s / r_b1 (the line that enters at s = 0, or leaves at s = g_α)."""
    s = np.asarray(s_rows)
    r = jg.quasi_static(mesh, None, torque, theta=s / pair.base_radii[0])
    ll = np.asarray(r.meshes[0].line_load)[:, :, 0]
    cs = np.asarray(r.meshes[0].cell_s)[:, :, 0]
    k = np.argmin(np.abs(cs - s[:, None]), axis=1)
    return ll[np.arange(len(k)), k] / ll.sum(axis=1)


def test_against_the_plane_strain_fe_contact_reference():
    # benchmarks/extended_contact_fe.py: the unmodified accessory pair in 2-D plane strain (five
    # P2 teeth a member on their rims, exact unilateral contact on the generated forms, gaps by
    # node-to-segment search), written separately; here the case's own Weber stiffness
    fe = _fe_record()
    text = jio.embedded_case_text("accessory-spur").replace("depth_um = 15.0", "depth_um = 0.0")
    text = _extended_case_text(text[: text.index("[scene]")], True)
    case = jio.parse_case(__import__("tomllib").loads(text), "accessory-unmodified")
    pair, mesh = case.pair, case.mesh_model(slices=1)
    g = pair.path_of_contact
    assert fe["geometry"]["path_of_contact_m"] == pytest.approx(g, rel=1e-9)
    for record in fe["torques"]:
        T = record["torque_Nm"]
        lp = jg.loaded_path(mesh, None, np.array([T]), positions_per_pitch=1024)
        # the start and the end of contact within 2 % of the engagement interval g_α
        assert float(lp.start[0]) == pytest.approx(record["s_start_mm"] * 1e-3, abs=0.02 * g)
        assert float(lp.end[0]) - g == pytest.approx(
            record["s_end_minus_g_alpha_mm"] * 1e-3, abs=0.02 * g
        )
        # the entering pair's share of the load within 0.05 across the engagement, the leaving
        # pair's within 0.06
        for rows, tol in ((record["approach"], 0.05), (record["recess"], 0.06)):
            s = np.array([row["s_mm"] for row in rows]) * 1e-3
            share = np.array([row["share"] for row in rows])
            np.testing.assert_allclose(_entering_share(mesh, pair, T, s), share, atol=tol)


# --- the dynamic factor of unmodified teeth at quasi-static speeds (the evidence) -------
# References: at a mesh frequency far below the first mode the response is quasi-static, DF = 1
# (the criterion: within 15 % below a fifth of the first mode); a load that steps onto a
# lightly damped oscillator overshoots to twice its static deflection (the undamped step
# response, x_max = 2 F/k), which the theoretical path's engagement step approaches.


def _extended_case_text(text: str, extended: bool) -> str:
    out, n = re.subn(
        r"^\[mesh\]$",
        f"[mesh]\nextended_contact = {str(extended).lower()}",
        text,
        flags=re.MULTILINE,
    )
    assert n == 1
    return out


def _unmodified_spur_torsional(extended: bool):
    import tomllib

    text = jio.embedded_case_text("accessory-spur")
    text, n = re.subn(r"depth_um = 15\.0", "depth_um = 0.0", text, count=1)  # no tip relief
    assert n == 1
    # the model built on the run's 4096 positions per mesh period: the run below takes the
    # rows the build holds (one table and static solve compiled, not two)
    text = text[: text.index("[scene]")] + '[scene]\nmodel = "torsional"\n'
    text += "[scene.integration]\nsteps_per_period = 4096\n"
    case = jio.parse_case(tomllib.loads(_extended_case_text(text, extended)))
    return case, jio.build_dynamic_model(case, slices=2)[0]


def _first_elastic_mode(model) -> float:
    import jaxgear.dynamics as jd

    modes = jd.mesh_averaged_modes(model)
    return float(np.asarray(modes.frequency)[~np.asarray(modes.rigid)][0])


def test_unmodified_spur_dynamic_factor_at_20_hz_mesh_frequency():
    import jaxgear.dynamics as jd

    df = {}
    for extended in (False, True):
        case, model = _unmodified_spur_torsional(extended)
        f1 = _first_elastic_mode(model)
        f_mesh = 20.0  # Hz: far below a fifth of the torsional mode (6.4 to 7 kHz)
        assert f_mesh < f1 / 5
        speed = 2 * np.pi * f_mesh / case.pair.pinion.teeth
        # 4096 steps per mesh period resolve the mode's ringing (~15 steps per its period);
        # the run starts from the static equilibrium, two periods suffice at this damping
        r = jd.simulate(
            model,
            speed,
            integrator=jd.Newmark(steps_per_period=4096),
            window=jd.SteadyState(periods=2, keep_periods=2),
        )
        df[extended] = float(r.dynamic_factor)
    assert abs(df[True] - 1.0) <= 0.15, df  # quasi-static: DF -> 1
    assert df[False] >= 1.5, df  # the engagement step on the theoretical path rings


@pytest.mark.slow
def test_nrel_planetary_dynamic_factor_at_quarter_rad_per_s(tmp_path):
    import jaxgear.dynamics as jd

    speed = 0.25  # rad/s on the carrier: mesh frequency 2.2 Hz, the first mode 63 Hz
    out = {}
    for extended in (False, True):
        path = tmp_path / f"planetary_{int(extended)}.toml"
        path.write_text(_extended_case_text(jio.embedded_case_text("nrel-5mw-planetary"), extended))
        model, _ = jio.build_dynamic_model(jio.load_case(path))
        f1 = _first_elastic_mode(model)
        assert speed / float(model.mesh_period_angle()) < f1 / 5
        r = jd.speed_sweep(model, np.array([speed]))
        sun, ring = r.results.dynamic_factors
        out[extended] = np.array([np.max(np.asarray(sun)), np.max(np.asarray(ring))])
    np.testing.assert_allclose(out[True], 1.0, atol=0.15)  # quasi-static
    np.testing.assert_allclose(out[False], 2.0, atol=0.15)  # the undamped step's overshoot
