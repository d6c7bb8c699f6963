"""What makes a gear pair impossible, not fixed ranges: a profile shift beyond ±1.5 and a
transverse contact ratio below 1 are legitimate (FZG's H951 low-loss gear has both); a pointed
tip, an undercut, a tip cutting into the mating root and a total contact ratio ε_γ below 1 are
refused in one line, by the API and in a case file's words.

References: GEARpie's report of H951 (cfernandesFEUP/GEARpie@8d9b8ee REPORT/H951.txt: ε_α
0.93, ε_β 1.00, a_w 91.5 mm, tip radii 38.115/55.867 mm, root radii 35.196/52.947 mm, Z_H 2.03,
Z_ε 1.03); ISO 21771's tip clearance c = a_w − r_a1 − r_f2 and tip thickness written here."""

from __future__ import annotations

import math
import re
import tomllib

import numpy as np
import pytest

import jaxgear as jg
import jaxgear.io as jio
import jaxgear.tribology as tr
from jaxgear import cli

DEG = math.pi / 180
K_H951 = 0.581696  # GEARpie's addendum reduction k of H951 (x1 + x2 − (a_w − a)/m_n)


def _h951_pair():
    members = [
        jg.Member(z, x, 1.0 - K_H951, 1.25, 21.2418e-3, 0.25)
        for z, x in ((38, 1.6915), (57, 2.0003))
    ]
    return jg.GearPair(*members, 1.75e-3, 20 * DEG, 15 * DEG)


def test_h951_builds_with_the_published_geometry():
    """x1 = 1.69, x2 = 2.00 and ε_α = 0.93 < 1 (ε_γ 1.93): built, with GEARpie's printed
    contact ratios, centre distance, tip and root radii (to their rounding)."""
    pair = _h951_pair()
    assert pair.transverse_contact_ratio == pytest.approx(0.93, abs=0.005)
    assert pair.transverse_contact_ratio < 1.0
    assert pair.overlap_ratio == pytest.approx(1.00, abs=0.005)
    assert pair.total_contact_ratio >= 1.0
    assert pair.center_distance * 1e3 == pytest.approx(91.5, abs=5e-4)
    np.testing.assert_allclose(np.array(pair.tip_radii) * 1e3, [38.115, 55.867], atol=1e-3)
    np.testing.assert_allclose(np.array(pair.root_radii) * 1e3, [35.196, 52.947], atol=1e-3)
    # the clearances from the printed radii: a_w − r_a1 − r_f2 and a_w − r_a2 − r_f1
    np.testing.assert_allclose(
        np.array(pair.tip_root_clearances) * 1e3,
        [91.5 - 38.115 - 52.947, 91.5 - 55.867 - 35.196],
        atol=2e-3,
    )


def test_h951_embedded_case_is_built_rated_and_lubricated(tmp_path):
    """The embedded fzg-h951 loads without a warning, its rating.md prints GEARpie's values
    beside its own (ε_α, ε_β, Z_H, Z_ε agree to the report's rounding), and a contact solve
    with the case's oil gives a finite film, loss and flash temperature."""
    case = jio.load_case("fzg-h951")
    assert jio.plausibility(case) == []
    published = jio.published_rating("fzg-h951")["mesh"]
    pair = case.pair
    assert pair.transverse_contact_ratio == pytest.approx(published["eps_alpha"], abs=0.005)
    assert pair.overlap_ratio == pytest.approx(published["eps_beta"], abs=0.005)
    cli.rating_outputs(case, str(tmp_path))
    md = (tmp_path / "rating.md").read_text(encoding="utf-8")
    rows = {c[1]: c for c in (
        [x.strip() for x in line.strip("|").split("|")]
        for line in md.splitlines() if line.startswith("| ") and line.count("|") >= 6
    )}
    for symbol, key in (("ε_α", "eps_alpha"), ("Z_H", "Z_H"), ("Z_ε", "Z_epsilon")):
        ours, printed = float(rows[symbol][2].split()[0]), float(rows[symbol][3])
        assert printed == published[key]
        assert ours == pytest.approx(printed, abs=0.005 + 1e-9), symbol
    assert "S_H" in md and "S_F" in md
    # a coarse contact solve with the case's oil: film, loss and Blok's θ_fl finite
    s, k = jg.stiffness_table(pair, jg.Weber(), youngs_modulus=case.youngs_modulus,
                              poisson_ratio=case.poisson_ratio,
                              line_load=case.torque / pair.pitch_radii[0] / pair.face_width)
    res = jg.quasi_static(jg.MeshModel.from_pair(pair, s, k, 8), None, case.torque,
                          positions_per_pitch=16).mesh
    inputs = jio.tribology_of(case)
    assert inputs.speed == pytest.approx(1500 * 2 * math.pi / 60)
    trib = tr.mesh_tribology(pair, res, inputs.lubricant, case.torque, inputs.speed,
                             inputs.roughness, case.youngs_modulus, case.poisson_ratio,
                             friction=inputs.friction)
    scuff = tr.mesh_scuffing(pair, res, trib, inputs.lubricant, case.youngs_modulus,
                             case.poisson_ratio, tr.ScuffingLimits(fzg_load_stage=12))
    assert 0.99 < float(trib.efficiency) < 1.0
    assert float(trib.min_specific_film) > 0.5
    assert np.all(np.isfinite(np.asarray(scuff.flash_temperature)))
    assert 0 < float(scuff.max_flash_temperature) < 200 and float(scuff.safety_factor) > 1


