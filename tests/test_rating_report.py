"""``rating.md`` as a rating report a reviewer signs: its rows and numbers
against independent values (the case file's inputs and ISO 6336's formulas written here), a
clause on every row of the rating's tables, the edition and its unconfirmed factors, S_H and
S_F against S_Hmin and S_Fmin with their verdicts, the NREL stages' published column against
the KISSsoft values as tests/test_rating_kisssoft.py types them, one notation, the measured
factors with where they come from and whether they are comparable with ISO's, and the page
docs/rating.md describing the report's sections."""

from __future__ import annotations

import math
import re
import tomllib
from pathlib import Path

import numpy as np
import pytest
from test_rating_kisssoft import RING_REPORTS, SPUR_REPORTS, STAGE_03_PRINTED

import jaxgear as jg
import jaxgear.io as jio
from jaxgear import cli

# the contact model a stub measured row states (jaxgear.rating.contact_model's words)
CONTACT = "stub contact model"

ROOT = Path(__file__).resolve().parents[1]
#: the report's sections (a pair's "##" headings), in order
SECTIONS = ["Input data", "Material", "Lubrication and roughness", "Accuracy",
            "Life and load cycles", "Operating point", "Load factors", "Pitting (ISO 6336-2)",
            "Bending (ISO 6336-3)", "Safety against the required minimum"]


def _report(name: str, tmp_path, data: dict | None = None) -> str:
    """rating.md of a pair case (embedded ``name``, or its parsed TOML ``data``) as
    jaxgear run's rating step writes it (no measured factors)."""
    case = jio.load_case(name) if data is None else jio.parse_case(data)
    cli.rating_outputs(case, str(tmp_path))
    return (tmp_path / "rating.md").read_text(encoding="utf-8")


def _rows(md: str) -> dict[str, list[str]]:
    """Each table row's cells by its symbol (the second cell; the first one seen)."""
    out = {}
    for line in md.splitlines():
        if line.startswith("| ") and not line.startswith(("| quantity", "| symbol", "|---",
                                                          "| safety factor |")):
            cells = [c.strip() for c in line.strip("|").split("|")]
            out.setdefault(cells[1], cells)
    return out


def _num(cell: str) -> list[float]:
    """The number(s) of a value cell ("1.500 / 1.531", "1.250 (given)")."""
    return [float(x) for x in re.findall(r"-?\d+(?:\.\d+)?(?:e[+-]\d+)?", cell.split("(")[0])]


def test_every_row_of_the_rating_tables_names_its_clause(tmp_path):
    """Every row of the rating's tables (both editions) names its reference: an input's
    geometry standard (ISO 21771) or the ISO 6336 part, edition and a clause number (this
    edition's, or the other's labelled with its year, "(2006 ed. 6.1)"); the K_v, K_Hβ rows
    2019's clauses 6, 7; Z_H 2006's 6.1; the report says which edition."""
    clause = re.compile(r"ISO 6336-[1235](:\d{4})? (\((in )?\d{4} ed\. |in )?\d+(\.\d+)?")
    for name, year in (("power-helical", "2019"), ("nrel-5mw-stage3", "2006")):
        md = _report(name, tmp_path)
        assert f"Edition: ISO 6336-1, -2 and -3:{year}, method B" in md
        n = 0
        for line in md.splitlines():
            if line.startswith("| ") and not line.startswith(("| quantity", "| safety factor",
                                                              "|---")):
                last = line.strip("|").split("|")[-1].strip()
                # an input, a geometry value from the inputs, a row reported only (the
                # material's name and hardness), the [lubricant] oil, or an ISO 6336 clause
                assert last.startswith(("ISO 21771 (", "reported only", "[lubricant]")) or (
                    clause.search(last)), line
                n += 1
        assert n > 60
        rows = _rows(md)
        k_v, z_h = rows["K_v"][-1], rows["Z_H"][-1]
        if year == "2019":
            assert k_v == "ISO 6336-1:2019 6" and z_h == "ISO 6336-2:2019 (2006 ed. 6.1)"
            assert rows["K_Hβ"][-1] == "ISO 6336-1:2019 7"
        else:
            assert k_v == "ISO 6336-1:2006 (2019 ed. 6)" and z_h == "ISO 6336-2:2006 6.1"
            assert rows["Y_F"][-1] == "ISO 6336-3:2006 6.2"


def test_edition_and_its_unconfirmed_factors_are_stated(tmp_path):
    """The 2019 edition (the default) names Y_β's 1/cos³β term as unconfirmed by a published
    worked example; the 2006 edition: none."""
    md19 = _report("power-helical", tmp_path)
    line = next(x for x in md19.splitlines() if x.startswith("Factors whose formula"))
    assert "Y_β" in line and "1/cos³β" in line and "2019" in line
    md06 = _report("nrel-5mw-stage3", tmp_path)
    assert "Factors whose formula no published worked example confirms: none." in md06


