"""The housing's default cut-off (docs/housing.md, "The cut-off"): a ``[housing]`` without
``cutoff_Hz`` or ``highest_mesh_frequency_Hz`` takes 1.5 x the highest frequency of the orders
its case's ``[whine]`` computes at the top of its speed range. Each case's expected cut-off is
written out here by hand from its TOML (tomllib): its teeth, the speed ratios they give, the
whine's ``speed_max_rad_s`` and ``harmonics``. Only the parsed table is checked (no housing is
condensed: that is the slow part)."""

import math
import pathlib
import re
import tomllib
from fractions import Fraction

import pytest

import jaxgear.io as jio
from jaxgear.io import SchemaError

DATA = pathlib.Path(__file__).parent / "data" / "gearbox"
KEYS = re.compile(r"^(cutoff_Hz|highest_mesh_frequency_Hz) = .*$", re.MULTILINE)


def _without_cutoff(tmp_path, text, name="case.toml"):
    """``text`` with its cut-off keys dropped, loaded from ``tmp_path``; its TOML."""
    text = KEYS.sub("", text)
    path = tmp_path / name
    path.write_text(text)
    return jio.load_case(str(path)), tomllib.loads(text)


def _check(spec, top_hz):
    """The cut-off 1.5 x the top order's frequency ``top_hz`` (raised by 1e-9, EDGE), so that
    the top order lies within the band, f <= f_c / 1.5, in floating point."""
    assert spec.cutoff == pytest.approx(1.5 * top_hz, rel=1e-8)
    assert top_hz <= spec.cutoff / 1.5


def _top(whine):
    """(H, the top speed's rotation frequency Hz) of a [whine] table."""
    return whine["harmonics"], whine["speed_max_rad_s"] / (2 * math.pi)


def test_pair_cutoff_from_whine(tmp_path):
    """A pair (harmonic balance): orders 1..H of the mesh frequency z1 Ω / 2π, so
    1.5 H z1 Ω_max / 2π (power-helical-housed: 35 teeth, H = 8, 800 rad/s: 53.5 kHz)."""
    case, toml = _without_cutoff(tmp_path, jio.embedded_case_text("power-helical-housed"))
    H, f = _top(toml["whine"])
    _check(case.housing, H * toml["pinion"]["teeth"] * f)
    assert case.housing.cutoff_source.startswith("[whine]")


def _train_teeth(toml):
    """Each mesh's teeth per input turn of a train's TOML, by hand: the driving gear's teeth
    times its shaft's turns per input turn (a gear's shaft its ``shaft`` key, else its name)."""
    gears = {g["name"]: g for g in toml["gears"]}
    shaft = {n: g.get("shaft", n) for n, g in gears.items()}
    turns = {shaft[toml["gears"][0]["name"]]: Fraction(1)}
    out = []
    for m in toml["meshes"]:
        a, b = gears[m["driving"]], gears[m["driven"]]
        r = turns[shaft[a["name"]]]
        turns[shaft[b["name"]]] = r * a["teeth"] / b["teeth"]
        out.append(r * a["teeth"])
    return out


def test_train_cutoff_from_whine(tmp_path):
    """A two-mesh train (two-stage-housed). Quasi-periodic: each mesh's own orders 1..H, so
    1.5 H max_k(t_k) Ω_max / 2π, t_k mesh k's teeth per input turn (28 and 35 x 28/127: the
    first's). Harmonic balance: orders h / q of the first mesh over the span of q first-mesh
    periods after which both meshes repeat (q = 127, the numerator of t_1 / t_2 = 127/35), so
    1.5 H t_1 Ω_max / (2π q)."""
    text = jio.embedded_case_text("two-stage-housed")
    case, toml = _without_cutoff(tmp_path, text)
    H, f = _top(toml["whine"])
    t = _train_teeth(toml)
    assert toml["whine"]["method"] == "quasi-periodic"
    _check(case.housing, H * float(max(t)) * f)
    hb = re.sub(r'method = "quasi-periodic"\nsidebands = \d+', 'method = "harmonic-balance"',
                text)
    case, _ = _without_cutoff(tmp_path, hb, "hb.toml")
    q = (t[0] / t[1]).numerator
    assert q == 127
    _check(case.housing, H * float(t[0]) * f / q)


