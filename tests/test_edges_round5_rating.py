"""Rating inputs (round 5 of the edges): a material's and a surface's values in the
ranges they can have (ISO 6336-5's material lines, finished flanks' roughness; case file and
API alike), keys that nothing
reads refused, ``use_measured`` a stage cannot measure refused before work, the rating objects of
the Python API refusing bad values and wrong kinds at construction in one line naming the
argument; a given K_Hα carried to K_Fα (ISO 6336-1 8.3.4); the edition's unconfirmed factors as
data on the rating."""

import dataclasses
import math
import tomllib

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest
from _rating_cases import rated_accessory_data, with_rating
from _toml import case_toml

import jaxgear as jg
import jaxgear.gearbox as jgb
import jaxgear.io as jio
import jaxgear.planetary as jp
import jaxgear.rating as jr
from fem_prep import schema as sc
from jaxgear.cli import main


def _refused(data, *needles) -> str:
    """``data`` (a parsed case) refused at load in one line holding every needle."""
    with pytest.raises(sc.SchemaError) as info:
        jio.parse_case(data)
    msg = str(info.value)
    assert "\n" not in msg, msg
    for n in needles:
        assert n in msg, msg
    return msg


def _rated(**changes) -> dict:
    """The rated accessory pair (tests/_rating_cases.py) with ``table/key`` entries set (``None``
    deletes the key)."""
    d = rated_accessory_data(4, 8)
    for path, value in changes.items():
        table, key = path.split("__")
        if value is None:
            d[table].pop(key, None)
        else:
            d[table][key] = value
    return d


# ------------------------------------------------------------------------------------------
# case file: ranges a material and a surface can have


@pytest.mark.parametrize(
    ("path", "value", "needles"),
    [
        ("material__sigma_H_lim_MPa", 1e-300, ("sigma_H_lim_MPa = 1e-300", "allowed [200, 2000]")),
        ("material__sigma_H_lim_MPa", 150.0, ("sigma_H_lim_MPa = 150", "ISO 6336-5")),
        ("material__sigma_H_lim_MPa", 2500.0, ("sigma_H_lim_MPa = 2500", "allowed [200, 2000]")),
        ("material__sigma_H_lim_MPa", [1500.0, 1e-300], ("element 1e-300", "ISO 6336-5")),
        ("material__sigma_F_lim_MPa", 1e-300, ("sigma_F_lim_MPa = 1e-300", "allowed [30, 800]")),
        # σ_FE = 2 σ_Flim of a case-hardened ME steel given for σ_Flim
        ("material__sigma_F_lim_MPa", 1050.0, ("sigma_F_lim_MPa = 1050", "σ_FE")),
        ("rating__roughness_Rz_flank_um", 1e-300, ("roughness_Rz_flank_um = 1e-300",
                                                    "allowed [0.1, 50]", "ground")),
        ("rating__roughness_Rz_flank_um", 5e-324, ("roughness_Rz_flank_um", "[0.1, 50]")),
        ("rating__roughness_Rz_flank_um", 80.0, ("roughness_Rz_flank_um = 80", "[0.1, 50]")),
        ("rating__roughness_Rz_flank_um", [3.0, 0.01], ("element 0.01", "[0.1, 50]")),
        ("rating__roughness_Rz_root_um", 1e-300, ("roughness_Rz_root_um = 1e-300",
                                                   "allowed [0.1, 100]")),
        ("rating__roughness_Rz_root_um", 150.0, ("roughness_Rz_root_um = 150", "[0.1, 100]")),
    ],
)
def test_material_and_surface_out_of_their_range_refused(path, value, needles):
    _refused(_rated(**{path: value}), *needles)