def test_power_helical_rows_against_the_case_file_and_iso_formulas(tmp_path):
    """power-helical's report (2019, K_A 1.25, class 5) against its case file and ISO 6336's
    formulas written here, each to the report's four significant digits: the input data (m_n
    2.5 mm, z 35/68, b 40 mm, x, β 12°, α_n 25°, u), the material (σ_Hlim 1500, σ_Flim 500,
    E 210 000 N/mm², ν 0.3), lubrication (ν₄₀ 25, R_z 2/10 µm), life 5000 h and
    N_L = 60 n L_h (the gear's /u), the operating point (T₁ 310 N·m, n₁ 28 648 1/min,
    P = T ω, F_t = 2T/d₁ with d₁ = z₁ m_n/cos β, v = ω d₁/2), K_Hβ's intermediates (F_m/b =
    F_t K_A K_v/b; K_Hβ = 1 + F_βy c_γβ/(2 F_m/b) with c_γβ = 0.85 c_γα), B_k = |1 − c' C_a/
    (F_t K_A/b)| from its printed c' and C_a, N_F = (b/h)²/(1 + b/h + (b/h)²), and the
    sections in order."""
    md = _report("power-helical", tmp_path)
    assert [x[3:] for x in md.splitlines() if x.startswith("## ")] == SECTIONS
    r = _rows(md)

    def close(symbol, want, rel=6e-4):
        got = _num(r[symbol][2])
        assert got == pytest.approx(np.broadcast_to(want, (len(got),)).tolist(), rel=rel), (
            symbol, got, want)

    close("m_n", 2.5)
    assert r["z"][2] == "35 / 68"
    close("b", 40.0)
    close("x", [0.275, 0.317])
    close("β", 12.0)
    close("α_n", 25.0)
    close("u", 68 / 35)
    close("σ_Hlim", 1500.0)
    close("σ_Flim", 500.0)
    close("E", 210000.0)
    close("ν", 0.3)
    close("ν₄₀", 25.0)
    assert _num(r["R_z"][2]) == [2.0, 2.0]  # flank (the first R_z row)
    assert "| root roughness | R_z | 10.00 / 10.00 | µm |" in md
    assert "| flank tolerance class | A | 5 |" in md
    close("L_h", 5000.0)
    n1 = 28648.0
    close("N_L", [60 * n1 * 5000, 60 * n1 * 5000 / (68 / 35)], rel=1e-3)
    omega = n1 * 2 * math.pi / 60
    d1 = 35 * 2.5e-3 / math.cos(math.radians(12.0))
    f_t = 2 * 310.0 / d1
    close("T₁", 310.0)
    close("n₁", n1)
    close("P", 310.0 * omega / 1e3)
    close("F_t", f_t)
    close("v", omega * d1 / 2)
    k_a, k_v = _num(r["K_A"][2])[0], _num(r["K_v"][2])[0]
    assert k_a == 1.25
    close("F_m/b", f_t * k_a * k_v / 40.0, rel=1e-3)  # N/mm
    f_by, c_gb, c_ga = _num(r["F_βy"][2])[0], _num(r["c_γβ"][2])[0], _num(r["c_γα"][2])[0]
    assert c_gb == pytest.approx(0.85 * c_ga, rel=1e-3)
    close("K_Hβ", 1 + f_by * c_gb / (2 * _num(r["F_m/b"][2])[0]), rel=1e-3)
    c1, ca = _num(r["c'"][2])[0], _num(r["C_a"][2])[0]
    close("B_k", abs(1 - c1 * ca / (f_t * k_a / 40.0)), rel=2e-3)
    h = (2.5 * (0.976 + 1.262))  # the smaller tooth depth (the gear's 0.970 + 1.268 is equal)
    bh = max(40.0 / h, 3.0)
    close("N_F", bh**2 / (1 + bh + bh**2), rel=2e-3)
    close("K_Fβ", _num(r["K_Hβ"][2])[0] ** (bh**2 / (1 + bh + bh**2)), rel=1e-3)
    assert "| S_H | 1.555 / 1.587 | S_Hmin = 1.000 | pass / pass |" in md


