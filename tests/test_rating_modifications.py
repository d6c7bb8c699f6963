"""One design for the rating and the optimiser: the rating reads ISO 6336-1's
tip relief C_a (K_v) and crowning C_β (K_Hβ) from the case's ``[modifications]`` (``[rating]
tip_relief_um`` an override), states them and their source in ``rating.md``; the least_safety
objective rates each design with its own relief and crowning and ISO's K_Hα, so that on
power-helical it no longer removes the tip relief that the TE objective keeps; ``jaxgear
optimise --write NEW.toml`` writes the optimum as a case file that loads back with the optimum's
modifications.

References: ISO 6336-1 clause 6 (C_a of K_v's B_k; the running-in C_ay = (σ_Hlim/97 − 18.45)²/18
+ 1.5 µm), clause 7 (K_Hβ = 1 + F_βy c_γβ/(2 F_m/b), F_βx = 1.33 B₁ f_sh + B₂ f_ma, B₂ = 0.5
for a crowning; F_βy = F_βx − y_β, y_β = min(0.15 F_βx, 6 µm) for case-hardened gears; c_γβ =
0.85 c_γα), written out here; the case files' depths by hand."""

import json
import math
import re
import tomllib

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest
from _rating_cases import rated_accessory_data

import jaxgear as jg
import jaxgear.io as jio
import jaxgear.rating as jr
import optimise as op
from jaxgear import cli
from jaxgear.cli import main

jax.config.update("jax_enable_x64", True)


def _power_helical(slices=40, ppp=64, **changes) -> dict:
    d = tomllib.loads(jio.embedded_case_text("power-helical"))
    d["mesh"].update(slices=slices, positions_per_pitch=ppp)
    for key, value in changes.items():
        table, name = key.split("/", 1)
        if value is None:
            d[table].pop(name, None)
        else:
            d[table][name] = value
    return d


def test_the_rating_takes_the_tip_relief_of_the_case_modifications():
    """C_a of K_v: the larger member's tip relief depth of ``[modifications]`` (pinion 12 µm,
    gear 8 µm → 12 µm; as K_v's ``C_a_m`` too), ``[rating] tip_relief_um`` over it when given
    (3 µm), and without a tip relief the running-in C_ay of σ_Hlim 1500 N/mm², by hand
    ((1500/97 − 18.45)²/18 + 1.5 = 1.9727 µm); each source in words."""
    d = rated_accessory_data(3, 8)
    d["modifications"] = {
        "pinion": {"tip_relief": {"depth_um": 12.0, "extent": 0.25}},
        "gear": {"tip_relief": {"depth_um": 8.0, "extent": 0.25}},
    }
    rc = jio.rating_of(jio.parse_case(d))
    assert rc.settings.tip_relief == pytest.approx(12e-6, rel=1e-6)
    assert rc.modification_inputs["tip_relief_source"].startswith("[modifications] tip_relief")
    rating = jr.rate(rc.geometry, rc.operating, rc.settings)
    assert float(rating.factors.details["C_a_m"]) == pytest.approx(12e-6, rel=1e-6)
    d["rating"]["tip_relief_um"] = 3.0
    rc = jio.rating_of(jio.parse_case(d))
    assert rc.settings.tip_relief == pytest.approx(3e-6, rel=1e-12)
    assert rc.modification_inputs["tip_relief_source"] == "[rating] tip_relief_um (given)"
    del d["rating"]["tip_relief_um"], d["modifications"]
    rc = jio.rating_of(jio.parse_case(d))
    assert rc.settings.tip_relief is None and rc.settings.crowning is None
    assert "running-in" in rc.modification_inputs["tip_relief_source"]
    rating = jr.rate(rc.geometry, rc.operating, rc.settings)
    c_ay = ((1500 / 97 - 18.45) ** 2 / 18 + 1.5) * 1e-6
    assert float(rating.factors.details["C_a_m"]) == pytest.approx(c_ay, rel=1e-12)