@pytest.mark.parametrize(
    ("path", "value"),
    [
        ("material__sigma_H_lim_MPa", 200.0),
        ("material__sigma_H_lim_MPa", 2000.0),
        ("material__sigma_H_lim_MPa", [1500.0, 700.0]),
        ("material__sigma_F_lim_MPa", 30.0),
        ("material__sigma_F_lim_MPa", 800.0),
        ("rating__roughness_Rz_flank_um", 0.1),
        ("rating__roughness_Rz_flank_um", 50.0),
        ("rating__roughness_Rz_root_um", 100.0),
    ],
)
def test_material_and_surface_at_the_range_ends_accepted(path, value):
    rc = jio.rating_of(jio.parse_case(_rated(**{path: value})))
    key = path.split("__")[1]
    got = {
        "sigma_H_lim_MPa": rc.settings.material.sigma_h_lim * 1e-6,
        "sigma_F_lim_MPa": rc.settings.material.sigma_f_lim * 1e-6,
        "roughness_Rz_flank_um": rc.settings.lubrication.roughness_flank * 1e6,
        "roughness_Rz_root_um": rc.settings.lubrication.roughness_root * 1e6,
    }[key]
    np.testing.assert_allclose(got, np.broadcast_to(value, (2,)), rtol=1e-12)


def test_reference_states_each_range_and_its_source():
    """The generated case-file reference prints the new ranges with their sources."""
    from docs._gen import schema_reference as sr

    page = sr.markdown(sr.trace_cases()[0], "Case file", "")
    rows = {line.split("|")[1].strip(): line for line in page.splitlines() if line.startswith("| `")}
    assert "[200, 2000]" in rows["`sigma_H_lim_MPa`"] and "ISO 6336-5" in rows["`sigma_H_lim_MPa`"]
    assert "[30, 800]" in rows["`sigma_F_lim_MPa`"] and "ISO 6336-5" in rows["`sigma_F_lim_MPa`"]
    assert "[0.1, 50]" in rows["`roughness_Rz_flank_um`"] and "ground" in rows[
        "`roughness_Rz_flank_um`"]
    assert "[0.1, 100]" in rows["`roughness_Rz_root_um`"]