def test_planetary_cutoff_from_whine(tmp_path):
    """A planetary stage (nrel-5mw-planetary-housed: the ring held, the carrier the input):
    orders 1..H of the mesh frequency z_s |ω_s − ω_c| / 2π = |z_r| ω_c / 2π (Willis:
    ω_s − ω_c = −(z_r / z_s)(ω_r − ω_c), ω_r = 0)."""
    case, toml = _without_cutoff(tmp_path, jio.embedded_case_text("nrel-5mw-planetary-housed"))
    p = toml["planetary"]
    assert (p["fixed"], p["input"]) == ("ring", "carrier")
    ring = next(g for g in toml["gears"] if g["name"] == p["ring_gear"])
    H, f = _top(toml["whine"])
    _check(case.housing, H * abs(ring["teeth"]) * f)


@pytest.mark.parametrize("side", ["pinion", "gear"])
def test_gearbox_cutoff_from_whine(tmp_path, side):
    """A gearbox's [housing] (two-pair-housed: 24/40 then 25/41, quasi-periodic): the largest
    over the stages of H × its mesh frequency. Stage 2 driven on its pinion: its pinion at
    Ω 24/40, t_2 = 25 × 24/40 = 15 < 24 (stage 1's); on its gear: its pinion at
    Ω (24/40)(41/25), t_2 = 24.6, stage 2's."""
    for f in DATA.glob("two-pair-*.toml"):
        (tmp_path / f.name).write_text(f.read_text())
    text = (DATA / "two-pair-housed.toml").read_text()
    text = text.replace('input = "pinion"\nshaft_Nm_per_rad', f'input = "{side}"\nshaft_Nm_per_rad')
    case, toml = _without_cutoff(tmp_path, text, "box.toml")
    z = [[tomllib.loads((tmp_path / s["case"]).read_text())[k]["teeth"] for k in ("pinion", "gear")]
         for s in toml["stages"]]
    out = Fraction(z[0][0], z[0][1])  # stage 2's input speed over Ω
    t = [z[0][0], z[1][0] * (out if side == "pinion" else out * Fraction(z[1][1], z[1][0]))]
    H, f = _top(toml["whine"])
    _check(case.form.housing, H * float(max(t)) * f)
    assert case.housing.cutoff == case.form.housing.cutoff
    assert ("stage2" in case.housing.cutoff_source) == (side == "gear")


def test_gearbox_with_a_planetary_stage_cutoff_from_whine(tmp_path):
    """planetary-pair-housed with a [whine]: stage 1 a planetary (ring held, carrier input,
    z_r = −80, z_s = 20: mesh frequency |z_r| Ω / 2π, the sun at (1 + 80/20) Ω), stage 2 the
    25/41 pair driven on its gear by the sun: t_2 = 25 × 5 × 41/25 = 205 > 80."""
    for f in DATA.glob("*.toml"):
        (tmp_path / f.name).write_text(f.read_text())
    text = (DATA / "planetary-pair-housed.toml").read_text() + (
        '\n[whine]\nspeed_min_rad_s = 1.0\nspeed_max_rad_s = 3.0\nspeeds = 2\nharmonics = 3\n'
        "positions_per_period = 24\n")
    case, toml = _without_cutoff(tmp_path, text, "box.toml")
    planetary = tomllib.loads((tmp_path / toml["stages"][0]["case"]).read_text())
    zs, _, zr = (g["teeth"] for g in planetary["gears"])
    assert (planetary["planetary"]["fixed"], planetary["planetary"]["input"]) == ("ring",
                                                                                  "carrier")
    pair = tomllib.loads((tmp_path / toml["stages"][1]["case"]).read_text())
    sun = 1 + Fraction(-zr, zs)  # the sun's turns per carrier turn
    t = [abs(zr), pair["pinion"]["teeth"] * sun * Fraction(pair["gear"]["teeth"],
                                                           pair["pinion"]["teeth"])]
    H, f = _top(toml["whine"])
    _check(case.form.housing, H * float(max(t)) * f)


def test_no_cutoff_without_whine_names_the_three_ways(tmp_path):
    """Neither key and no [whine]: one line naming cutoff_Hz, highest_mesh_frequency_Hz and
    [whine]; both keys: refused as before."""
    text = jio.embedded_case_text("power-helical-housed")
    bare = text[: text.index("\n[whine]\n")]
    with pytest.raises(SchemaError, match=r"cutoff_Hz.*highest_mesh_frequency_Hz.*\[whine\]") as e:
        _without_cutoff(tmp_path, bare)
    assert "\n" not in str(e.value)
    both = text.replace("highest_mesh_frequency_Hz = 4500.0",
                        "highest_mesh_frequency_Hz = 4500.0\ncutoff_Hz = 100.0")
    (tmp_path / "both.toml").write_text(both)
    with pytest.raises(SchemaError, match="exactly one"):
        jio.load_case(str(tmp_path / "both.toml"))