def test_the_crowning_of_power_helical_halves_the_iso_misalignment():
    """power-helical's 5 µm crowning (ISO 1328-1 class 5: f_Hβ below 10 µm, so at least f_Hβ/2
    deep): K_Hβ of clause 7 with F_βx = 0.5 f_Hβ, by hand from the rating's c_γα, F_t, K_A,
    K_v, b; without the crowning (and with one shallower than f_Hβ/2, 0.1 µm) F_βx = f_Hβ and
    K_Hβ is the uncrowned one; ``rating.md`` states both inputs and their source on one line."""
    def rated(crowning_um):
        d = _power_helical()
        if crowning_um is None:
            del d["modifications"]["crowning"]
        else:
            d["modifications"]["crowning"] = {"depth_um": crowning_um}
        rc = jio.rating_of(jio.parse_case(d))
        return rc, jr.rate(rc.geometry, rc.operating, rc.settings)

    rc, r = rated(5.0)
    assert rc.settings.crowning == pytest.approx(5e-6, rel=1e-6)
    f_hb = float(rc.settings.accuracy.helix_slope)
    assert 5e-6 >= f_hb / 2
    g = rc.geometry.derived()
    f_t = 2 * float(rc.operating.torque) / float(g.reference_diameter[0])
    f_m_per_b = f_t * 1.25 * float(r.factors.K_v) / float(g.face_width)
    c_gb = 0.85 * float(r.factors.details["c_gamma_alpha_N_per_m2"])

    def k_hb(b2):
        f_bx = max(b2 * f_hb, 5e-12 * f_m_per_b)
        f_by = f_bx - min(0.15 * f_bx, 6e-6)
        t = f_by * c_gb / f_m_per_b
        return 1 + t / 2 if t <= 2 else math.sqrt(2 * t)

    assert float(r.factors.K_Hbeta) == pytest.approx(k_hb(0.5), rel=1e-9)
    _, none = rated(None)
    assert float(none.factors.K_Hbeta) == pytest.approx(k_hb(1.0), rel=1e-9)
    _, shallow = rated(0.1)
    assert float(shallow.factors.K_Hbeta) == pytest.approx(k_hb(1.0), rel=1e-9)
    assert float(r.factors.K_Hbeta) < float(none.factors.K_Hbeta) - 0.05


def test_rating_md_states_the_modification_inputs_and_their_source(tmp_path):
    """One line of rating.md (and summary.json's ``modification_inputs``): C_a 10 µm and C_β
    5 µm of power-helical's [modifications], each with its source; with ``[rating]
    tip_relief_um = 20`` the given value and its key."""
    case = jio.parse_case(_power_helical(4, 8))
    section = cli.rating_outputs(case, str(tmp_path))
    m = section["modification_inputs"]
    assert m["tip_relief_um"] == pytest.approx(10.0, rel=1e-6)
    assert m["crowning_um"] == pytest.approx(5.0, rel=1e-6)
    assert m["B_2"] == 0.5
    lines = [
        ln for ln in (tmp_path / "rating.md").read_text(encoding="utf-8").splitlines()
        if "modification inputs" in ln
    ]
    assert len(lines) == 1
    assert re.search(r"tip relief C_a = 10 µm of K_v \(\[modifications\] tip_relief", lines[0])
    assert re.search(r"crowning C_β = 5 µm of K_Hβ \(\[modifications\] crowning", lines[0])
    d = _power_helical(4, 8)
    d["rating"]["tip_relief_um"] = 20.0
    section = cli.rating_outputs(jio.parse_case(d), str(tmp_path))
    assert section["modification_inputs"]["tip_relief_um"] == pytest.approx(20.0, rel=1e-12)
    text = (tmp_path / "rating.md").read_text(encoding="utf-8")
    assert "tip relief C_a = 20 µm of K_v ([rating] tip_relief_um (given))" in text