def test_verdicts_follow_s_against_s_min(tmp_path):
    """S_Hmin between the two gears' S_H (1.555 / 1.587 on power-helical) fails the pinion
    alone; S_Fmin above both S_F fails both; the permissible stresses are σ_G/S_min."""
    d = tomllib.loads(jio.embedded_case_text("power-helical"))
    d["rating"].update(min_safety_pitting=1.57, min_safety_bending=2.5)
    md = _report("", tmp_path, d)
    assert "| S_H | 1.555 / 1.587 | S_Hmin = 1.570 | FAIL / pass |" in md
    assert "| S_F | 2.419 / 2.378 | S_Fmin = 2.500 | FAIL / FAIL |" in md
    r = _rows(md)
    hg, hp = _num(r["σ_HG"][2]), _num(r["σ_HP"][2])
    assert hp == pytest.approx([x / 1.57 for x in hg], rel=1e-3)


def test_nrel_published_column_is_the_kisssoft_reports(tmp_path):
    """nrel-5mw-stage3's published column carries the report's printed values as
    tests/test_rating_kisssoft.py types them (every symbol the report table has a row of),
    beside ours within the tests' 0.5 %; nrel-5mw-stage2's two meshes (the planetary rating,
    K_γ of the case) likewise with its two reports' rows (the ring's root section aside, its
    known gap). A case without a published report has no such column."""
    md = _report("nrel-5mw-stage3", tmp_path)
    assert "@NREL_5MW/stage_03.rtf" in md and "| published |" in md
    r = _rows(md)
    by_name = {"Y_F": "Y_F", "Y_S": "Y_S", "Y_beta": "Y_β", "sigma_F0 (N/mm2)": "σ_F0",
               "sigma_F (N/mm2)": "σ_F", "Y_NT": "Y_NT", "sigma_FP (N/mm2)": "σ_FP",
               "S_F": "S_F", "Z_H": "Z_H", "Z_E": "Z_E", "Z_eps": "Z_ε", "Z_beta": "Z_β",
               "sigma_H0 (N/mm2)": "σ_H0", "sigma_H (N/mm2)": "σ_H", "Z_L": "Z_L", "Z_v": "Z_v",
               "Z_R": "Z_R", "Z_NT": "Z_NT", "sigma_HP (N/mm2)": "σ_HP", "S_H": "S_H",
               "K_Fbeta": "K_Fβ", "eps_alpha": "ε_α", "eps_beta": "ε_β",
               "sigma_HG (N/mm2)": "σ_HG", "sigma_FG (N/mm2)": "σ_FG", "Y_X": "Y_X"}
    for name, printed, _ in STAGE_03_PRINTED:
        if name not in by_name:
            continue
        cells = r[by_name[name]]
        assert _num(cells[3]) == pytest.approx(np.atleast_1d(printed).tolist(), rel=1e-12), name
        assert _num(cells[2]) == pytest.approx(_num(cells[3]), rel=5e-3), name
    assert "| published |" not in _report("power-helical", tmp_path)

    from jaxgear.cli.planetary import rating_section

    case = jio.load_case("nrel-5mw-stage2")
    rating_section(case, str(tmp_path), 1.10)
    md2 = (tmp_path / "rating.md").read_text(encoding="utf-8")
    assert md2.count("@NREL_5MW/stage_02.rtf") == 2
    meshes = md2.split("## nrel-5mw-stage2, mesh ")[1:]
    assert [m.split(":")[0] for m in meshes] == ["sun2-planet2", "planet2-ring2"]
    for text, rows in zip(meshes, (SPUR_REPORTS[0][-1], RING_REPORTS[0][-1]), strict=True):
        r = _rows(text)
        for name, sym in (("S_H", "S_H"), ("Z_NT", "Z_NT"), ("sigma_H0", "σ_H0"),
                          ("Y_M", "Y_M"), ("sigma_FG", "σ_FG")):
            printed = next(p for n, p, _ in rows if n == name)
            assert _num(r[sym][3]) == pytest.approx(np.atleast_1d(printed).tolist()), name
            assert _num(r[sym][2]) == pytest.approx(_num(r[sym][3]), rel=5e-3), name
        assert "| K_γ | 1.100 (given) |" in text


def test_one_notation_and_number_format(tmp_path):
    """ISO's symbols (K_Hβ, not K_Hbeta) in every row, measured ones included (a rigid mesh's
    K_Hβ and K_Hα measured on power-helical); every value cell of the rating's tables in four
    significant digits."""
    import jaxgear as jg

    case = jio.load_case("power-helical")
    res = jg.quasi_static(case.mesh_model(slices=8), case.modifications, case.torque,
                          positions_per_pitch=8)
    cli.rating_outputs(case, str(tmp_path), res)
    md = (tmp_path / "rating.md").read_text(encoding="utf-8")
    assert re.search(r"K_[HF](beta|alpha)", md) is None
    assert "| K_Hβ measured | " in md and "| K_Hα measured | " in md
    for line in md.splitlines():
        if line.startswith("| ") and " N/mm² |" in line and "σ_" in line:
            for x in re.findall(r"\b\d+\.\d+\b", line.split("|")[3]):
                assert len(x.replace(".", "").lstrip("0")) == 4, line