@pytest.mark.parametrize(
    ("path", "value", "key"),
    [
        ("material__sigma_H_lim_MPa", 1e-300, "[material] sigma_H_lim_MPa = 1e-300"),
        ("rating__roughness_Rz_flank_um", 1e-300, "[rating] roughness_Rz_flank_um = 1e-300"),
        ("material__proof_stress_MPa", 1000.0, "[material] proof_stress_MPa = 1000"),
    ],
)
def test_run_refuses_in_one_line_before_writing(tmp_path, capsys, path, value, key):
    """``jaxgear run`` (today: S_H = 1e-303 or 2e24 with exit 0, or a silently unread key):
    exit 2, one line on stderr naming the key, its value and why, no output folder."""
    file = tmp_path / "bad.toml"
    file.write_text(case_toml(_rated(**{path: value})))
    out = tmp_path / "out"
    assert main(["run", str(file), "--out", str(out), "--quiet"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("jaxgear: error: ") and key in err[0], err
    assert not out.exists()


# ------------------------------------------------------------------------------------------
# case file: keys that nothing reads


@pytest.mark.parametrize(
    ("treatment", "extra", "needles"),
    [
        ("case_hardened", {"proof_stress_MPa": 1000.0},
         ("proof_stress_MPa = 1000: not read", "no gear is through_hardened", "case_hardened")),
        (["case_hardened", "nitrided"], {"proof_stress_MPa": [800.0, 900.0]},
         ("proof_stress_MPa", "not read", "nitrided")),
        ("case_hardened", {"brinell_hardness_HB": 650.0},
         ("brinell_hardness_HB = 650: not read", "Z_W")),
        # two through-hardened gears: Z_W = 1 whatever their hardness
        ("through_hardened", {"brinell_hardness_HB": 240.0},
         ("brinell_hardness_HB = 240: not read", "through_hardened")),
    ],
)
def test_material_keys_no_gear_reads_are_refused(treatment, extra, needles):
    d = _rated(material__treatment=treatment)
    d["material"].update(extra)
    _refused(d, *needles)


@pytest.mark.parametrize(
    ("treatment", "extra"),
    [
        (["case_hardened", "through_hardened"], {"proof_stress_MPa": [1000.0, 800.0]}),
        ("through_hardened", {"proof_stress_MPa": 800.0}),
        (["case_hardened", "through_hardened"], {"brinell_hardness_HB": [650.0, 240.0]}),
    ],
)
def test_material_keys_a_gear_reads_are_accepted(treatment, extra):
    d = _rated(material__treatment=treatment)
    d["material"].update(extra)
    t = jio.rating_of(jio.parse_case(d)).settings.material.treatment
    gear = t.gear if isinstance(t, jr.PairTreatment) else t
    if "proof_stress_MPa" in extra:  # ρ' of the table's row (ISO 6336-3: 800 N/mm² → 0.0064 mm)
        assert gear.slip_layer == pytest.approx(0.0064e-3, rel=1e-12)
    else:  # Z_W = 1.2 − (HB − 130)/1700 (ISO 6336-2) against the case-hardened pinion
        assert gear.work_hardening(t.pinion) == pytest.approx(1.2 - 110 / 1700, rel=1e-12)


def test_train_proof_stress_with_no_through_hardened_gear_refused():
    d = with_rating(tomllib.loads(jio.embedded_case_text("accessory-idler-train")))
    d.pop("scene", None)
    d["material"]["proof_stress_MPa"] = 1000.0
    with pytest.raises(sc.SchemaError) as info:
        jio.parse_train(d)
    msg = str(info.value)
    assert "\n" not in msg and "[material] proof_stress_MPa = 1000: not read" in msg, msg


def _planetary(name: str, *subs) -> str:
    text = jio.embedded_case_text(name)
    for old, new in subs:
        assert old in text, old
        text = text.replace(old, new, 1)
    return text


@pytest.mark.parametrize(
    ("name", "subs", "needles"),
    [
        # the lumped form (no rating) and the gear form (rated): speed_rpm is read by neither
        ("lin-parker-1999", (("speed_rad_s = 100.0", "speed_rad_s = 100.0\nspeed_rpm = 955.0"),),
         ("[operating] speed_rpm = 955: not read in a planetary stage", "speed_rad_s")),
        ("nrel-5mw-planetary",
         (("speed_rad_s = 1.2671", "speed_rad_s = 1.2671\nspeed_rpm = 12.1"),),
         ("[operating] speed_rpm = 12.1: not read in a planetary stage",)),
        ("nrel-5mw-planetary",
         (("edition = 2006", 'edition = 2006\nuse_measured = ["K_Hbeta"]'),),
         ("[rating] use_measured = ['K_Hbeta']", "helical stage only")),
        ("nrel-5mw-planetary",
         (("edition = 2006", 'edition = 2006\nuse_measured = ["K_Halpha", "K_Hbeta"]'),),
         ("use_measured", "K_Hbeta is measured on a helical stage only")),
    ],
)
def test_planetary_unread_keys_refused_at_load(tmp_path, name, subs, needles):
    path = tmp_path / f"{name}.toml"
    path.write_text(_planetary(name, *subs))
    with pytest.raises(sc.SchemaError) as info:
        jio.load_case(path)
    msg = str(info.value)
    assert "\n" not in msg, msg
    for n in needles:
        assert n in msg, msg


def test_planetary_use_measured_k_halpha_accepted(tmp_path):
    """K_Hα is measured on a stage given by its gears (its quasi-static load sharing): kept."""
    path = tmp_path / "stage.toml"
    path.write_text(_planetary("nrel-5mw-planetary",
                               ("edition = 2006", 'edition = 2006\nuse_measured = ["K_Halpha"]')))
    rcs = jio.ratings_of(jio.load_case(path))
    assert [rc.use_measured for rc in rcs] == [("K_Halpha",), ("K_Halpha",)]


# ------------------------------------------------------------------------------------------
# Python API: values and kinds at construction


def _settings(**kw):
    base = {
        "material": jr.RatingMaterial(1500e6, 430e6),
        "lubrication": jr.Lubrication(220e-6, 3e-6, 10e-6),
        "accuracy": jr.GearAccuracy(5e-6, 5e-6, 5e-6),
        "life": 1e8,
    }
    return jr.RatingSettings(**(base | kw))


@pytest.mark.parametrize(
    ("make", "needles"),
    [
        (lambda: jr.GivenFactors(K_Hbeta=0.5), ("GivenFactors: K_Hbeta = 0.5", "allowed >= 1")),
        (lambda: jr.GivenFactors(K_v=math.nan), ("GivenFactors: K_v = nan", ">= 1")),
        (lambda: jr.GivenFactors(K_v=0.999), ("K_v = 0.999 is out of range",)),
        (lambda: jr.GivenFactors(K_Falpha=math.inf), ("K_Falpha = inf",)),
        (lambda: jr.GivenFactors(K_Halpha="1.1"), ("K_Halpha = '1.1' is not a number",)),
        (lambda: jr.GivenFactors(K_Fbeta=[1.1, 1.2]), ("K_Fbeta must have shape a scalar",)),
        (lambda: jr.RatingMaterial(1e-300, 430e6),
         ("RatingMaterial: sigma_h_lim = 1e-300 Pa", "[2e+08, 2e+09] Pa")),
        (lambda: jr.RatingMaterial(1500e6, [430e6, 1050e6]),
         ("RatingMaterial: sigma_f_lim[1] = 1.05e+09 Pa", "[3e+07, 8e+08] Pa")),
        (lambda: jr.Lubrication(220e-6, 1e-300, 10e-6),
         ("Lubrication: roughness_flank = 1e-300 m", "[1e-07, 5e-05] m")),
        (lambda: jr.Lubrication(220e-6, 3e-6, 1e-3), ("roughness_root = 0.001 m",)),
        (lambda: _settings(life=-1), ("RatingSettings: life = -1 s", "> 0 s")),
        (lambda: _settings(application_factor=0.5),
         ("RatingSettings: application_factor = 0.5", ">= 1")),
        (lambda: _settings(min_safety_bending=0.0), ("min_safety_bending = 0", "> 0")),
        (lambda: _settings(tip_relief=-1e-6), ("tip_relief = -1e-06 m", ">= 0 m")),
        (lambda: _settings(given={"K_v": 1.1}), ("given = ", "jaxgear.rating.GivenFactors")),
        (lambda: _settings(standard=2006), ("standard = 2006", "Edition2019()")),
        (lambda: _settings(material=None), ("material = None",)),
        (lambda: jr.ThroughHardened(brinell_hardness=-5),
         ("ThroughHardened: brinell_hardness = -5 HB", "[100, 700] HB")),
        (lambda: jr.ThroughHardened(brinell_hardness="hard"),
         ("brinell_hardness = 'hard' is not a number",)),
        (lambda: jr.ThroughHardened(brinell_hardness=math.nan), ("brinell_hardness = nan",)),
        (lambda: jr.ThroughHardened(proof_stress="high"), ("proof_stress = 'high'",)),
        (lambda: jr.ThroughHardened(slip_layer_m=math.inf), ("slip_layer_m = inf m",)),
        (lambda: jr.PairTreatment(jr.CaseHardened(), "through"),
         ("PairTreatment: gear = 'through'", "ThroughHardened")),
        (lambda: jr.PairTreatment(None, jr.CaseHardened()), ("PairTreatment: pinion = None",)),
        (lambda: jr.PairTreatment(jr.CaseHardened(), jr.PairTreatment(jr.CaseHardened(),
                                                                       jr.Nitrided())),
         ("gear = PairTreatment", "not a PairTreatment")),
    ],
)
def test_rating_objects_refuse_bad_values_at_construction(make, needles):
    with pytest.raises((TypeError, ValueError)) as info:
        make()
    msg = str(info.value)
    assert "\n" not in msg, msg
    for n in needles:
        assert n in msg, msg


def test_rating_objects_at_the_range_ends_construct():
    jr.GivenFactors(K_v=1.0, K_Hbeta=12.0, K_Fbeta=1, K_Halpha=np.float32(1.5), K_Falpha=None)
    _settings(life=1.0, application_factor=1.0, tip_relief=0.0, min_safety_pitting=1e-3)
    jr.RatingMaterial([200e6, 2000e6], [30e6, 800e6])
    jr.Lubrication(220e-6, [0.1e-6, 50e-6], [0.1e-6, 100e-6])
    assert jr.ThroughHardened(brinell_hardness=100).work_hardening(jr.CaseHardened()) == 1.2
    assert jr.ThroughHardened(brinell_hardness=700.0).brinell_hardness == 700.0
    jr.PairTreatment(jr.CaseHardened(), jr.ThroughHardened(proof_stress=1000e6))


@pytest.fixture(scope="module")
def rated():
    """The rated accessory pair's (geometry, operating point, settings): spur, class 6."""
    rc = jio.rating_of(jio.parse_case(rated_accessory_data(4, 8)))
    return rc.geometry, rc.operating, rc.settings


def test_given_factors_traced_under_grad_and_jit(rated):
    """A given K_Hβ traced (the optimiser's measured one) still constructs: dS_H/dK_Hβ against
    σ_H ∝ √K_Hβ (ISO 6336-2), i.e. dS_H/dK_Hβ = −S_H/(2 K_Hβ); and a traced life under jit."""
    geometry, op, settings = rated

    def s_h(k):
        s = eqx.tree_at(lambda s: s.given, settings, jr.GivenFactors(K_Hbeta=k))
        return jr.rate(geometry, op, s).pitting.S_H

    k = 1.3
    # compiled: eagerly each primitive of the rating's tangent compiles on its own (this test
    # 5.4 -> 3.2 CPU s alone)
    jac = jax.jit(jax.jacfwd(s_h))(jnp.asarray(k))
    np.testing.assert_allclose(jac, -s_h(k) / (2 * k), rtol=1e-10)

    @jax.jit
    def with_life(life):
        s = dataclasses.replace(settings, life=life)  # constructed anew: its checks run
        return jr.rate(geometry, op, s).bending.S_F

    np.testing.assert_allclose(with_life(settings.life), jr.rate(geometry, op, settings).bending.S_F,
                               rtol=1e-12)


def test_functions_refuse_arguments_of_the_wrong_kind(rated):
    geometry, op, settings = rated
    stage = None  # the model is checked first: any stage
    cases = [
        (lambda: jr.rate(geometry, op, "x"), "rate: settings = 'x' (str)"),
        (lambda: jr.rate("x", op, settings), "rate: geometry = 'x'"),
        (lambda: jr.rate(geometry, (10.0, 100.0), settings), "rate: operating = (10.0, 100.0)"),
        (lambda: jg.rating.load_factors(geometry, op, None), "load_factors: settings = None"),
        (lambda: jr.pitting_rating(geometry, None, settings), "pitting_rating: operating = None"),
        (lambda: jr.bending_rating(geometry, op, {}), "bending_rating: settings = {}"),
        (lambda: jp.planetary_modes("planar", stage), "planetary_modes: model = 'planar'"),
        (lambda: jp.planetary_modes(jp.PlanarPlanetary(), "stage"),
         "planetary_modes: stage = 'stage'"),
        (lambda: jp.campbell("planar", stage, jnp.ones(2)), "campbell: model = 'planar'"),
        (lambda: jgb.gearbox_modes("x"), "gearbox_modes: chain = 'x'"),
        (lambda: jp.CraigBamptonRing.from_stations(None, 2),
         "CraigBamptonRing.from_stations: stations = None"),
    ]
    for make, needle in cases:
        with pytest.raises((TypeError, ValueError)) as info:
            make()
        msg = str(info.value)
        assert needle in msg and "allowed" in msg and "\n" not in msg, msg


# ------------------------------------------------------------------------------------------
# a given K_Hα carries to K_Fα


def test_given_k_halpha_carries_to_k_falpha(rated):
    """ISO 6336-1 8.3.4: K_Fα = K_Hα, within [1, ε_γ/(0.25 ε_α + 0.75)]. σ_F = σ_F0 K_A K_v K_Fβ
    K_Fα (ISO 6336-3) with σ_F0, K_A, K_v, K_Fβ independent of K_Hα, so a given K_Hα = x moves
    σ_F by exactly min(x, cap)/K_Fα(ISO); a given K_Fα still wins."""
    geometry, op, settings = rated
    iso = jr.rate(geometry, op, settings)
    g = geometry.derived()
    ea = float(g.transverse_contact_ratio)
    eg = ea + float(g.overlap_ratio)
    cap = eg / (0.25 * ea + 0.75)
    kfa_iso = float(iso.factors.K_Falpha)
    for x in (1.0 + 0.5 * (cap - 1.0), cap + 0.3):
        assert abs(min(x, cap) - kfa_iso) > 1e-3  # the test can tell the two apart
        s = eqx.tree_at(lambda s: s.given, settings, jr.GivenFactors(K_Halpha=x))
        r = jr.rate(geometry, op, s)
        assert float(r.factors.K_Falpha) == pytest.approx(min(x, cap), rel=1e-12)
        np.testing.assert_allclose(
            r.bending.sigma_F / iso.bending.sigma_F, min(x, cap) / kfa_iso, rtol=1e-12
        )
        np.testing.assert_allclose(r.bending.sigma_F0, iso.bending.sigma_F0, rtol=1e-14)
    both = eqx.tree_at(lambda s: s.given, settings, jr.GivenFactors(K_Halpha=1.2, K_Falpha=1.1))
    assert float(jr.rate(geometry, op, both).factors.K_Falpha) == 1.1


# ------------------------------------------------------------------------------------------
# the edition's unconfirmed factors, as data


def test_rating_names_the_editions_unconfirmed_factors():
    """2019: Y_β = (1 − ε_β β/120°)/cos³β, whose 1/cos³β no published worked example confirms:
    the rating carries ("Y_beta",) with its edition; 2006 (checked against a KISSsoft report):
    none. The term itself: Y_β(2019)/Y_β(2006) = 1/cos³β."""
    beta = math.radians(15.0)
    m = {"face_width": 40e-3, "addendum_coeff": 1.0, "dedendum_coeff": 1.25}
    pair = jg.GearPair(jg.Member(21, 0.2, **m), jg.Member(62, 0.0, **m), 3e-3, math.radians(20),
                       helix_angle=beta)
    geometry, op = jr.RatingGeometry.of(pair), jr.OperatingPoint(300.0, 300.0)
    r19 = jr.rate(geometry, op, _settings())
    r06 = jr.rate(geometry, op, _settings(standard=jg.rating.Edition2006()))
    assert (r19.method, r19.unconfirmed) == ("ISO 6336:2019 method B", ("Y_beta",))
    assert (r06.method, r06.unconfirmed) == ("ISO 6336:2006 method B", ())
    assert float(r19.bending.Y_beta / r06.bending.Y_beta) == pytest.approx(
        1 / math.cos(beta) ** 3, rel=1e-12)
    for name in r19.unconfirmed:  # each names a factor of the result
        assert hasattr(r19.bending, name) or hasattr(r19.pitting, name)
    jitted = eqx.filter_jit(jr.rate)(geometry, op, _settings())
    assert jitted.unconfirmed == ("Y_beta",)