def test_least_safety_rates_each_design_with_its_own_relief_and_iso_k_halpha():
    """The objective's safety factors of a design are jg.rating.rate's with the K_Hβ measured on the
    load map given, K_Hα and K_Fα ISO's (not the measured load sharing), and the design's tip
    relief and crowning as C_a and C_β (the larger member's depths, set here by hand)."""
    case = jio.parse_case(_power_helical(4, 8))
    rc = jio.rating_of(case)
    obj = op.LeastSafetyFactor(rc.geometry, rc.operating, rc.settings)
    tip = {"tip_relief_depth": 14e-6, "tip_relief_extent": 0.3}
    mods = jg.Modifications(
        jg.MemberModification(crowning_depth=7e-6, **tip), jg.MemberModification(**tip)
    )
    res = jg.quasi_static(case.mesh_model(), mods, case.torque, positions_per_pitch=8)
    got = np.asarray(obj.safety_factors(res, mods))
    settings = eqx.tree_at(
        lambda s: (s.given, s.tip_relief, s.crowning),
        rc.settings,
        (jr.GivenFactors(K_Hbeta=float(jg.rating.face_load_factor(res))), 14e-6, 7e-6),
        is_leaf=lambda x: x is None,
    )
    ref = jr.rate(rc.geometry, rc.operating, settings)
    want = np.concatenate([np.asarray(ref.pitting.S_H), np.asarray(ref.bending.S_F)])
    np.testing.assert_allclose(got, want, rtol=1e-12)
    rating = obj.rating(res, mods)
    assert rating.factors.sources["K_Halpha"] == "ISO 6336-1 method B"
    assert rating.factors.sources["K_Falpha"] == "ISO 6336-1 method B"


# default tier: tests/test_rating_modifications.py::test_least_safety_rates_each_design_with_its_own_relief_and_iso_k_halpha
# (the objective rates each design with its own relief and ISO's K_Halpha, against jg.rating.rate)
@pytest.mark.slow
def test_least_safety_keeps_the_tip_relief_of_power_helical():
    """The slow test below's least_safety claim on the case file's contact (beyond the path),
    power-helical at 8 slices and 16 positions per pitch, exact contact, sharp relief starts:
    the case's 10 µm tip relief gives a lower least_safety objective (a higher least safety
    factor) than no relief."""
    case = jio.parse_case(_power_helical(8, 16, **{"mesh/extended_contact": True}))
    prob = jio.case_problem(case, "tip_relief.depth", "least_safety").sharp()
    least = [
        float(prob.value(jnp.asarray(prob.from_physical({"tip_relief.depth": d})),
                         jg.ExactContact()))
        for d in (0.0, 10.0)
    ]
    assert least[1] < least[0] - 1e-3, least


# default tier: tests/test_rating_modifications.py::test_least_safety_keeps_the_tip_relief_of_power_helical
# (the least_safety claim), tests/test_extended_contact.py::test_enough_tip_relief_leaves_no_offline_contact
# (TE beyond the path equals the path's once no corner touches, 1e-9)
@pytest.mark.slow
def test_least_safety_and_te_rms_both_keep_the_tip_relief_of_power_helical():
    """power-helical (8 slices, 16 positions per pitch), the tip relief depth the variable,
    exact contact, sharp relief starts. On the theoretical path the case's 10 µm gives a lower
    TE RMS objective than no relief and a lower least_safety objective (a higher least safety
    factor: the relief evens the face load the measured K_Hβ reads); with the measured K_Hα
    (main), least_safety rose with any relief and removed it.

    With contact beyond the path (the case file's default) the least_safety objective also
    falls with the 10 µm relief. The TE RMS objective does not (3.20 against 3.15 unrelieved):
    the unrelieved pair's tip corners already engage gradually beyond the path (a lower TE
    than on the path), and 10 µm removes that corner contact without yet giving an engagement
    as gradual of its own; from 15 µm no corner touches, and at 20 µm (the TE RMS's least on
    both models) the TE equals the theoretical path's (1e-9) and is below the unrelieved
    one's."""
    values = {}
    for extended in (False, True):
        case = jio.parse_case(_power_helical(8, 16, **{"mesh/extended_contact": extended}))
        for objective in ("te_rms", "least_safety"):
            prob = jio.case_problem(case, "tip_relief.depth", objective).sharp()
            values[extended, objective] = [
                float(prob.value(jnp.asarray(prob.from_physical({"tip_relief.depth": d})),
                                 jg.ExactContact()))
                * (float(prob.scale) if objective == "te_rms" else 1.0)
                for d in ((0.0, 10.0, 20.0) if objective == "te_rms" else (0.0, 10.0))
            ]
    on_path, beyond = values[False, "te_rms"], values[True, "te_rms"]
    assert on_path[1] < on_path[0]
    for extended in (False, True):
        least = values[extended, "least_safety"]
        assert least[1] < least[0] - 1e-3, (extended, least)
    assert beyond[0] < on_path[0]  # the corners' gradual engagement
    assert beyond[1] > beyond[0]  # 10 µm: the corners' contact gone, the relief too shallow
    assert beyond[2] == pytest.approx(on_path[2], rel=1e-9)  # no corner touches
    assert beyond[2] < beyond[0]