def test_measured_k_v_far_below_the_first_mode_is_not_comparable():
    """A planetary stage's measured K_v says where it comes from and whether it is comparable
    with ISO's: at mesh frequencies 2–13 Hz with the first mode at 100 Hz (the NREL stage 1's
    situation) "not comparable", naming the entering pair; at 80 Hz "comparable". The sweep's
    own summary carries the same caveat for its dynamic factors and dynamic K_γ."""
    from jaxgear.cli.planetary import measured_k_v

    sharing = {"planar": {"sun_mesh_forces_N": [1.0, 1.0], "ring_mesh_forces_N": [1.0, 1.0]}}
    sweep = {"speeds_rad_s": [1.0, 2.0], "mesh_names": ["s1", "s2", "r1", "r2"],
             "dynamic_factor_mesh": [[2.0, 2.0, 1.5, 1.5], [2.0, 2.0, 1.5, 1.5]],
             "model": "planar", "ring_model": "rigid", "mesh_frequency_Hz": [2.0, 13.0],
             "natural_frequencies_Hz": [100.0, 200.0]}
    k = measured_k_v(sweep, 1.5, sharing, CONTACT)
    assert k[0]["comparable"] is False and k[0]["note"].startswith("not comparable")
    assert "entering contact" in k[0]["note"] and "7.500 Hz" in k[0]["note"]
    sweep["mesh_frequency_Hz"] = [60.0, 100.0]
    k = measured_k_v(sweep, 1.5, sharing, CONTACT)
    assert k[0]["comparable"] is True and k[0]["note"].startswith("comparable")


def test_docs_describe_the_report(tmp_path):
    """docs/rating.md's description of rating.md names each of its sections, the published
    column, the verdict and the unconfirmed-factor line, as the report has them."""
    text = (ROOT / "docs" / "rating.md").read_text(encoding="utf-8")
    start = text.index("## The rating report")
    part = text[start:text.index("\n## ", start + 5)]
    for s in SECTIONS:
        assert f"**{s}**" in part, s
    for words in ("published", "pass", "FAIL", "Factors whose formula", "↳",
                  "comparable with ISO's"):
        assert words in part, words
    md = _report("nrel-5mw-stage3", tmp_path)
    for words in ("published", "pass", "Factors whose formula", "↳"):
        assert words in md


def test_pair_measured_k_v_says_whether_it_is_comparable(tmp_path):
    """A pair's measured K_v (a speed sweep's dynamic factor at the rating speed) carries
    ``comparable`` and ``note`` from its mesh frequency z₁ n₁ against ISO 6336-1's mesh
    resonance z₁ n_E1 (f_mesh/f_E1 = ISO's N): nrel-5mw-stage3 at N = 0.419 (ISO's
    ↳ row) not comparable on the theoretical path, comparable with contact beyond it,
    power-helical at N = 3.54 comparable; rating.md prints the note in its K_v measured row."""
    # far below resonance on the theoretical path not comparable; with contact beyond it (the
    # case files' default) comparable (docs/extended-contact.md)
    for name, n_iso, extended, comparable in (("nrel-5mw-stage3", 0.4188, False, False),
                                              ("nrel-5mw-stage3", 0.4188, True, True),
                                              ("power-helical", 3.542, True, True)):
        case = jio.load_case(name).replace(
            contact_geometry=jg.BeyondPath() if extended else jg.TheoreticalPath()
        )
        out = tmp_path / f"{name}-{extended}"
        out.mkdir()
        summary = {"rating": cli.rating_outputs(case, str(out))}
        speed = float(jio.ratings_of(case)[0].operating.speed)
        dynamics = {"speeds_rad_s": [0.5 * speed, 2 * speed], "dynamic_factor": [1.3, 1.3],
                    "model": "stub", "slices": 2}
        cli.measured_dynamic_factor(case, str(out), summary, dynamics)
        k_v = summary["rating"]["measured"]["K_v"]
        assert k_v["value"] == pytest.approx(1.3) and k_v["comparable"] is comparable
        z1 = case.pair.pinion.teeth
        f_mesh = z1 * speed / (2 * math.pi)
        m = re.search(r"mesh frequency ([\d.e+]+) Hz = ([\d.]+) × ", k_v["note"])
        assert float(m[1]) == pytest.approx(f_mesh, rel=5e-4)
        assert float(m[2]) == pytest.approx(n_iso, rel=5e-4)
        assert k_v["note"].startswith("comparable" if comparable else "not comparable")
        md = (out / "rating.md").read_text(encoding="utf-8")
        assert "| K_v measured | 1.300 | " in md and k_v["note"] in md