# -- refusals: what makes a gear impossible -----------------------------------------------------


def _pair(p1, p2, **kw):
    return jg.GearPair(p1, p2, kw.pop("module", 2e-3), 20 * DEG, kw.pop("beta", 0.0), **kw)


def _tip_thickness(z, x, ha, beta, mn=2e-3, alpha_n=20 * DEG):
    """The transverse tip thickness s_a (m) of a rack-generated gear (ISO 21771), written
    here: s_a = d_a ((π/2 + 2 x tan α_n)/z + inv α_t − inv α_at)."""
    def inv(a):
        return math.tan(a) - a

    alpha_t = math.atan(math.tan(alpha_n) / math.cos(beta))
    r = z * mn / math.cos(beta) / 2
    rb, ra = r * math.cos(alpha_t), r + mn * (ha + x)
    aa = math.acos(rb / ra)
    return 2 * ra * ((math.pi / 2 + 2 * x * math.tan(alpha_n)) / z + inv(alpha_t) - inv(aa))


@pytest.mark.parametrize(
    "p1, p2, beta, match",
    [
        # x = 2.2 on 20 teeth, full addendum: s_a < 0 (pointed)
        (jg.Member(20, 2.2, 1.0, 1.25, 0.02), jg.Member(40, 0.0, 1.0, 1.25, 0.02), 0.0,
         r"^pinion\.addendum_coeff \(tip thickness -[\d.]+ mm: pointed tooth; lower "),
        # x = −1.6 on 30 teeth: the rack cuts below the base circle
        (jg.Member(30, -1.6, 1.0, 1.25, 0.02), jg.Member(60, 1.6, 0.4, 1.25, 0.02), 0.0,
         r"^pinion\.profile_shift \(undercut: form circle roll -"),
        # spur, short addenda: ε_α = ε_γ < 1
        (jg.Member(30, 0.0, 0.45, 1.25, 0.02), jg.Member(60, 0.0, 0.45, 1.25, 0.02), 0.0,
         r"^total contact ratio = 0\.\d+ is out of range: allowed >= 1 \(ε_α = 0\.\d+ \+ ε_β = 0"),
        # helical but too narrow: ε_α 0.8 + ε_β 0.1
        (jg.Member(30, 0.0, 0.45, 1.25, 0.004), jg.Member(60, 0.0, 0.45, 1.25, 0.004), 15 * DEG,
         r"^total contact ratio = 0\.9\d* is out of range"),
        # x1 + x2 = 1, dedenda no deeper than the addenda: the tips cut into the mating roots
        (jg.Member(40, 0.5, 1.0, 1.0, 0.02, 0.1), jg.Member(60, 0.5, 1.0, 1.0, 0.02, 0.1), 0.0,
         r"^tip-to-root clearance c1 \(pinion tip to gear root, .*allowed >= 0 \(the pinion tip "),
    ],
)
def test_impossible_gears_refused_in_one_line(p1, p2, beta, match):
    with pytest.raises(ValueError, match=match) as err:
        _pair(p1, p2, beta=beta)
    assert "\n" not in str(err.value)


def test_refusals_match_the_geometry_written_here():
    """The pointed-tip limit is where s_a (written here) crosses 0; the clearance limit where
    a_w − r_a1 − r_f2 does; both sides of each are built / refused."""
    # pointed: 20 teeth, full addendum, β 20°; s_a(x) = 0 between x = 1.0 and 2.2
    beta = 20 * DEG
    lo, hi = 1.0, 2.2
    for _ in range(40):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if _tip_thickness(20, mid, 1.0, beta) > 0 else (lo, mid)
    gear = jg.Member(200, 0.0, 0.3, 1.25, 0.02)  # a short gear tip: no interference, ε_γ>=1
    built = _pair(jg.Member(20, lo - 1e-3, 1.0, 1.25, 0.02), gear, beta=beta)
    want = _tip_thickness(20, lo - 1e-3, 1.0, beta)
    assert built.tip_thickness[0] == pytest.approx(want, rel=1e-9)
    assert 0 < built.tip_thickness[0] < 0.05 * 2e-3
    with pytest.raises(ValueError, match="pointed tooth"):
        _pair(jg.Member(20, hi + 1e-3, 1.0, 1.25, 0.02), gear, beta=beta)
    # clearance: z 40/60, x1 = x2 = x, h_a* = h_f* = 1 (c = −k m_n < 0 once x1 + x2 > 0)
    for x, ok in ((0.0, True), (0.3, False)):
        p1, p2 = (jg.Member(z, x, 1.0, 1.0, 0.02, 0.1) for z in (40, 60))
        if ok:
            pair = _pair(p1, p2)
            c = pair.center_distance - pair.tip_radii[0] - pair.root_radii[1]
            assert pair.tip_root_clearances[0] == pytest.approx(c, abs=1e-15)
            assert c > -1e-15
        else:
            with pytest.raises(ValueError, match="tip-to-root clearance"):
                _pair(p1, p2)