@pytest.mark.filterwarnings("ignore:optimiser stopped at the iteration cap")  # 3 iterations
@pytest.mark.usefixtures("no_figures")  # no figure is read: the optimiser draws none
def test_optimise_write_saves_the_optimum_as_a_case_file_that_loads_back(tmp_path, capsys):
    """``jaxgear optimise CASE --write NEW.toml`` (3 iterations, tip relief depth and extent
    against te_rms on tests/test_optimise_candidates.py's uniform spur pair, the programs its
    tests compile, with a 2 µm relief far below the TE RMS valley's E* ≈ 1, where the optimum
    beats the case's design and the bare flanks): NEW.toml loads (jio.load_case), its tip relief
    is the report's optimum to the written precision (the double exactly; 1e-6 relative
    in the float32 model fields), every other table the case's, its comments kept. Refused before any work in one line, nothing written: a name not
    ending in .toml, a folder that is a file. (slow) The same on power-helical, whose rating
    reads the new relief: the test below."""
    from test_optimise_candidates import SPUR

    src = tmp_path / "spur.toml"
    text = "# a spur pair whose relief is too shallow\n" + SPUR + """[modifications]
tip_relief = { depth_um = 2.0, extent = 0.3 }
[optimise]
objective = "te_rms"
vars = ["tip_relief.depth", "tip_relief.extent"]
max_iterations = 3
"""
    src.write_text(text, encoding="utf-8")
    _write_round_trip(tmp_path, capsys, src, text, [], crowning=0.0)


def _write_round_trip(tmp_path, capsys, src, text, extra, crowning):
    """``jaxgear optimise src --write designs/new.toml`` (``extra`` arguments) and its checks
    (the docstrings above and below); ``crowning`` the case's crowning depth in m."""
    new = tmp_path / "designs" / "new.toml"
    new.parent.mkdir()
    argv = ["optimise", str(src), *extra, "--quiet", "--out", str(tmp_path / "o")]
    assert main([*argv, "--write", str(new)]) == 0
    rep = json.loads((tmp_path / "o" / "optimum.json").read_text())
    assert rep["best"] == "optimum"
    final = rep["final"]["parameters"]
    loaded = jio.load_case(str(new))
    for member in (loaded.modifications.pinion, loaded.modifications.gear):
        assert float(member.tip_relief_depth) * 1e6 == pytest.approx(
            final["tip_relief.depth"], rel=1e-6)  # float32 model fields
        assert float(member.tip_relief_extent) == pytest.approx(
            final["tip_relief.extent"], rel=1e-6)
        assert float(member.crowning_depth) == pytest.approx(crowning, rel=1e-6, abs=1e-15)
    written = tomllib.loads(new.read_text(encoding="utf-8"))
    tip = written["modifications"]["tip_relief"]
    assert tip["depth_um"] == final["tip_relief.depth"]  # the double, exactly
    assert tip["extent"] == final["tip_relief.extent"]
    original = tomllib.loads(text)
    kept = {k: v for k, v in original["modifications"]["tip_relief"].items()
            if k not in ("depth_um", "extent")}  # the shape, where the case names it
    assert {k: v for k, v in tip.items() if k not in ("depth_um", "extent")} == kept
    assert {k: v for k, v in written.items() if k != "modifications"} == {
        k: v for k, v in original.items() if k != "modifications"
    }
    assert new.read_text(encoding="utf-8").startswith(text.splitlines()[0] + "\n")
    if "rating" in original:
        rc = jio.rating_of(loaded)
        assert rc.settings.tip_relief == pytest.approx(final["tip_relief.depth"] * 1e-6, rel=1e-6)
    for bad, message in (
        (str(tmp_path / "new.txt"), r"--write .*new\.txt: a case file name ending in \.toml"),
        (str(src / "x.toml"), rf"--write .*x\.toml: its folder .*{src.name} is a file"),
    ):
        capsys.readouterr()
        assert main([*argv, "--write", bad]) == 2
        err = capsys.readouterr().err.strip()
        assert len(err.splitlines()) == 1 and re.search(message, err), err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["designs", "o", src.name]
    assert sorted(p.name for p in new.parent.iterdir()) == ["new.toml"]


# default tier: tests/test_rating_modifications.py::test_optimise_write_saves_the_optimum_as_a_case_file_that_loads_back
# (the same --write round trip on the candidates' spur pair)
@pytest.mark.slow
@pytest.mark.filterwarnings("ignore:optimiser stopped at the iteration cap")  # 2 iterations
@pytest.mark.usefixtures("no_figures")  # no figure is read: the optimiser draws none
def test_optimise_write_saves_the_optimum_of_power_helical(tmp_path, capsys):
    """The round trip above on power-helical (2 iterations, a coarse mesh at 1200 N·m, where
    the optimum beats the case's design and the bare flanks; its 5 µm crowning kept; its
    rating reads the new relief)."""
    src = tmp_path / "ph.toml"
    text = (
        jio.embedded_case_text("power-helical")
        .replace("slices = 40", "slices = 4")
        .replace("positions_per_pitch = 64", "positions_per_pitch = 8")
        # at 310 N·m the bare flanks beat a 2-iteration optimum (the case's crowning held) and
        # --write would write them (tests/test_optimise_candidates.py); loaded 4× the relief pays
        .replace("torque_Nm = 310.0", "torque_Nm = 1200.0")
    )
    src.write_text(text, encoding="utf-8")
    _write_round_trip(tmp_path, capsys, src, text, ["--max-iterations", "2"], crowning=5e-6)


def test_a_design_is_written_into_the_modifications_tables_it_reads_from():
    """The text writer on a case with common and per-member tables between other tables: a
    variable on both members over a per-member entry is written per member, each member's
    other keys kept (its own entry replaces the common one whole, as the reader takes it); a
    pinion-only value splits the common entry; an entry equal on both members is written once;
    the other tables (before and after, ``[[...]]`` arrays too) and comments kept; the text
    reads back (tomllib) to exactly these tables; an inline ``modifications = {...}`` refused."""
    text = """# a comment kept
name = "t"
[modifications]
tip_relief = { depth_um = 10.0, extent = 0.2 }
crowning = { depth_um = 5.0 }
[modifications.gear]
tip_relief = { depth_um = 7.0, extent = 0.3, shape = "parabolic" }
[[gears]]
name = "a"
[rating]
life_h = 1.0
"""
    table = tomllib.loads(text)["modifications"]
    values = {
        (("pinion", "gear"), "tip_relief", "depth_um"): 12.345678901234567,
        (("pinion",), "crowning", "depth_um"): 2.5,
    }
    new = jio.modifications_with(table, values)
    assert new == {
        "pinion": {
            "tip_relief": {"depth_um": 12.345678901234567, "extent": 0.2},
            "crowning": {"depth_um": 2.5},
        },
        "gear": {
            "tip_relief": {"depth_um": 12.345678901234567, "extent": 0.3, "shape": "parabolic"},
            "crowning": {"depth_um": 5.0},
        },
    }
    same = jio.modifications_with(table, {(("gear",), "tip_relief", "extent"): 0.2})
    assert same["crowning"] == {"depth_um": 5.0} and "crowning" not in same.get("gear", {})
    out = jio.case_text_with_modifications(text, new)
    parsed = tomllib.loads(out)
    assert parsed["modifications"] == new
    assert parsed["gears"] == [{"name": "a"}] and parsed["rating"] == {"life_h": 1.0}
    assert out.startswith("# a comment kept\nname = \"t\"\n")
    with pytest.raises(ValueError, match=r"dotted or inline key"):
        jio.case_text_with_modifications('name = "t"\nmodifications = { crowning = {} }\n', new)