def _case_data(name="fzg-h951", **changes):
    data = tomllib.loads(jio.embedded_case_text(name))
    for path, value in changes.items():
        table, key = path.split("/")
        data[table][key] = value
    return data


def test_case_file_accepts_large_shifts_and_refuses_impossible_gears_in_its_words():
    """A profile shift of 1.69 and 2.0 in a case file loads (fzg-h951's own); a pointed tip, an
    undercut, a clearance below 0 and ε_γ < 1 are refused in one line naming the file's keys."""
    jio.parse_case(_case_data())
    cases = [
        ({"pinion/profile_shift": 3.0, "pinion/addendum_coeff": 1.0},
         r"^\[pinion\] addendum_coeff = 1: out of range \(tip thickness -[\d.]+ mm: pointed"),
        ({"pinion/teeth": 12, "pinion/profile_shift": 0.0, "pinion/addendum_coeff": 1.0},
         r"^\[pinion\] profile_shift = 0: out of range \(undercut: form circle roll -[\d.]+ mm"),
        ({"name": "power-helical", "pinion/addendum_coeff": 1.05, "gear/dedendum_coeff": 1.0,
          "gear/fillet_radius_coeff": 0.0},
         (r"^\[pinion\] addendum_coeff = 1\.05, \[pinion\] profile_shift = 0\.275: the pinion "
          r"tip cuts into the gear root \(tip-to-root clearance -0\.159 mm\), allowed a clearance")),
        ({"pinion/face_width_mm": 1.0, "gear/face_width_mm": 1.0},
         (r"^\[pinion\]/\[gear\] addendum_coeff, face_width_mm, \[pair\] helix_angle_deg: "
          r"total contact ratio ε_γ = 0\.\d+: out of range, allowed >= 1")),
    ]
    for change, match in cases:
        with pytest.raises(ValueError, match=match) as err:
            jio.parse_case(_case_data(**change))
        assert "\n" not in str(err.value), change


def test_thin_tip_warns_with_the_normal_tip_thickness_written_here():
    """A tip thinner than 0.2 m_n (not pointed) is built, with a one-line CaseWarning naming the
    keys and s_an = s_at cos β_a, both written here (tan β_a = tan β d_a/d)."""
    data = _case_data("power-helical", **{"pinion/profile_shift": 0.9,
                                          "pinion/addendum_coeff": 1.1,
                                          "gear/addendum_coeff": 0.6})
    mn, beta = 2.5e-3, 12 * DEG
    s_at = _tip_thickness(35, 0.9, 1.1, beta, mn, 25 * DEG)
    r = 35 * mn / math.cos(beta) / 2
    r_a = r + mn * 2.0
    s_an = s_at * math.cos(math.atan(math.tan(beta) * r_a / r))
    assert 0 < s_an < 0.2 * mn
    with pytest.warns(jio.CaseWarning):
        case = jio.parse_case(data)
    (msg,) = jio.plausibility(case)
    assert msg.startswith("[pinion] addendum_coeff = 1.1, profile_shift = 0.9: normal tip "
                          f"thickness {s_an * 1e3:.4g} mm is below 0.2 m_n = 0.5 mm")
    assert "\n" not in msg
    assert jio.plausibility(jio.parse_case(_case_data("power-helical"))) == []


@pytest.mark.slow
def test_h951_runs_end_to_end(tmp_path):
    """``jaxgear run fzg-h951``: the contact solve, the ISO 6336 rating and the tribology with
    scuffing on a pair with ε_α < 1, every output finite (no NaN or Infinity in its files)."""
    from jaxgear.cli.run import run_case

    case = jio.load_case("fzg-h951")
    summary = run_case(case, str(tmp_path), show_progress=False)
    assert summary["geometry"]["transverse_contact_ratio"] == pytest.approx(0.93, abs=0.005)
    s_h = summary["rating"]["pitting"]["S_H"]
    assert all(1.0 < s < 2.0 for s in s_h)
    trib = summary["tribology"]
    assert 0.99 < trib["efficiency"] < 1.0 and trib["scuffing"]["scuffing_safety_factor"] > 1
    for f in tmp_path.iterdir():
        if f.suffix in (".json", ".csv", ".md"):
            text = f.read_text(encoding="utf-8")
            assert not re.search(r"\b(NaN|nan|-?Infinity|-?inf)\b", text), f.name
